//! The scale (px per mm) from the ring itself: its four marks lie 90 degrees apart on a circle
//! of known radius (the mark circle of `recording::marks`), so in each frame where all four are
//! found they are two conjugate semi-diameters of that circle's image, whose semi-major axis
//! is the radius in pixels. For a camera far away that holds at every height. A near one
//! magnifies what rides higher (a pinhole at distance `D`: `D / (D - z)`), and a tilted one
//! what lies on its far side: there the inverse of each frame's scale is fitted to second order
//! in the marks' height and the ring's place in the image, and its value at the table under
//! the image centre is the scale; `D` follows from the height's term.

use super::find::ellipse_axes;
use crate::recording::FrameMarks;

/// The scale measured from the marks.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RingScale {
    pub px_per_mm: f64,
    /// Its standard error (px per mm).
    pub sigma: f64,
    /// Frames it is measured over.
    pub frames: usize,
    /// The marks' mean height above the table (mm) over those frames: where it holds.
    pub height_mm: f64,
    /// The relative change of the scale per mm of the marks' height (0 for a far camera);
    /// a camera `D` mm away gives about `1 / D`.
    pub growth_per_mm: f64,
    /// Its standard error.
    pub growth_sigma: f64,
    /// A near camera: the scale at the table under the image centre (px per mm), its standard
    /// error and the camera's distance (mm) from the second-order fit.
    pub table: Option<TableScale>,
    /// One centre's error (px per coordinate) that the marks' figure leaves through that near
    /// camera and through a far one ([`RingScale::check_figure`]).
    pub figure_px: Option<(f64, f64)>,
}

/// How much better than a far camera a near one must close the marks' figure to be believed:
/// a true near camera closes it to well under this, a growth faked by errors that frames share
/// (strong compression) to about as well as a far one (docs/film.md has the figures).
pub const NEAR_FIGURE_GAIN: f64 = 0.7;

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TableScale {
    pub px_per_mm: f64,
    pub sigma: f64,
    pub camera_distance_mm: f64,
}

impl RingScale {
    /// Whether the scale grows with the marks' height beyond its noise.
    pub fn grows_with_height(&self) -> bool {
        self.growth_per_mm > 4.0 * self.growth_sigma && self.growth_per_mm > 2e-4
    }

    /// A near camera: the scale grows with the marks' height, and the camera that growth
    /// implies closes the marks' figure clearly better than a far one, where that was checked.
    pub fn camera_is_near(&self) -> bool {
        self.grows_with_height()
            && self.figure_px.is_none_or(|(near, far)| near < NEAR_FIGURE_GAIN * far)
    }

    /// Records the marks' figure through the near camera and a far one (one centre's error
    /// each, px); where the near camera does not close it clearly better, the camera is taken
    /// as far (the growth came from errors that frames share) and its table scale dropped.
    pub fn check_figure(&mut self, near_px: f64, far_px: f64) {
        self.figure_px = Some((near_px, far_px));
        if !self.camera_is_near() {
            self.table = None;
        }
    }
}

/// The scale from the frames with all four marks. `mark_radius_mm`: the mark circle's radius;
/// `outer_radius_mm` and `width_mm` give the top edge's height for each pose.
pub fn ring_scale(
    frames: &[FrameMarks],
    mark_radius_mm: f64,
    outer_radius_mm: f64,
    width_mm: f64,
    image_centre: [f64; 2],
) -> Option<RingScale> {
    let mut s = Vec::new();
    let mut z = Vec::new();
    let mut at = Vec::new();
    for f in frames {
        let [Some(p1), Some(p2), Some(p3), Some(p4)] = *f else { continue };
        let d1 = [(p1[0] - p3[0]) / 2.0, (p1[1] - p3[1]) / 2.0];
        let d2 = [(p2[0] - p4[0]) / 2.0, (p2[1] - p4[1]) / 2.0];
        let (a, b) = ellipse_axes(d1, d2);
        if !(a > 0.0) {
            continue;
        }
        // The ring's axis tilts theta from the table (b / a = sin theta); A is then
        // h sin(theta) + R cos(theta) above it (`recording::marks`).
        let sin_t = (b / a).min(1.0);
        let cos_t = (1.0 - sin_t * sin_t).sqrt();
        s.push(a / mark_radius_mm);
        z.push(width_mm * sin_t + outer_radius_mm * cos_t);
        at.push([
            (p1[0] + p2[0] + p3[0] + p4[0]) / 4.0 - image_centre[0],
            (p1[1] + p2[1] + p3[1] + p4[1]) / 4.0 - image_centre[1],
        ]);
    }
    let n = s.len();
    if n < 3 {
        return None;
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(|a, b| a.total_cmp(b));
        v[v.len() / 2]
    };
    let px_per_mm = median(&mut s.clone());
    let mut dev: Vec<f64> = s.iter().map(|v| (v - px_per_mm).abs()).collect();
    let spread = 1.4826 * median(&mut dev);
    // Straight line of the scale against the height, over the frames within 5 spreads.
    let keep: Vec<usize> =
        (0..n).filter(|&i| (s[i] - px_per_mm).abs() <= 5.0 * spread.max(1e-9)).collect();
    let m = keep.len() as f64;
    let (zm, sm) =
        (keep.iter().map(|&i| z[i]).sum::<f64>() / m, keep.iter().map(|&i| s[i]).sum::<f64>() / m);
    let szz: f64 = keep.iter().map(|&i| (z[i] - zm).powi(2)).sum();
    let szs: f64 = keep.iter().map(|&i| (z[i] - zm) * (s[i] - sm)).sum();
    let (slope, slope_sigma) = if szz > 0.0 && m > 3.0 {
        let slope = szs / szz;
        let rss: f64 = keep.iter().map(|&i| (s[i] - sm - slope * (z[i] - zm)).powi(2)).sum();
        (slope, (rss / (m - 2.0) / szz).sqrt())
    } else {
        (0.0, f64::INFINITY)
    };
    // Frames a few apart share their errors (the marks' smooth bias): count every fifth.
    let independent = (m / 5.0).max(1.0);
    let mut scale = RingScale {
        px_per_mm,
        sigma: spread / independent.sqrt(),
        frames: n,
        height_mm: zm,
        growth_per_mm: slope / px_per_mm,
        growth_sigma: slope_sigma / px_per_mm,
        table: None,
        figure_px: None,
    };
    if scale.grows_with_height() {
        let rows: Vec<(f64, f64, [f64; 2])> = keep.iter().map(|&i| (s[i], z[i], at[i])).collect();
        scale.table = table_scale(&rows, independent);
    }
    Some(scale)
}

/// `1 / scale` against 1, z, x, y, zx, zy, x^2, y^2, xy by least squares (x, y in units of
/// 100 px about the image centre); the scale at the table under the centre is `1 / c0`, and
/// `D / (D - z)` to first order gives `D = -c0 / c_z`.
fn table_scale(rows: &[(f64, f64, [f64; 2])], independent: f64) -> Option<TableScale> {
    const N: usize = 9;
    let terms = |z: f64, p: [f64; 2]| {
        let (x, y) = (p[0] / 100.0, p[1] / 100.0);
        [1.0, z, x, y, z * x, z * y, x * x, y * y, x * y]
    };
    let mut ata = nalgebra::SMatrix::<f64, N, N>::zeros();
    let mut atb = nalgebra::SVector::<f64, N>::zeros();
    for &(s, z, p) in rows {
        let t = nalgebra::SVector::<f64, N>::from(terms(z, p));
        ata += t * t.transpose();
        atb += t / s;
    }
    let inv = ata.try_inverse()?;
    let c = inv * atb;
    let rss: f64 = rows
        .iter()
        .map(|&(s, z, p)| {
            (1.0 / s - nalgebra::SVector::<f64, N>::from(terms(z, p)).dot(&c)).powi(2)
        })
        .sum();
    let var = rss / (rows.len() as f64 - N as f64).max(1.0);
    // Correlated frames: the variance as if `independent` frames had been fitted.
    let c0_sigma = (inv[(0, 0)] * var * rows.len() as f64 / independent).sqrt();
    let (c0, cz) = (c[0], c[1]);
    if !(c0 > 0.0 && cz < 0.0) {
        return None;
    }
    Some(TableScale {
        px_per_mm: 1.0 / c0,
        sigma: c0_sigma / (c0 * c0),
        camera_distance_mm: -c0 / cz,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tilted_circle_gives_its_radius_in_pixels() {
        // Radius 20 mm at 3 px/mm, axis tilted so that b/a = 0.6, turning over 50 frames.
        let frames: Vec<FrameMarks> = (0..50)
            .map(|i| {
                let phase = i as f64 * 0.3;
                std::array::from_fn(|k| {
                    let a = phase + k as f64 * std::f64::consts::FRAC_PI_2;
                    Some([300.0 + 60.0 * a.cos(), 200.0 + 36.0 * a.sin()])
                })
            })
            .collect();
        let s = ring_scale(&frames, 20.0, 20.5, 18.0, [320.0, 240.0]).expect("scale");
        assert!((s.px_per_mm - 3.0).abs() < 1e-9, "{s:?}");
        assert!(!s.camera_is_near());
    }
}
