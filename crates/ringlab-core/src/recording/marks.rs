//! Where the four marks sit for a given pose (`RECORDING_FORMAT.md`; checked against the
//! sample and its truth).
//!
//! The marks lie on the top edge circle (centre A = C + (h/2) e2), 90 degrees apart, on the
//! ring's mean radius `R - w/2` (a disk: its rim, `R`). The body turns by `psi` about `e2`
//! (right-handed), so mark `k` (0-based) points along `cos(a_k) e1 + sin(a_k) e3` with
//! `a_k = s k pi/2 - psi`; `s = +1` when the numbers run from `e1` towards `e3`
//! ([`MarkOrder::Forward`], as in the sample), `-1` the other way round. Seen from above the
//! forward order runs clockwise (`e1 x (-sin(theta) E2') = -sin(theta) Z`), whatever the pose,
//! so a recording's order shows in the sign of the area of its mark quadrilateral.
//!
//! Projected straight down, `e1 -> (cos phi, sin phi)` and `e3 -> sin(theta) (sin phi, -cos phi)`.
//! Heights (for a camera that sees them, [`MarkGeometry::marks3`]): A is `h sin(theta) +
//! R cos(theta)` above the table (`z_C` of `PHYSICS.md` plus `(h/2) sin(theta)`), and `e3` rises
//! by `cos(theta)`, so mark `k` is at `z_A + r sin(a_k) cos(theta)`.

use super::MARKS;
use crate::physics::trig::sin_cos;
use crate::physics::{Body, Shape};
use std::f64::consts::FRAC_PI_2;

/// Which way the mark numbers run round the top edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum MarkOrder {
    /// From `e1` towards `e3`: clockwise seen from above.
    Forward,
    /// The other way: counter-clockwise seen from above.
    Reverse,
}

impl MarkOrder {
    pub fn sign(self) -> f64 {
        match self {
            MarkOrder::Forward => 1.0,
            MarkOrder::Reverse => -1.0,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            MarkOrder::Forward => "clockwise seen from above",
            MarkOrder::Reverse => "counter-clockwise seen from above",
        }
    }
}

/// Radius of the circle the marks sit on: the mean radius of a ring, the rim of a disk.
pub fn mark_radius(body: &Body) -> f64 {
    match body.shape {
        Shape::Ring => body.r - body.w / 2.0,
        Shape::Disk => body.r,
    }
}

/// The marks' circle and numbering, and the body's dimensions that set its height.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MarkGeometry {
    /// Radius of the marks' circle (the length unit of the caller).
    pub radius: f64,
    /// The body's outer radius `R` and width `h` (same unit): the top edge's height.
    pub r_outer: f64,
    pub h: f64,
    pub order: MarkOrder,
}

impl MarkGeometry {
    /// The marks of `body` (its length unit).
    pub fn of_body(body: &Body, order: MarkOrder) -> MarkGeometry {
        MarkGeometry { radius: mark_radius(body), r_outer: body.r, h: body.h, order }
    }

    /// The same geometry with every length multiplied by `k` (a change of unit).
    pub fn scaled(self, k: f64) -> MarkGeometry {
        MarkGeometry {
            radius: self.radius * k,
            r_outer: self.r_outer * k,
            h: self.h * k,
            order: self.order,
        }
    }

    /// Angle `a_k` of mark `k` (0-based) from `e1` towards `e3`.
    #[inline]
    pub fn angle(&self, k: usize, psi: f64) -> f64 {
        self.order.sign() * k as f64 * FRAC_PI_2 - psi
    }

    /// `(sin a_k, cos a_k)` from those of `psi`: `a_k` is `psi` turned by quarter turns, so
    /// one sine and cosine serve the four marks (the projection runs for every sample of
    /// every fit).
    #[inline]
    fn sin_cos_of(&self, k: usize, (sp, cp): (f64, f64)) -> (f64, f64) {
        match (self.order.sign() as i64 * k as i64).rem_euclid(4) {
            0 => (-sp, cp),
            1 => (cp, sp),
            2 => (sp, -cp),
            _ => (-cp, -sp),
        }
    }

    /// Table positions of the four marks for point A at `a` and angles `phi, theta, psi`.
    #[inline]
    pub fn marks(&self, a: [f64; 2], phi: f64, theta: f64, psi: f64) -> [[f64; 2]; MARKS] {
        self.marks_sc(a, sin_cos(phi), sin_cos(theta).0, sin_cos(psi))
    }

    /// [`MarkGeometry::marks`] from the sine and cosine of `phi` and of `psi` and the sine of
    /// `theta` ([`MarkGeometry::marks3`] needs them too).
    fn marks_sc(
        &self,
        a: [f64; 2],
        (sp, cp): (f64, f64),
        st: f64,
        sc_psi: (f64, f64),
    ) -> [[f64; 2]; MARKS] {
        let e1 = [cp, sp];
        let e3 = [st * sp, -st * cp];
        std::array::from_fn(|k| {
            let (s, c) = self.sin_cos_of(k, sc_psi);
            [
                a[0] + self.radius * (c * e1[0] + s * e3[0]),
                a[1] + self.radius * (c * e1[1] + s * e3[1]),
            ]
        })
    }

    /// As [`MarkGeometry::marks`], with each mark's height above the table third (the body
    /// rolling on the table: A's height follows from `theta`).
    #[inline]
    pub fn marks3(&self, a: [f64; 2], phi: f64, theta: f64, psi: f64) -> [[f64; 3]; MARKS] {
        let (st, ct) = sin_cos(theta);
        let sc_psi = sin_cos(psi);
        let m = self.marks_sc(a, sin_cos(phi), st, sc_psi);
        let z_a = self.h * st + self.r_outer * ct;
        std::array::from_fn(|k| {
            [m[k][0], m[k][1], z_a + self.radius * self.sin_cos_of(k, sc_psi).0 * ct]
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forward_order_runs_clockwise_from_above() {
        let g = MarkGeometry { radius: 1.0, r_outer: 1.1, h: 0.9, order: MarkOrder::Forward };
        for (phi, theta, psi) in [(0.3, 0.5, 1.0), (-2.0, 1.4, -0.3), (4.0, 0.1, 2.5)] {
            let m = g.marks([0.0, 0.0], phi, theta, psi);
            let area: f64 =
                (0..4).map(|k| m[k][0] * m[(k + 1) % 4][1] - m[(k + 1) % 4][0] * m[k][1]).sum();
            assert!(area < 0.0, "area {area}");
            // Opposite marks are symmetric about A; L13^2 + L24^2 = D^2 (1 + sin^2 theta) (the paper).
            let l13 = (m[0][0] - m[2][0]).hypot(m[0][1] - m[2][1]);
            let l24 = (m[1][0] - m[3][0]).hypot(m[1][1] - m[3][1]);
            assert!((l13 * l13 + l24 * l24 - 4.0 * (1.0 + theta.sin().powi(2))).abs() < 1e-12);
            // 1 + sin^2(psi) (sin^2(theta) - 1) = L13^2 / D^2.
            assert!(
                (1.0 + psi.sin().powi(2) * (theta.sin().powi(2) - 1.0) - l13 * l13 / 4.0).abs()
                    < 1e-12
            );
        }
    }

    /// The marks in 3D from the frame vectors of `PHYSICS.md`: A = P + h e2 + R e3 above the
    /// contact point P, mark k = A + r (cos a_k e1 + sin a_k e3).
    #[test]
    fn marks3_follow_the_body_frame() {
        let body = Body::new(Shape::Ring, 20.66, 18.0, 1.0).expect("ring");
        for order in [MarkOrder::Forward, MarkOrder::Reverse] {
            let g = MarkGeometry::of_body(&body, order);
            assert_eq!((g.radius, g.r_outer, g.h), (mark_radius(&body), 20.66, 18.0));
            for (phi, theta, psi) in
                [(0.3, 0.5, 1.0), (-2.0, 1.4, -0.3), (4.0, 0.1, 2.5), (1.0, 0.0, 0.7)]
            {
                let (sp, cp) = f64::sin_cos(phi);
                let (st, ct) = f64::sin_cos(theta);
                let e2p = [-sp, cp, 0.0];
                let e1 = [cp, sp, 0.0];
                let e2: [f64; 3] = std::array::from_fn(|i| ct * e2p[i] + st * [0.0, 0.0, 1.0][i]);
                let e3: [f64; 3] = std::array::from_fn(|i| -st * e2p[i] + ct * [0.0, 0.0, 1.0][i]);
                let p = [3.0, -7.0, 0.0];
                let a: [f64; 3] = std::array::from_fn(|i| p[i] + body.h * e2[i] + body.r * e3[i]);
                let m = g.marks3([a[0], a[1]], phi, theta, psi);
                let flat = g.marks([a[0], a[1]], phi, theta, psi);
                for k in 0..MARKS {
                    let (s, c) = g.angle(k, psi).sin_cos();
                    let expected: [f64; 3] =
                        std::array::from_fn(|i| a[i] + g.radius * (c * e1[i] + s * e3[i]));
                    for i in 0..3 {
                        assert!(
                            (m[k][i] - expected[i]).abs() < 1e-12,
                            "{k} {i}: {:?} vs {expected:?}",
                            m[k]
                        );
                    }
                    assert_eq!([m[k][0], m[k][1]], flat[k]);
                }
            }
        }
        let mm = MarkGeometry::of_body(&body, MarkOrder::Forward).scaled(0.5);
        assert_eq!((mm.radius, mm.r_outer, mm.h), (0.5 * mark_radius(&body), 10.33, 9.0));
    }
}
