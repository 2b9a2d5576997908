//! The ring's motion recovered from a recording, frame by frame, with uncertainties.
//!
//! - The pixel noise is estimated from the data: the residuals of the per-frame pose fits
//!   (two coordinates per mark, five parameters per frame).
//! - Point A: the centroid of the four marks (or the midpoint of a complete opposite pair:
//!   see [`super::pose`]); `sigma_A = sigma / sqrt(2 pairs)` per axis.
//! - `theta, psi` and the heading `phi` (the line of nodes `e1`): the pose fit, sigmas from
//!   its covariance `sigma^2 (J^T J)^-1`. Near the flat end `phi` and `psi` lose their meaning
//!   one by one (only their sum shows) and their sigmas grow without bound, as they should.
//! - `(phi, psi)` or `(phi + pi, psi + pi)`: the marks cannot tell; the rolling can. Along a
//!   stretch of frames where `phi` is well determined the angles are followed continuously,
//!   and the stretch is turned round when the velocity of A that rolling predicts from the
//!   angles' rates (`v_A = (w2 R - w3 h) e1 - w1 R e2 + w1 h e3`) points against the measured one.
//! - The order of the mark numbers (clockwise or not seen from above) from the sign of the
//!   area of the mark quadrilateral; the spin direction from `omega . Z = phi' + psi' sin(theta)`.
//! - `v_p`: the velocity of A on the table (central differences), the paper's Fig. 3.
//! - Turning points: extrema of the smoothed `theta` that stand out of its noise by 3 sigma;
//!   the first inner turning point (`theta` minimum) is where the paper starts its model.
//! - Rest: the frames at the end whose marks stay put within the noise.
//!
//! Everything is stored in mm, s and rad; [`RecoveredMotion::units`] are the model's units
//! (lengths in mean radii, `g` as in the paper's case) and [`RecoveredMotion::to_model`]
//! converts.

use super::camera::Camera;
use super::camera::TRIPOD_TILT_DEG;
use super::marks::{MarkGeometry, MarkOrder};
use super::pose::{PoseFit, fit_pose, initial_pose, point_a};
use super::pose_seen::marks_on_table;
use super::smooth::{Extremum, extrema, local_quadratic, smooth};
use super::tracks::check_tracks;
use super::{FrameMarks, Recording};
use crate::physics::model::STATE_LEN;
use crate::physics::{Body, Conversion, ParamError, TurnKind, Units, paper};
use rayon::prelude::*;
use std::f64::consts::PI;
use thiserror::Error;

/// Half width (frames) of the local quadratic fits for rates and turning points.
pub const SMOOTH_HALF_WINDOW: usize = 3;
/// Largest `phi` sigma (rad) for which `phi` is followed from frame to frame.
const PHI_SIGMA_TRACKED: f64 = 0.15;
/// Shortest stretch (frames) whose `(phi, psi)` branch the rolling settles.
const MIN_STRETCH: usize = 10;
/// Largest jump of `phi` (rad) between frames of one stretch.
const PHI_JUMP_MAX: f64 = 1.2;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum RecoverError {
    #[error("the recording's body is impossible: {0}")]
    Body(ParamError),
    #[error("no frame has three or more marks: the pose cannot be recovered")]
    NoPose,
}

/// Euler angles (rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Angles {
    pub phi: f64,
    pub theta: f64,
    pub psi: f64,
}

/// What one frame shows, in mm, s and rad.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameMotion {
    pub t_s: f64,
    /// Marks tracked.
    pub marks: usize,
    pub a_mm: Option<[f64; 2]>,
    /// Per axis.
    pub a_sigma_mm: f64,
    /// Angles; `phi` and `psi` continuous along each stretch.
    pub angles: Option<Angles>,
    pub angles_sigma: [f64; 3],
    /// Whether the `(phi, psi)` branch was settled by the rolling (else it is a guess).
    pub branch_checked: bool,
    /// The stretch of frames along which `phi` and `psi` are continuous (None: not followed).
    pub stretch: Option<usize>,
    /// Velocity of A on the table.
    pub v_mm_s: Option<[f64; 2]>,
    pub v_p_mm_s: Option<f64>,
    pub v_p_sigma_mm_s: f64,
}

/// A turning point of `theta`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DataTurningPoint {
    pub kind: TurnKind,
    /// Fractional index into the frames, and its standard deviation.
    pub at: f64,
    pub at_sigma: f64,
    pub t_s: f64,
    pub theta: f64,
    pub theta_sigma: f64,
}

#[derive(Clone, Debug)]
pub struct RecoveredMotion {
    pub frames: Vec<FrameMotion>,
    /// Pixel noise per coordinate from each mark's track alone (`tracks::check_tracks`, as the
    /// fit and the diagnosis judge by; a film tracker's own estimate where larger), else the
    /// marks' scatter about their poses (None: neither could be estimated).
    pub noise_px: Option<f64>,
    /// The marks' scatter about each frame's fitted pose, per coordinate (None: no frame had a
    /// spare mark). Above the noise where the camera is not the flat view the pose assumes
    /// (a near or tilted camera, a lens).
    pub pose_scatter_px: Option<f64>,
    pub mark_order: MarkOrder,
    /// +1 when the ring spins counter-clockwise seen from above, -1 clockwise.
    pub spin_sign: f64,
    pub turning_points: Vec<DataTurningPoint>,
    /// The first inner turning point (the first frame when that is one).
    pub first_inner_turn: Option<DataTurningPoint>,
    /// First frame index of the still end, if the ring comes to rest in the recording.
    pub rest_from: Option<usize>,
    pub camera: Camera,
    pub body_mm: Body,
    pub geometry_mm: MarkGeometry,
    /// The model's units: length = mean radius, `g` as in the paper's case.
    pub units: Units,
    pub fps: f64,
}

/// Recovers the motion with the recording's own camera (no lens distortion).
pub fn recover(rec: &Recording) -> Result<RecoveredMotion, RecoverError> {
    recover_with(rec, Camera::for_recording(&rec.header, &rec.frames))
}

/// Recovers the motion through a given camera (e.g. with a lens distortion).
pub fn recover_with(rec: &Recording, camera: Camera) -> Result<RecoveredMotion, RecoverError> {
    let body_mm = rec.header.body_mm().map_err(RecoverError::Body)?;
    let fps = rec.header.fps;
    let flat: Vec<FrameMarks> =
        rec.frames.iter().map(|f| f.map(|m| m.map(|p| camera.to_mm(p)))).collect();
    let mark_order = mark_order(&flat);
    let geometry_mm = MarkGeometry::of_body(&body_mm, mark_order);
    // A camera tilted as a tripod's sees each mark where its ray meets the mark's height, far
    // from where it meets the table: the marks mapped onto the plan through their frames'
    // poses in space. A camera looking down (a near one included) keeps the flat mapping, the
    // start the diagnosis's fits through a pinhole were made for.
    let tripod = camera.tilt_rad.abs() >= TRIPOD_TILT_DEG.to_radians();
    let marks_mm = if tripod { marks_on_table(&rec.frames, &geometry_mm, &camera) } else { flat };
    let fits: Vec<Option<PoseFit>> = marks_mm
        .par_iter()
        .map(|m| initial_pose(m, &geometry_mm).map(|s| fit_pose(m, &geometry_mm, s)))
        .collect();
    if fits.iter().all(Option::is_none) {
        return Err(RecoverError::NoPose);
    }
    let (ss, dof) =
        fits.iter().flatten().fold((0.0, 0usize), |(s, d), f| (s + f.residual_ss, d + f.dof()));
    let sigma_mm = (dof > 0).then(|| (ss / dof as f64).sqrt());
    let sigma = sigma_mm.unwrap_or(f64::NAN);

    let mut frames: Vec<FrameMotion> = marks_mm
        .iter()
        .zip(&fits)
        .enumerate()
        .map(|(i, (m, fit))| {
            let pairs = (m[0].is_some() && m[2].is_some()) as usize
                + (m[1].is_some() && m[3].is_some()) as usize;
            let angles_sigma = fit.map_or([f64::INFINITY; 3], |f| f.angle_sigmas(sigma));
            FrameMotion {
                t_s: rec.time_s(i),
                marks: m.iter().flatten().count(),
                a_mm: fit.map(|f| f.pose.a).or_else(|| point_a(m)),
                a_sigma_mm: if pairs > 0 {
                    sigma / (2.0 * pairs as f64).sqrt()
                } else {
                    f64::INFINITY
                },
                angles: fit.map(|f| Angles {
                    phi: f.pose.phi,
                    theta: f.pose.theta,
                    psi: f.pose.psi,
                }),
                angles_sigma,
                branch_checked: false,
                stretch: None,
                v_mm_s: None,
                v_p_mm_s: None,
                v_p_sigma_mm_s: f64::INFINITY,
            }
        })
        .collect();
    velocities(&mut frames, fps);
    resolve_branches(&mut frames, &body_mm, fps);

    let theta: Vec<f64> = frames.iter().map(|f| f.angles.map_or(f64::NAN, |a| a.theta)).collect();
    let theta_sigma: Vec<f64> = frames.iter().map(|f| f.angles_sigma[1]).collect();
    let smoothed = smooth(&theta, &theta_sigma, SMOOTH_HALF_WINDOW);
    let to_point = |e: &Extremum| DataTurningPoint {
        kind: e.kind,
        at: e.at,
        at_sigma: e.at_sigma,
        t_s: rec.time_s(0) + e.at / fps,
        theta: e.value,
        theta_sigma: e.sigma,
    };
    let turning_points: Vec<DataTurningPoint> =
        extrema(&smoothed, 3.0).iter().map(to_point).collect();
    let first_inner_turn =
        first_inner_turn(&theta, &theta_sigma, &turning_points).map(|at| match at {
            Some(p) => p,
            None => DataTurningPoint {
                kind: TurnKind::ThetaMin,
                at: 0.0,
                at_sigma: 0.5,
                t_s: rec.time_s(0),
                theta: smoothed.value[0],
                theta_sigma: smoothed.value_sigma[0],
            },
        });
    let tracks_px = check_tracks(rec).noise.map(|n| n.px);
    let scatter_px = sigma_mm.map(|s| s * camera.px_per_mm);
    let noise_px = tracks_px.or(scatter_px);
    // A still mark jitters by all of its noise: the scatter about the poses holds a tracker's
    // noise correlated in time, which the tracks' differences miss. Beyond twice the tracks'
    // noise the scatter is the camera's (a near or tilted camera, a lens), not jitter, and
    // judged by it a ring still walking slowly was called still.
    let still_px = match (tracks_px, scatter_px) {
        (Some(t), Some(s)) => Some(s.max(t).min(2.0 * t)),
        (t, s) => t.or(s),
    };
    let rest_from = still_px.and_then(|n| rest_from(&marks_mm, n / camera.px_per_mm));
    let spin_sign = spin_sign(&frames, fps);
    let units = Units::dimensionless(body_mm.mean_radius(), paper::g());
    Ok(RecoveredMotion {
        frames,
        noise_px,
        pose_scatter_px: sigma_mm.map(|s| s * camera.px_per_mm),
        mark_order,
        spin_sign,
        turning_points,
        first_inner_turn,
        rest_from,
        camera,
        body_mm,
        geometry_mm,
        units,
        fps,
    })
}

/// Frames before the recording's start that a minimum of `theta` may lie and still count as
/// the first frame's (the fit then places it exactly: `analysis::fit`).
pub const START_VERTEX_FRAMES: f64 = 1.5;

/// The first inner turning point: `Some(None)` when it is the first frame, that is, `theta`
/// rises to a maximum first and the vertex of a quadratic through the first five frames lies
/// at most [`START_VERTEX_FRAMES`] before it; else the first minimum found.
fn first_inner_turn(
    theta: &[f64],
    sigma: &[f64],
    points: &[DataTurningPoint],
) -> Option<Option<DataTurningPoint>> {
    let first_min = points.iter().find(|p| p.kind == TurnKind::ThetaMin).copied();
    if points.first().is_some_and(|p| p.kind == TurnKind::ThetaMax) {
        let w: Vec<f64> = sigma
            .iter()
            .map(|s| if s.is_finite() && *s > 0.0 { 1.0 / (s * s) } else { 0.0 })
            .collect();
        if let Some(([_, slope, half_curv], _)) = local_quadratic(theta, &w, 0, 4, 0.0) {
            let vertex = -slope / (2.0 * half_curv);
            if half_curv > 0.0 && vertex >= -START_VERTEX_FRAMES {
                return Some(None);
            }
        }
    }
    first_min.map(Some)
}

/// The order of the mark numbers from the signed areas of the frames' quadrilaterals (on the
/// table, `Y` up: clockwise is negative).
fn mark_order(marks: &[FrameMarks]) -> MarkOrder {
    let mut votes = 0i64;
    for m in marks {
        if let [Some(a), Some(b), Some(c), Some(d)] = m {
            let p = [a, b, c, d];
            let area: f64 =
                (0..4).map(|k| p[k][0] * p[(k + 1) % 4][1] - p[(k + 1) % 4][0] * p[k][1]).sum();
            votes += if area < 0.0 { 1 } else { -1 };
        }
    }
    if votes >= 0 { MarkOrder::Forward } else { MarkOrder::Reverse }
}

/// Central differences of A (one-sided at gaps and ends).
fn velocities(frames: &mut [FrameMotion], fps: f64) {
    let n = frames.len();
    for i in 0..n {
        let a = |j: usize| frames[j].a_mm.map(|p| (p, frames[j].a_sigma_mm));
        let (lo, hi) =
            match (i.checked_sub(1).and_then(a), (i + 1 < n).then(|| a(i + 1)).flatten(), a(i)) {
                (Some(p), Some(q), _) => (p, q),
                (Some(p), None, Some(c)) => (p, c),
                (None, Some(q), Some(c)) => (c, q),
                _ => continue,
            };
        let span =
            if i > 0 && i + 1 < n && frames[i - 1].a_mm.is_some() && frames[i + 1].a_mm.is_some() {
                2.0
            } else {
                1.0
            };
        let dt = span / fps;
        let v = [(hi.0[0] - lo.0[0]) / dt, (hi.0[1] - lo.0[1]) / dt];
        frames[i].v_mm_s = Some(v);
        frames[i].v_p_mm_s = Some(v[0].hypot(v[1]));
        frames[i].v_p_sigma_mm_s = lo.1.hypot(hi.1) / dt;
    }
}

fn wrap(x: f64) -> f64 {
    (x + PI).rem_euclid(2.0 * PI) - PI
}

/// Follows `(phi, psi)` continuously along stretches and turns each stretch to the branch
/// whose rolling agrees with the measured velocity of A.
fn resolve_branches(frames: &mut [FrameMotion], body: &Body, fps: f64) {
    let mut start = 0;
    let mut stretches = 0;
    while start < frames.len() {
        // Grow a stretch from `start`.
        let mut end = start;
        if frames[start].angles.is_some() && frames[start].angles_sigma[0] < PHI_SIGMA_TRACKED {
            if let Some(a) = frames[start].angles.as_mut() {
                a.phi = wrap(a.phi);
                a.psi = wrap(a.psi);
            }
            while end + 1 < frames.len() {
                let (prev, next) = (frames[end].angles, frames[end + 1].angles);
                let (Some(p), Some(mut q)) = (prev, next) else { break };
                if frames[end + 1].angles_sigma[0] >= PHI_SIGMA_TRACKED {
                    break;
                }
                if wrap(q.phi - p.phi).abs() > PI / 2.0 {
                    q.phi += PI;
                    q.psi += PI;
                }
                let dphi = wrap(q.phi - p.phi);
                if dphi.abs() > PHI_JUMP_MAX {
                    break;
                }
                q.phi = p.phi + dphi;
                q.psi = p.psi + wrap(q.psi - p.psi);
                frames[end + 1].angles = Some(q);
                end += 1;
            }
        }
        if frames[start].angles.is_some() && frames[start].angles_sigma[0] < PHI_SIGMA_TRACKED {
            for f in &mut frames[start..=end] {
                f.stretch = Some(stretches);
            }
            stretches += 1;
        }
        if end + 1 >= start + MIN_STRETCH {
            let score = rolling_agreement(&frames[start..=end], body, fps);
            for f in &mut frames[start..=end] {
                if score < 0.0
                    && let Some(a) = f.angles.as_mut()
                {
                    a.phi += PI;
                    a.psi += PI;
                }
                f.branch_checked = true;
            }
        }
        start = end + 1;
    }
}

/// Sum over a stretch of `v_pred . v_measured`, `v_pred` the velocity of A that rolling gives
/// for the stretch's angles and their rates.
fn rolling_agreement(frames: &[FrameMotion], body: &Body, fps: f64) -> f64 {
    let mut score = 0.0;
    for i in 1..frames.len() - 1 {
        let (Some(p), Some(c), Some(q), Some(v)) =
            (frames[i - 1].angles, frames[i].angles, frames[i + 1].angles, frames[i].v_mm_s)
        else {
            continue;
        };
        let rate = |a: f64, b: f64| (b - a) * fps / 2.0;
        let v_pred = rolling_velocity_of_a(
            body,
            &c,
            [rate(p.theta, q.theta), rate(p.phi, q.phi), rate(p.psi, q.psi)],
        );
        score += v_pred[0] * v[0] + v_pred[1] * v[1];
    }
    score
}

/// Velocity of A on the table under rolling for angles `a` and rates `(theta', phi', psi')`.
pub fn rolling_velocity_of_a(body: &Body, a: &Angles, rates: [f64; 3]) -> [f64; 2] {
    let (st, ct) = a.theta.sin_cos();
    let (sp, cp) = a.phi.sin_cos();
    let w1 = rates[0];
    let w2 = rates[1] * st + rates[2];
    let w3 = rates[1] * ct;
    // Frame components (w2 R - w3 h, -w1 R, w1 h); e2 and e3 project onto E2' by cos and -sin.
    let v1 = w2 * body.r - w3 * body.h;
    let along = -w1 * body.r * ct - w1 * body.h * st;
    [v1 * cp - along * sp, v1 * sp + along * cp]
}

/// First frame of the still end: every mark within 5 sigma of its mean over the last ten frames.
fn rest_from(marks: &[FrameMarks], sigma_mm: f64) -> Option<usize> {
    const TAIL: usize = 10;
    let n = marks.len();
    if n < TAIL {
        return None;
    }
    let mut mean = [[0.0f64; 2]; 4];
    let mut count = [0usize; 4];
    for m in &marks[n - TAIL..] {
        for k in 0..4 {
            if let Some(p) = m[k] {
                mean[k][0] += p[0];
                mean[k][1] += p[1];
                count[k] += 1;
            }
        }
    }
    for k in 0..4 {
        if count[k] > 0 {
            mean[k] = [mean[k][0] / count[k] as f64, mean[k][1] / count[k] as f64];
        }
    }
    let still = |m: &FrameMarks| {
        (0..4).all(|k| {
            m[k].is_none_or(|p| {
                count[k] > 0 && (p[0] - mean[k][0]).hypot(p[1] - mean[k][1]) < 5.0 * sigma_mm
            })
        })
    };
    if !marks[n - TAIL..].iter().all(still) {
        return None;
    }
    let mut first = n - TAIL;
    while first > 0 && still(&marks[first - 1]) {
        first -= 1;
    }
    Some(first)
}

/// Sign of `omega . Z = phi' + psi' sin(theta)` over the first checked frames.
fn spin_sign(frames: &[FrameMotion], fps: f64) -> f64 {
    let mut sum = 0.0;
    let mut used = 0;
    for i in 1..frames.len().saturating_sub(1) {
        let (Some(p), Some(c), Some(q)) =
            (frames[i - 1].angles, frames[i].angles, frames[i + 1].angles)
        else {
            continue;
        };
        if !(frames[i - 1].branch_checked
            && frames[i].branch_checked
            && frames[i + 1].branch_checked)
        {
            continue;
        }
        sum += (q.phi - p.phi) * fps / 2.0 + (q.psi - p.psi) * fps / 2.0 * c.theta.sin();
        used += 1;
        if used == 100 {
            break;
        }
    }
    if sum < 0.0 { -1.0 } else { 1.0 }
}

impl RecoveredMotion {
    /// A sentence where the marks scatter about their flat poses more than twice the noise.
    pub fn pose_scatter_note(&self) -> Option<String> {
        let (noise, scatter) = (self.noise_px?, self.pose_scatter_px?);
        (scatter > 2.0 * noise).then(|| {
            format!(
                "the marks scatter {scatter:.2} px about each frame's flat pose, {:.0} times the noise: the camera is not the flat view the pose assumes (near, tilted, a lens: the diagnosis's camera effects), or the tracker slipped",
                scatter / noise
            )
        })
    }

    /// From mm and s to the model's units.
    pub fn to_model(&self) -> Conversion {
        Conversion::between(Units::MM_S, self.units)
    }

    /// The body in the model's units.
    pub fn body_model(&self) -> Result<Body, ParamError> {
        self.body_mm.scaled(self.to_model().length)
    }

    /// Rates `(theta', phi', psi')` in rad/s at frame `i` from local quadratic fits of the
    /// angles over `+-half` frames of the same stretch, with their sigmas.
    pub fn rates(&self, i: usize, half: usize) -> Option<([f64; 3], [f64; 3])> {
        let n = self.frames.len();
        let stretch = self.frames.get(i)?.stretch?;
        let lo = i.saturating_sub(half);
        let hi = (i + half).min(n.checked_sub(1)?);
        let mut rates = [0.0; 3];
        let mut sigmas = [0.0; 3];
        for k in 0..3 {
            let (mut y, mut w) = (vec![f64::NAN; n], vec![0.0; n]);
            for j in lo..=hi {
                let f = &self.frames[j];
                if let (Some(a), true) = (f.angles, f.stretch == Some(stretch)) {
                    y[j] = [a.theta, a.phi, a.psi][k];
                    let s = f.angles_sigma[[1, 0, 2][k]];
                    w[j] = if s.is_finite() && s > 0.0 { 1.0 / (s * s) } else { 0.0 };
                }
            }
            let ([_, d, _], [_, sd]) = super::smooth::local_quadratic(&y, &w, lo, hi, i as f64)?;
            rates[k] = d * self.fps;
            sigmas[k] = sd * self.fps;
        }
        Some((rates, sigmas))
    }

    /// The state at frame `i` as the paper reads it at an inner turning point: `theta' = 0`,
    /// `psi' = 0`, and `phi'` from the velocity of A, which rolling then makes
    /// `(R sin(theta) - h cos(theta)) phi'` along `e1` (`flipped` as in
    /// [`RecoveredMotion::state`]). None without a pose or a velocity, or where that lever is
    /// too short to divide by (`tan(theta)` near `h/R`).
    pub fn turning_point_state(&self, i: usize, flipped: bool) -> Option<[f64; STATE_LEN]> {
        let f = self.frames.get(i)?;
        let (mut a, p, v) = (f.angles?, f.a_mm?, f.v_mm_s?);
        if flipped {
            a.phi += PI;
            a.psi += PI;
        }
        let b = &self.body_mm;
        let (st, ct) = a.theta.sin_cos();
        let lever = b.r * st - b.h * ct;
        if lever.abs() < 0.05 * b.r {
            return None;
        }
        let (sp, cp) = a.phi.sin_cos();
        let k = self.to_model();
        let phi_dot = (v[0] * cp + v[1] * sp) / lever * k.rate();
        let half_h = 0.5 * b.h;
        let c = [p[0] + half_h * ct * sp, p[1] - half_h * ct * cp];
        Some([
            a.phi,
            a.theta,
            a.psi,
            0.0,
            phi_dot * st,
            phi_dot * ct,
            c[0] * k.length,
            c[1] * k.length,
        ])
    }

    /// The model's state `[phi, theta, psi, w1, w2, w3, x_C, y_C]` at frame `i` in model
    /// units, with the angles' rates from [`RecoveredMotion::rates`]; `flipped` takes the
    /// other branch `(phi + pi, psi + pi)`, the same marks. None where the pose or its rates
    /// are not known.
    pub fn state(&self, i: usize, half: usize, flipped: bool) -> Option<[f64; STATE_LEN]> {
        let f = self.frames.get(i)?;
        let (mut a, p) = (f.angles?, f.a_mm?);
        if flipped {
            a.phi += PI;
            a.psi += PI;
        }
        let (rates, _) = self.rates(i, half)?;
        let k = self.to_model();
        let (st, ct) = a.theta.sin_cos();
        let (sp, cp) = a.phi.sin_cos();
        let [theta_dot, phi_dot, psi_dot] = rates.map(|r| r * k.rate());
        // C = A - (h/2) e2, e2 on the table = cos(theta) (-sin phi, cos phi).
        let half_h = 0.5 * self.body_mm.h;
        let c = [p[0] + half_h * ct * sp, p[1] - half_h * ct * cp];
        Some([
            a.phi,
            a.theta,
            a.psi,
            theta_dot,
            phi_dot * st + psi_dot,
            phi_dot * ct,
            c[0] * k.length,
            c[1] * k.length,
        ])
    }
}
