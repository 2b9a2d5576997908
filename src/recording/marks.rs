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

use super::MARKS;
use crate::physics::{Body, Shape};
use std::f64::consts::FRAC_PI_2;

/// Which way the mark numbers run round the top edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
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

/// The marks' circle and numbering.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarkGeometry {
    /// Radius of the marks' circle (the length unit of the caller).
    pub radius: f64,
    pub order: MarkOrder,
}

impl MarkGeometry {
    /// Angle `a_k` of mark `k` (0-based) from `e1` towards `e3`.
    #[inline]
    pub fn angle(&self, k: usize, psi: f64) -> f64 {
        self.order.sign() * k as f64 * FRAC_PI_2 - psi
    }

    /// Table positions of the four marks for point A at `a` and angles `phi, theta, psi`.
    #[inline]
    pub fn marks(&self, a: [f64; 2], phi: f64, theta: f64, psi: f64) -> [[f64; 2]; MARKS] {
        let (sp, cp) = phi.sin_cos();
        let st = theta.sin();
        let e1 = [cp, sp];
        let e3 = [st * sp, -st * cp];
        std::array::from_fn(|k| {
            let (s, c) = self.angle(k, psi).sin_cos();
            [a[0] + self.radius * (c * e1[0] + s * e3[0]), a[1] + self.radius * (c * e1[1] + s * e3[1])]
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forward_order_runs_clockwise_from_above() {
        let g = MarkGeometry { radius: 1.0, order: MarkOrder::Forward };
        for (phi, theta, psi) in [(0.3, 0.5, 1.0), (-2.0, 1.4, -0.3), (4.0, 0.1, 2.5)] {
            let m = g.marks([0.0, 0.0], phi, theta, psi);
            let area: f64 = (0..4).map(|k| m[k][0] * m[(k + 1) % 4][1] - m[(k + 1) % 4][0] * m[k][1]).sum();
            assert!(area < 0.0, "area {area}");
            // Opposite marks are symmetric about A; L13^2 + L24^2 = D^2 (1 + sin^2 theta) (the paper).
            let l13 = (m[0][0] - m[2][0]).hypot(m[0][1] - m[2][1]);
            let l24 = (m[1][0] - m[3][0]).hypot(m[1][1] - m[3][1]);
            assert!((l13 * l13 + l24 * l24 - 4.0 * (1.0 + theta.sin().powi(2))).abs() < 1e-12);
            // 1 + sin^2(psi) (sin^2(theta) - 1) = L13^2 / D^2.
            assert!((1.0 + psi.sin().powi(2) * (theta.sin().powi(2) - 1.0) - l13 * l13 / 4.0).abs() < 1e-12);
        }
    }
}
