//! The start states: the recording's poses made into model states, each segment's state fitted
//! with the globals fixed, and the model's state at the first inner turning point.

use super::coarse::Features;
use super::lm::{self, LmError, LmOptions};
use super::options::{FitError, FitStage};
use super::shooting::{OneSegment, Shooting, predict_samples};
use crate::physics::model::ix;
use crate::physics::{Initial, Model, RunOptions, Simulation, StateVec, TurnKind};
use crate::recording::recover::RecoveredMotion;
use std::ops::Range;

/// Every segment's start state with the globals fixed, each from the previous segment's end
/// or the recovered poses, whichever fits better; and the total cost.
pub(super) fn init_segments(
    sh: &Shooting,
    motion: &RecoveredMotion,
    global: &[f64],
    y0: StateVec,
    report: &dyn Fn(FitStage, usize, usize, Option<f64>),
) -> Result<(f64, Vec<StateVec>), FitError> {
    let count = sh.segments.len();
    let (model, _) = sh.spec.build(global).ok_or(FitError::BadStart)?;
    let (y0, mut total) = fit_segment(sh, 0, global, &[y0])?;
    let mut states = vec![y0];
    for s in 1..count {
        report(FitStage::Segments, s, count, None);
        let mut starts = Vec::new();
        let prev = sh.segments[s - 1].clone();
        if let Some(samples) =
            predict_samples(&model, &sh.run, sh.dt, &states[s - 1], prev.start..prev.end + 1)
            && let Some(last) = samples.last().filter(|x| x.t > (prev.end as f64 - 0.5) * sh.dt)
        {
            starts.push(last.y);
        }
        starts.extend(reconstruct(motion, sh.segments[s].start));
        if starts.is_empty() {
            starts.push(states[s - 1]);
        }
        let (y, cost) = fit_segment(sh, s, global, &starts)?;
        states.push(y);
        total += cost;
    }
    Ok((total, states))
}

/// Segments of `len` frames over `start..end`; a short remainder joins the last segment.
pub(super) fn split(start: usize, end: usize, len: usize) -> Vec<Range<usize>> {
    let mut out = Vec::new();
    let mut a = start;
    while a < end {
        let b = (a + len).min(end);
        out.push(a..b);
        a = b;
    }
    if out.len() > 1
        && out.last().is_some_and(|r| r.len() < len / 2)
        && let Some(last) = out.pop()
        && let Some(prev) = out.last_mut()
    {
        prev.end = last.end;
    }
    out
}

/// The state at frame `i` from the recovered poses (or the nearest frame that has one), on
/// both branches `(phi, psi)` and `(phi + pi, psi + pi)` and with rates over +-2 and +-4
/// frames (the shorter for slow cameras): the fit keeps the one that fits best.
pub(super) fn reconstruct(motion: &RecoveredMotion, i: usize) -> Vec<StateVec> {
    let j = (0..4)
        .flat_map(|d| [i + d, i.saturating_sub(d)])
        .find(|&j| motion.state(j, 4, false).is_some());
    let Some(j) = j else { return Vec::new() };
    [(4, false), (4, true), (2, false), (2, true)]
        .iter()
        .filter_map(|&(half, f)| motion.state(j, half, f))
        .collect()
}

/// Fits segment `s`'s start state from the best of `starts` with the globals fixed.
pub(super) fn fit_segment(
    sh: &Shooting,
    s: usize,
    global: &[f64],
    starts: &[StateVec],
) -> Result<(StateVec, f64), FitError> {
    let problem = OneSegment { shooting: sh, segment: s, global: global.to_vec() };
    let cost = |y: &StateVec| {
        sh.segment_residuals(s, global, y)
            .map_or(f64::INFINITY, |r| r.iter().map(|x| x * x).sum::<f64>())
    };
    let best = starts
        .iter()
        .copied()
        .min_by(|a, b| cost(a).total_cmp(&cost(b)))
        .ok_or(FitError::BadStart)?;
    let opts = LmOptions { max_iterations: 25, rel_tol: 1e-6, ..LmOptions::default() };
    match lm::solve(&problem, best.to_vec(), vec![vec![]], &opts, &mut |_, _| {}, sh.cancel) {
        Ok(sol) => Ok((sol.global.as_slice().try_into().unwrap_or(best), sol.cost)),
        Err(LmError::Cancelled) => Err(FitError::Cancelled),
        // A start the model cannot run from: keep it, the joint fit may still move it.
        Err(LmError::BadStart) => Ok((best, f64::INFINITY)),
    }
}

/// A state with `theta' = 0` and the same `phi'` and `psi'` (w2 and w3 do not hold theta').
pub(super) fn level_start(y: &StateVec) -> StateVec {
    let mut y = *y;
    y[ix::W1] = 0.0;
    y
}

/// The data's features for the coarse stage, in model time.
pub(super) fn features(
    motion: &RecoveredMotion,
    f0: usize,
    moving_end: usize,
    n: usize,
    dt: f64,
) -> Features {
    let turning_points = motion
        .turning_points
        .iter()
        .filter(|p| p.at > f0 as f64 + 0.5 && p.at < moving_end as f64)
        .map(|p| (p.kind, p.at * dt, p.theta, p.theta_sigma))
        .collect();
    let t_end = (moving_end < n).then_some(moving_end as f64 * dt);
    Features { turning_points, t_end, t_end_sigma: 2.0 * dt }
}

/// The model's state at the first inner turning point: at frame `f0` when `theta`'s minimum
/// lies within half a frame before it (the start is the turning point to the frame), else the
/// first minimum the model passes in the next `window` frames.
pub(super) fn start_at_turning_point(
    model: &Model,
    run: &RunOptions,
    dt: f64,
    f0: usize,
    window: usize,
    y0: &StateVec,
) -> (Initial, f64) {
    let t0 = f0 as f64 * dt;
    let theta_ddot = model.dynamics_of(y0).omega_dot.x;
    let vertex = if theta_ddot > 0.0 { -y0[ix::W1] / theta_ddot } else { f64::INFINITY };
    if (-0.5 * dt..=0.0).contains(&vertex) {
        return (Initial::from_state(y0), t0);
    }
    let opts = RunOptions {
        t_end: t0 + window as f64 * dt,
        sample_dt: None,
        track_validity: false,
        ..run.clone()
    };
    if let Ok(sim) = Simulation::from_state(model.clone(), t0, *y0, opts) {
        let summary = sim.run(&mut |_| {});
        if let Some(p) = summary.turning_points.iter().find(|p| p.kind == TurnKind::ThetaMin) {
            return (Initial::from_state(&p.sample.y), p.sample.t);
        }
    }
    (Initial::from_state(y0), t0)
}
