//! A frame's pose through a camera that sees height (a pinhole, a tilted camera): the marks'
//! pixels fitted by the rolling ring's marks in space ([`MarkGeometry::marks3`]: A's height
//! follows from `theta`, the ring touching the table), projected by the camera.
//!
//! Parameters `(A_x, A_y, phi, theta, psi)` as [`super::pose`]'s, residuals in pixels.
//! Through such a camera the two poses the flat view cannot tell apart, `(phi, psi)` and
//! `(phi + pi, psi + pi)`, put the marks at different heights: both are fitted and the
//! smaller residual is kept. The start is the flat pose of the marks mapped onto a plane at
//! the ring's mean height.

use super::camera::Camera;
use super::marks::MarkGeometry;
use super::pose::{Pose, fit_pose, initial_pose};
use super::{FrameMarks, MARKS};
use nalgebra::{SMatrix, SVector};
use rayon::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};

type Vector5 = SVector<f64, 5>;

/// A pose fitted through a camera: the pose, the residuals' sum of squares (px^2) and the
/// marks used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeenPose {
    pub pose: Pose,
    pub residual_ss_px: f64,
    pub marks: usize,
}

impl SeenPose {
    /// The four marks in space (mm) for this pose.
    pub fn marks3(&self, g: &MarkGeometry) -> [[f64; 3]; MARKS] {
        let p = &self.pose;
        g.marks3(p.a, p.phi, p.theta, p.psi)
    }
}

/// The pose of one frame's marks (pixels) seen by `camera`, `g` in mm, from the flat starts
/// and their turned-round twins; `None` with fewer than three marks.
pub fn pose_seen(m: &FrameMarks, g: &MarkGeometry, camera: &Camera) -> Option<SeenPose> {
    if m.iter().flatten().count() < 3 {
        return None;
    }
    let mut best: Option<SeenPose> = None;
    for start in flat_starts(m, g, camera)? {
        for s in [start, turned_round(start)] {
            let fit = pose_seen_from(m, g, camera, s);
            if fit.residual_ss_px.is_finite()
                && best.is_none_or(|b| fit.residual_ss_px < b.residual_ss_px)
            {
                best = Some(fit);
            }
        }
    }
    best
}

/// The marks on the table's plan (mm): each mark seen with three or more others is mapped
/// through `camera` onto the plane at the height its frame's pose gives it; in a frame of
/// fewer, onto the plane at the ring's mean height. A camera that does not see height maps
/// each straight onto the table.
pub fn marks_on_table(frames: &[FrameMarks], g: &MarkGeometry, camera: &Camera) -> Vec<FrameMarks> {
    if !camera.sees_height() {
        return frames.iter().map(|f| f.map(|m| m.map(|p| camera.to_mm(p)))).collect();
    }
    let mean_height = 0.5 * (g.h + g.r_outer);
    frames
        .par_iter()
        .map(|m| {
            let heights: [f64; MARKS] = match pose_seen(m, g, camera) {
                Some(fit) => fit.marks3(g).map(|p| p[2]),
                None => [mean_height; MARKS],
            };
            std::array::from_fn(|k| m[k].map(|p| camera.to_mm_at(p, heights[k])))
        })
        .collect()
}

/// The other pose of the flat view's pair.
fn turned_round(p: Pose) -> Pose {
    Pose { phi: p.phi + PI, psi: p.psi + PI, ..p }
}

/// Flat poses of the marks mapped onto the plane at the ring's mean height (and onto the
/// table, where that plane is beyond the camera's view).
fn flat_starts(m: &FrameMarks, g: &MarkGeometry, camera: &Camera) -> Option<Vec<Pose>> {
    let mut out = Vec::new();
    for z in [0.5 * (g.h + g.r_outer), 0.0] {
        let mm: FrameMarks = m.map(|p| p.map(|p| camera.to_mm_at(p, z)));
        if mm.iter().flatten().any(|p| !p.iter().all(|v| v.is_finite())) {
            continue;
        }
        if let Some(s) = initial_pose(&mm, g) {
            out.push(fit_pose(&mm, g, s).pose);
        }
    }
    (!out.is_empty()).then_some(out)
}

/// Model minus observed (px) of the marks tracked, in mark order (unused rows zero).
fn residuals(m: &FrameMarks, g: &MarkGeometry, camera: &Camera, x: &Vector5) -> SVector<f64, 8> {
    let model = camera.to_px3_each(g.marks3([x[0], x[1]], x[2], x[3], x[4]));
    SVector::<f64, 8>::from_fn(|i, _| match m[i / 2] {
        Some(o) => model[i / 2][i % 2] - o[i % 2],
        None => 0.0,
    })
}

/// The pose nearest `start` (a previous fit's through a slightly different camera): Levenberg-
/// Marquardt with a forward-difference Jacobian (the projection has no closed derivative
/// here), `theta` held within `[0, pi/2]`.
pub fn pose_seen_from(m: &FrameMarks, g: &MarkGeometry, camera: &Camera, start: Pose) -> SeenPose {
    let clamp = |mut x: Vector5| {
        x[3] = x[3].clamp(0.0, FRAC_PI_2);
        x
    };
    let mut x = clamp(Vector5::new(start.a[0], start.a[1], start.phi, start.theta, start.psi));
    let mut r = residuals(m, g, camera, &x);
    let mut cost = r.norm_squared();
    let mut lambda = 1e-3;
    for _ in 0..50 {
        if !cost.is_finite() {
            break;
        }
        let mut jac = SMatrix::<f64, 8, 5>::zeros();
        for j in 0..5 {
            let h = if j < 2 { 1e-5 * g.radius } else { 1e-6 };
            let mut xh = x;
            xh[j] += h;
            jac.set_column(j, &((residuals(m, g, camera, &xh) - r) / h));
        }
        let jtj = jac.transpose() * jac;
        let grad = jac.transpose() * r;
        let mut a = jtj;
        for i in 0..5 {
            a[(i, i)] += lambda * jtj[(i, i)].max(1e-12);
        }
        let Some(step) = a.lu().solve(&(-grad)) else { break };
        let trial = clamp(x + step);
        let rt = residuals(m, g, camera, &trial);
        let ct = rt.norm_squared();
        if ct.is_finite() && ct <= cost {
            let done = cost - ct <= 1e-12 * cost + 1e-18;
            (x, r, cost, lambda) = (trial, rt, ct, (lambda * 0.3).max(1e-12));
            if done {
                break;
            }
        } else {
            lambda *= 10.0;
            if lambda > 1e10 {
                break;
            }
        }
    }
    SeenPose {
        pose: Pose { a: [x[0], x[1]], phi: x[2], theta: x[3], psi: x[4] },
        residual_ss_px: cost,
        marks: m.iter().flatten().count(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recording::marks::MarkOrder;

    #[test]
    fn a_tilted_pinhole_gives_the_pose_back() {
        let g = MarkGeometry { radius: 19.9, r_outer: 20.66, h: 18.0, order: MarkOrder::Forward };
        let camera = Camera {
            distance_mm: Some(550.0),
            tilt_rad: 30f64.to_radians(),
            ..Camera::centred(3.36, 1280.0, 1024.0)
        };
        for (a, phi, theta, psi) in [
            ([10.0, -20.0], 0.4, 0.5, 1.2),
            ([-60.0, 40.0], 2.5, 0.1, -0.7),
            ([0.0, 0.0], -1.0, 1.3, 3.0),
        ] {
            let m3 = g.marks3(a, phi, theta, psi);
            let m: FrameMarks =
                std::array::from_fn(|k| Some(camera.to_px3(m3[k][0], m3[k][1], m3[k][2])));
            let fit = pose_seen(&m, &g, &camera).expect("a pose");
            assert!(fit.residual_ss_px < 1e-10, "{fit:?}");
            let back = fit.marks3(&g);
            for k in 0..MARKS {
                for i in 0..3 {
                    assert!((back[k][i] - m3[k][i]).abs() < 1e-4, "{k} {i}: {back:?} vs {m3:?}");
                }
            }
        }
    }
}
