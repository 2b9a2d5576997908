//! The centres' error through a near camera, where the marks' parallelogram (`error`) fails.
//!
//! The four marks are four points 90 degrees apart on a circle of known radius in space: its
//! centre (3 numbers), its normal (2) and the marks' turn about it (1) make eight pixel
//! coordinates through the pinhole the tracker fitted, so each frame keeps two checks, as
//! the parallelogram does far away (its orthographic limit). A frame's least-squares pose
//! leaves a residual whose sum of squares holds two centres' error variances: the RMS of
//! `sqrt(sum / 2)` is one centre's error per coordinate. The camera's tilt and a small error
//! in its distance hardly move that residual: the pose absorbs them.

use super::error::closure_sigma;
use super::scale::RingScale;
use crate::recording::{Camera, FrameMarks};
use nalgebra::{SMatrix, SVector};

type Pose = SVector<f64, 6>;
type Residual = SVector<f64, 8>;

/// One centre's error per coordinate (px) from each frame's pose of the marks' circle of
/// `radius_mm` seen by `camera`, over the frames with all four marks, outliers beyond five
/// robust spreads left out; `None` with fewer than 10 such frames.
pub fn pinhole_closure_sigma(
    frames: &[FrameMarks],
    camera: &Camera,
    radius_mm: f64,
) -> Option<f64> {
    let per_frame: Vec<f64> = frames
        .iter()
        .filter_map(|f| {
            let [Some(p1), Some(p2), Some(p3), Some(p4)] = *f else { return None };
            best_fit(&[p1, p2, p3, p4], camera, radius_mm).map(|ss| (ss / 2.0).sqrt())
        })
        .collect();
    if per_frame.len() < 10 {
        return None;
    }
    let mut sorted = per_frame.clone();
    sorted.sort_by(|a, b| a.total_cmp(b));
    // Each value is a chi with two degrees of freedom, scaled: its median is 1.18 sigma.
    let spread = sorted[sorted.len() / 2] / 1.1774;
    let kept: Vec<f64> = per_frame.into_iter().filter(|g| *g <= 5.0 * spread.max(1e-6)).collect();
    Some((kept.iter().map(|g| g * g).sum::<f64>() / kept.len() as f64).sqrt())
}

/// Whether the near camera a growing scale implies is believed: through it the marks' figure
/// must close clearly better than through a far one ([`RingScale::check_figure`]). A growth
/// that frames sharing their errors fake (strong compression) implies a camera that does not.
/// The note where it is not believed.
pub fn check_near_camera(
    rs: &mut RingScale,
    frames: &[FrameMarks],
    image_size: [f64; 2],
    radius_mm: f64,
) -> Option<String> {
    let t = rs.table?;
    let camera = Camera {
        distance_mm: Some(t.camera_distance_mm),
        ..Camera::centred(t.px_per_mm, image_size[0], image_size[1])
    };
    let near = pinhole_closure_sigma(frames, &camera, radius_mm)?;
    let far = closure_sigma(frames)?;
    rs.check_figure(near, far);
    (!rs.camera_is_near()).then(|| {
        format!(
            "the marks' scale grows with their height as through a camera {:.0} mm away, but such a camera leaves the marks' figure {near:.2} px against {far:.2} px far away: not clearly better, so the camera is taken as far, and the scale as the marks' own ({:.4} px/mm, holding {:.1} mm above the table; give --px-per-mm where the camera is near)",
            t.camera_distance_mm, rs.px_per_mm, rs.height_mm
        )
    })
}

/// The four marks of a pose: centre, normal's polar and azimuth angles, turn; `hand` +1 or -1
/// for the order in which the marks go round.
fn marks(q: &Pose, radius: f64, hand: f64) -> [[f64; 3]; 4] {
    let (st, ct) = q[3].sin_cos();
    let (sp, cp) = q[4].sin_cos();
    let n = [st * cp, st * sp, ct];
    let e1 = [-sp, cp, 0.0];
    let e2 =
        [n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2], n[0] * e1[1] - n[1] * e1[0]];
    std::array::from_fn(|k| {
        let (s, c) = (q[5] - hand * k as f64 * std::f64::consts::FRAC_PI_2).sin_cos();
        std::array::from_fn(|i| q[i] + radius * (c * e1[i] + s * e2[i]))
    })
}

fn residual(q: &Pose, obs: &[[f64; 2]; 4], cam: &Camera, radius: f64, hand: f64) -> Residual {
    let m = marks(q, radius, hand);
    Residual::from_fn(|i, _| {
        let p = cam.to_px3(m[i / 2][0], m[i / 2][1], m[i / 2][2]);
        p[i % 2] - obs[i / 2][i % 2]
    })
}

/// The smallest sum of squared residuals over the starts (both signs of the marks' heights,
/// both orders round the circle).
fn best_fit(obs: &[[f64; 2]; 4], cam: &Camera, radius: f64) -> Option<f64> {
    let mut best: Option<f64> = None;
    for hand in [1.0, -1.0] {
        for up in [1.0, -1.0] {
            let Some(q0) = start(obs, cam, radius, hand, up) else { continue };
            if let Some(ss) = gauss_newton(q0, obs, cam, radius, hand) {
                best = Some(best.map_or(ss, |b: f64| b.min(ss)));
            }
        }
    }
    best
}

/// A pose from the orthographic reading: the marks' centre and two conjugate semi-diameters
/// on the table, shrunk by the magnification their size shows, lifted to length `radius`.
fn start(obs: &[[f64; 2]; 4], cam: &Camera, radius: f64, hand: f64, up: f64) -> Option<Pose> {
    let p = obs.map(|o| cam.to_mm(o));
    let centre = [0, 1].map(|i| p.iter().map(|q| q[i]).sum::<f64>() / 4.0);
    let u = [0, 1].map(|i| (p[0][i] - p[2][i]) / 2.0);
    let v = [0, 1].map(|i| (p[1][i] - p[3][i]) / 2.0);
    let s = u[0] * u[0] + u[1] * u[1] + v[0] * v[0] + v[1] * v[1];
    let cross = (u[0] * v[1] - u[1] * v[0]).abs();
    let semi_major = (0.5 * (s + (s * s - 4.0 * cross * cross).max(0.0).sqrt())).sqrt();
    let magnification = (semi_major / radius).max(1.0);
    let height = cam.distance_mm.map_or(0.0, |d| d * (1.0 - 1.0 / magnification));
    let (u, v, centre) = (
        u.map(|x| x / magnification),
        v.map(|x| x / magnification),
        centre.map(|x| x / magnification),
    );
    let uz = up * (radius * radius - u[0] * u[0] - u[1] * u[1]).max(1e-6 * radius * radius).sqrt();
    let vz = -(u[0] * v[0] + u[1] * v[1]) / uz;
    let (u3, v3) = ([u[0], u[1], uz], [v[0], v[1], vz]);
    // The normal for the order `hand`: marks turn clockwise about it for hand +1.
    let mut n = [
        u3[1] * v3[2] - u3[2] * v3[1],
        u3[2] * v3[0] - u3[0] * v3[2],
        u3[0] * v3[1] - u3[1] * v3[0],
    ];
    let norm = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if !(norm > 0.0) {
        return None;
    }
    n = n.map(|x| -hand * x / norm);
    let theta = n[2].clamp(-1.0, 1.0).acos();
    let psi = n[1].atan2(n[0]);
    let (sp, cp) = psi.sin_cos();
    let e1 = [-sp, cp, 0.0];
    let e2 =
        [n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2], n[0] * e1[1] - n[1] * e1[0]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let turn = dot(u3, e2).atan2(dot(u3, e1));
    Some(Pose::from([centre[0], centre[1], height, theta, psi, turn]))
}

/// Levenberg-Marquardt steps from `q`; the final sum of squares, `None` where it ran off.
fn gauss_newton(
    mut q: Pose,
    obs: &[[f64; 2]; 4],
    cam: &Camera,
    radius: f64,
    hand: f64,
) -> Option<f64> {
    let mut r = residual(&q, obs, cam, radius, hand);
    let mut cost = r.norm_squared();
    let mut lambda = 1e-3;
    for _ in 0..40 {
        if !cost.is_finite() {
            return None;
        }
        let mut jac = SMatrix::<f64, 8, 6>::zeros();
        for j in 0..6 {
            let h = 1e-6 * q[j].abs().max(1.0);
            let mut qh = q;
            qh[j] += h;
            jac.set_column(j, &((residual(&qh, obs, cam, radius, hand) - r) / h));
        }
        let jtj = jac.transpose() * jac;
        let g = jac.transpose() * r;
        let mut a = jtj;
        for i in 0..6 {
            a[(i, i)] += lambda * jtj[(i, i)].max(1e-12);
        }
        let step = a.lu().solve(&(-g))?;
        let trial = q + step;
        let rt = residual(&trial, obs, cam, radius, hand);
        let ct = rt.norm_squared();
        if ct.is_finite() && ct < cost {
            let done = cost - ct < 1e-12 * cost.max(1e-12);
            (q, r, cost, lambda) = (trial, rt, ct, (lambda * 0.3).max(1e-9));
            if done {
                break;
            }
        } else {
            lambda *= 10.0;
            if lambda > 1e8 {
                break;
            }
        }
    }
    cost.is_finite().then_some(cost)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recording::rng::Rng;

    #[test]
    fn a_pinhole_pose_reads_each_centres_error() {
        let camera = Camera { distance_mm: Some(400.0), ..Camera::centred(3.4, 1280.0, 1024.0) };
        let mut rng = Rng::new(11);
        let radius = 20.0;
        let frames: Vec<FrameMarks> = (0..2000)
            .map(|i| {
                let t = i as f64 * 0.01;
                let q = Pose::from([
                    30.0 * t.cos(),
                    20.0 * t.sin(),
                    15.0 + 5.0 * t.sin(),
                    0.6 + 0.3 * (0.7 * t).sin(),
                    2.0 * t,
                    9.0 * t,
                ]);
                let m = marks(&q, radius, 1.0);
                std::array::from_fn(|k| {
                    let p = camera.to_px3(m[k][0], m[k][1], m[k][2]);
                    Some([p[0] + 0.3 * rng.normal(), p[1] + 0.3 * rng.normal()])
                })
            })
            .collect();
        let s = pinhole_closure_sigma(&frames, &camera, radius).expect("enough frames");
        assert!((s - 0.3).abs() < 0.02, "{s}");
        // The parallelogram would read the perspective as error.
        let flat = super::super::error::closure_sigma(&frames).expect("enough frames");
        assert!(flat > 0.5, "{flat}");
    }
}
