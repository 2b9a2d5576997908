//! The pose of the ring in one frame from its marks (table coordinates, after the camera).
//!
//! Start: the paper's formulas, `1 + sin^2(theta) = (L13^2 + L24^2) / D^2` and
//! `1 + sin^2(psi) (sin^2(theta) - 1) = L13^2 / D^2`, `D` the marks' diameter, `L13` and `L24`
//! the apparent distances between opposite marks. They give `theta` and `|sin(psi)|`; the
//! quadrant of `psi` and the heading `phi` follow from the half-chords `p = m1 - A` and
//! `q = m2 - A`: `r e1 = cos(psi) p + s sin(psi) q` (`s` the mark order), and the candidate
//! with the smallest residual wins. With a mark missing, one opposite pair is complete: it
//! gives A (its midpoint: the centroid of three marks would be off by a third of the missing
//! mark's offset) and the other half-chord follows from the third mark.
//!
//! Then a least-squares fit of `(A, phi, theta, psi)` to the marks (Levenberg-Marquardt,
//! analytic Jacobian). What remains ambiguous from one frame: `(phi, psi)` and
//! `(phi + pi, psi + pi)` project to the same marks (the ring tilted the other way); the
//! recovery settles it from the motion (`super::recover`).

use super::marks::MarkGeometry;
use super::{FrameMarks, MARKS};
use nalgebra::{SMatrix, SVector};
use std::f64::consts::PI;

pub type Matrix5 = SMatrix<f64, 5, 5>;
type Vector5 = SVector<f64, 5>;

/// Point A and the Euler angles of one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub a: [f64; 2],
    pub phi: f64,
    pub theta: f64,
    pub psi: f64,
}

/// A fitted pose with what its uncertainty needs.
#[derive(Clone, Copy, Debug)]
pub struct PoseFit {
    pub pose: Pose,
    /// Sum of squared residuals (table units squared).
    pub residual_ss: f64,
    /// The fitted `sin(theta)` before clamping to `[0, 1]`.
    pub sin_theta: f64,
    /// Marks used.
    pub marks: usize,
    /// `J^T J` at the solution: the information per unit noise variance, in the order
    /// `(A_x, A_y, phi, sin(theta), psi)`.
    pub information: Matrix5,
}

impl PoseFit {
    /// Residual degrees of freedom: two coordinates per mark, less five parameters.
    pub fn dof(&self) -> usize {
        (2 * self.marks).saturating_sub(5)
    }
}

/// Point A from the marks: the centroid of all four, else the midpoint of a complete
/// opposite pair.
pub fn point_a(m: &FrameMarks) -> Option<[f64; 2]> {
    let mid = |a: [f64; 2], b: [f64; 2]| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
    match (m[0], m[1], m[2], m[3]) {
        (Some(a), Some(b), Some(c), Some(d)) => {
            Some([0.25 * (a[0] + b[0] + c[0] + d[0]), 0.25 * (a[1] + b[1] + c[1] + d[1])])
        }
        (Some(a), _, Some(c), _) => Some(mid(a, c)),
        (_, Some(b), _, Some(d)) => Some(mid(b, d)),
        _ => None,
    }
}

/// Half-chords `p = m1 - A`, `q = m2 - A` and A, when three or four marks are tracked.
fn half_chords(m: &FrameMarks) -> Option<([f64; 2], [f64; 2], [f64; 2])> {
    let a = point_a(m)?;
    let from_a = |x: [f64; 2]| [x[0] - a[0], x[1] - a[1]];
    let to_a = |x: [f64; 2]| [a[0] - x[0], a[1] - x[1]];
    let p = m[0].map(from_a).or(m[2].map(to_a))?;
    let q = m[1].map(from_a).or(m[3].map(to_a))?;
    Some((p, q, a))
}

/// The paper's start, with `psi`'s quadrant and `phi` from the half-chords.
pub fn initial_pose(m: &FrameMarks, g: &MarkGeometry) -> Option<Pose> {
    let (p, q, a) = half_chords(m)?;
    let d2 = 4.0 * g.radius * g.radius;
    let (l13, l24) = (4.0 * (p[0] * p[0] + p[1] * p[1]), 4.0 * (q[0] * q[0] + q[1] * q[1]));
    let sin2_theta = ((l13 + l24) / d2 - 1.0).clamp(0.0, 1.0);
    let cos2_theta = 1.0 - sin2_theta;
    let sin2_psi =
        if cos2_theta > 1e-9 { ((1.0 - l13 / d2) / cos2_theta).clamp(0.0, 1.0) } else { 0.5 };
    let theta = sin2_theta.sqrt().asin();
    let psi0 = sin2_psi.sqrt().asin();
    let s = g.order.sign();
    let mut best: Option<(f64, Pose)> = None;
    for psi in [psi0, -psi0, PI - psi0, PI + psi0] {
        let (sp, cp) = psi.sin_cos();
        let e1 = [cp * p[0] + s * sp * q[0], cp * p[1] + s * sp * q[1]];
        let pose = Pose { a, phi: e1[1].atan2(e1[0]), theta, psi };
        let ss =
            residuals(m, g, &pose).iter().flatten().map(|r| r[0] * r[0] + r[1] * r[1]).sum::<f64>();
        if best.is_none_or(|(b, _)| ss < b) {
            best = Some((ss, pose));
        }
    }
    best.map(|b| b.1)
}

/// Model minus observed, per tracked mark.
fn residuals(m: &FrameMarks, g: &MarkGeometry, pose: &Pose) -> [Option<[f64; 2]>; MARKS] {
    let model = g.marks(pose.a, pose.phi, pose.theta, pose.psi);
    std::array::from_fn(|k| m[k].map(|o| [model[k][0] - o[0], model[k][1] - o[1]]))
}

/// Residuals and Jacobian of the tracked marks in the parameters `x = (A_x, A_y, phi, s, psi)`,
/// `s = sin(theta)`: the marks depend on `theta` only through `s`, and in `s` the fit stays
/// well conditioned up to the flat pose (in `theta` its column vanishes there).
fn linearize(m: &FrameMarks, g: &MarkGeometry, x: &Vector5) -> (Matrix5, Vector5, f64, usize) {
    let (sp, cp) = x[2].sin_cos();
    let s = x[3];
    let r = g.radius;
    let (mut jtj, mut jtr, mut ss, mut n) = (Matrix5::zeros(), Vector5::zeros(), 0.0, 0);
    for (k, o) in m.iter().enumerate() {
        let Some(o) = o else { continue };
        n += 1;
        let (sa, ca) = g.angle(k, x[4]).sin_cos();
        // Mark = A + r (cos(a) e1 + sin(a) e3), e1 = (cp, sp), e3 = s (sp, -cp).
        let model = [x[0] + r * (ca * cp + sa * s * sp), x[1] + r * (ca * sp - sa * s * cp)];
        let res = [model[0] - o[0], model[1] - o[1]];
        let d_phi = [r * (-ca * sp + sa * s * cp), r * (ca * cp + sa * s * sp)];
        let d_s = [r * sa * sp, -r * sa * cp];
        let d_psi = [r * (sa * cp - ca * s * sp), r * (sa * sp + ca * s * cp)];
        for (i, ri) in res.iter().enumerate() {
            let row = Vector5::new(
                (i == 0) as u8 as f64,
                (i == 1) as u8 as f64,
                d_phi[i],
                d_s[i],
                d_psi[i],
            );
            jtj += row * row.transpose();
            jtr += row * *ri;
            ss += ri * ri;
        }
    }
    (jtj, jtr, ss, n)
}

/// Least-squares pose from a start (Levenberg-Marquardt on five parameters). `sin(theta)` is
/// free during the fit (noise can make the marks look rounder than a circle); `theta` is then
/// `asin` of it clamped to `[0, 1]`.
pub fn fit_pose(m: &FrameMarks, g: &MarkGeometry, start: Pose) -> PoseFit {
    let mut x = Vector5::new(start.a[0], start.a[1], start.phi, start.theta.sin(), start.psi);
    let (mut jtj, mut jtr, mut ss, n) = linearize(m, g, &x);
    let mut lambda = 1e-3;
    let scale = g.radius * g.radius;
    for _ in 0..60 {
        let mut a = jtj;
        for i in 0..5 {
            a[(i, i)] += lambda * jtj[(i, i)] + 1e-12 * scale;
        }
        let Some(step) = a.cholesky().map(|c| c.solve(&(-jtr))) else {
            lambda *= 10.0;
            continue;
        };
        let trial = x + step;
        let (jtj_t, jtr_t, ss_t, _) = linearize(m, g, &trial);
        if ss_t <= ss {
            let converged = ss - ss_t <= 1e-12 * ss + 1e-24 * scale;
            x = trial;
            (jtj, jtr, ss) = (jtj_t, jtr_t, ss_t);
            lambda = (lambda * 0.3).max(1e-12);
            if converged {
                break;
            }
        } else {
            lambda *= 10.0;
            if lambda > 1e12 {
                break;
            }
        }
    }
    let pose = Pose { a: [x[0], x[1]], phi: x[2], theta: x[3].clamp(0.0, 1.0).asin(), psi: x[4] };
    PoseFit { pose, sin_theta: x[3], residual_ss: ss, marks: n, information: jtj }
}

impl PoseFit {
    /// Standard deviations of `(phi, theta, psi)` for a pixel noise `sigma` (table units),
    /// infinite where the marks do not determine them. Near the flat pose `theta`'s sigma is
    /// taken from that of `s = sin(theta)` as `sigma_s / sqrt(cos^2(theta) + sigma_s / 2)`
    /// (`sigma_s / cos(theta)` away from flat, `sqrt(2 sigma_s)` at flat, where
    /// `1 - s = (pi/2 - theta)^2 / 2`).
    pub fn angle_sigmas(&self, sigma: f64) -> [f64; 3] {
        let mut out = [f64::INFINITY; 3];
        let Some(cov) = self.information.try_inverse() else { return out };
        let sd = |i: usize| {
            let v = cov[(i, i)];
            if v.is_finite() && v >= 0.0 { sigma * v.sqrt() } else { f64::INFINITY }
        };
        out[0] = sd(2);
        out[2] = sd(4);
        let (s_sigma, c) = (sd(3), self.pose.theta.cos());
        out[1] = s_sigma / (c * c + s_sigma / 2.0).sqrt();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recording::marks::MarkOrder;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn recovers_pose_from_four_and_three_marks() {
        for order in [MarkOrder::Forward, MarkOrder::Reverse] {
            let g = MarkGeometry { radius: 20.0, r_outer: 20.5, h: 18.0, order };
            for (phi, theta, psi) in
                [(0.3, 0.6, 1.0), (-2.0, 1.2, -0.3), (2.5, 0.9, 2.8), (1.0, 1.5, -2.0)]
            {
                let truth = Pose { a: [10.0, -5.0], phi, theta, psi };
                let exact = g.marks(truth.a, phi, theta, psi);
                for missing in [None, Some(0), Some(1), Some(2), Some(3)] {
                    let marks: FrameMarks =
                        std::array::from_fn(|k| (Some(k) != missing).then_some(exact[k]));
                    let start = initial_pose(&marks, &g).expect("start");
                    let fit = fit_pose(&marks, &g, start);
                    let p = fit.pose;
                    // Up to the (phi + pi, psi + pi) ambiguity.
                    let d = |x: f64, y: f64| (x - y + PI).rem_euclid(2.0 * PI) - PI;
                    let flipped = d(p.phi, phi).abs() > FRAC_PI_2;
                    let shift = if flipped { PI } else { 0.0 };
                    assert!(
                        fit.residual_ss < 1e-16,
                        "{order:?} {missing:?}: ss {}",
                        fit.residual_ss
                    );
                    assert!(
                        (p.theta - theta).abs() < 1e-7,
                        "{order:?} {missing:?}: theta {} vs {theta}",
                        p.theta
                    );
                    assert!(
                        d(p.phi, phi + shift).abs() < 1e-7 && d(p.psi, psi + shift).abs() < 1e-7
                    );
                    assert!((p.a[0] - 10.0).abs() < 1e-8 && (p.a[1] + 5.0).abs() < 1e-8);
                }
            }
        }
    }
}
