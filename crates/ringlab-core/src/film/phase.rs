//! One mark taken from something else, told by its phase round the ring. The marks'
//! parallelogram gap is the same whichever mark is off, so it cannot say which; the ellipse
//! of the frame before can. Mapped through that ellipse onto a circle, the four marks sit 90
//! degrees apart (an affine map keeps conjugate diameters conjugate), so where the other
//! three put a mark (the centre halfway between its neighbours, the phase theirs) shows the
//! one left behind on a look-alike (a weak mark's hue lost to the codec beside the table's
//! grain of that hue).

use nalgebra::{Matrix2, Vector2};

/// The marks' ellipse in one frame: the map from the unit circle onto it, and back.
#[derive(Clone, Copy, Debug)]
pub struct Figure {
    from_circle: Matrix2<f64>,
    to_circle: Matrix2<f64>,
}

impl Figure {
    /// From four marks 90 degrees apart: `(p1 - p3) / 2` and `(p2 - p4) / 2` are conjugate
    /// semi-diameters, the columns of the map from the unit circle.
    pub fn from_marks(p: [[f64; 2]; 4]) -> Option<Figure> {
        let v = |a: [f64; 2]| Vector2::new(a[0], a[1]);
        let from_circle =
            Matrix2::from_columns(&[(v(p[0]) - v(p[2])) / 2.0, (v(p[1]) - v(p[3])) / 2.0]);
        let to_circle = from_circle.try_inverse()?;
        Some(Figure { from_circle, to_circle })
    }

    /// The ellipse's semi-minor axis (px).
    /// The same figure seen through an image turned by `turn_rad` (a camera that turned).
    pub fn turned(&self, turn_rad: f64) -> Figure {
        let r = Matrix2::new(turn_rad.cos(), -turn_rad.sin(), turn_rad.sin(), turn_rad.cos());
        Figure { from_circle: r * self.from_circle, to_circle: self.to_circle * r.transpose() }
    }

    pub fn minor_axis(&self) -> f64 {
        let (u, v) = (self.from_circle.column(0), self.from_circle.column(1));
        super::find::ellipse_axes([u.x, u.y], [v.x, v.y]).1
    }

    /// The mark (0-3) more than `tolerance_px` from where the other three put it on this
    /// figure's ellipse (its centre halfway between the mark's two neighbours, its phase the
    /// others'), while those three sit within half of it of their own places.
    pub fn odd_one_out(&self, p: [[f64; 2]; 4], tolerance_px: f64) -> Option<usize> {
        let v = |a: [f64; 2]| Vector2::new(a[0], a[1]);
        let quarter = std::f64::consts::FRAC_PI_2;
        let test = |k: usize| -> (f64, f64) {
            let centre = (v(p[(k + 1) % 4]) + v(p[(k + 3) % 4])) / 2.0;
            let others = [(k + 1) % 4, (k + 2) % 4, (k + 3) % 4];
            // Mark j sits at phase phi + j * 90 degrees on the circle.
            let (s, c) = others.iter().fold((0.0, 0.0), |(s, c), &j| {
                let w = self.to_circle * (v(p[j]) - centre);
                let phi = w.y.atan2(w.x) - j as f64 * quarter;
                (s + phi.sin(), c + phi.cos())
            });
            let miss = |phi: f64, j: usize| {
                let a = phi + j as f64 * quarter;
                (v(p[j]) - centre - self.from_circle * Vector2::new(a.cos(), a.sin())).norm()
            };
            // The circle's mean phase, then the phase nearest in pixels: seen near edge, the
            // circle's phases are stretched along the short axis.
            let cost = |phi: f64| others.iter().map(|&j| miss(phi, j).powi(2)).sum::<f64>();
            let phi = (-50..=50)
                .map(|i| s.atan2(c) + 0.01 * i as f64)
                .min_by(|a, b| cost(*a).total_cmp(&cost(*b)))
                .expect("steps");
            let miss = |j: usize| miss(phi, j);
            (miss(k), others.iter().map(|&j| miss(j)).fold(0.0, f64::max))
        };
        let (k, (miss, rest)) =
            (0..4).map(|k| (k, test(k))).max_by(|a, b| a.1.0.total_cmp(&b.1.0))?;
        (miss > tolerance_px && rest < 0.5 * tolerance_px).then_some(k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn on_ellipse(phase: f64) -> [[f64; 2]; 4] {
        std::array::from_fn(|k| {
            let a = phase + k as f64 * std::f64::consts::FRAC_PI_2;
            [300.0 + 40.0 * a.cos() - 8.0 * a.sin(), 200.0 + 24.0 * a.sin()]
        })
    }

    #[test]
    fn a_mark_left_behind_is_told_from_the_three_that_turned_on() {
        let before = Figure::from_marks(on_ellipse(0.3)).expect("figure");
        let mut now = on_ellipse(0.36);
        assert_eq!(before.odd_one_out(now, 4.0), None);
        now[2] = on_ellipse(0.3)[2];
        now[2][0] += 6.0;
        assert_eq!(before.odd_one_out(now, 4.0), Some(2));
    }
}
