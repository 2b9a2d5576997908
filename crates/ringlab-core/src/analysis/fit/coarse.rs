//! The coarse stage: a grid of drag coefficients (the sweep's machinery), each run once from
//! the start state and scored on features that do not depend on the path's phase: the
//! envelopes of `theta` (its values at the turning points, against time) and the time the
//! motion ends. A plain point-by-point misfit from one start would be ragged over the grid
//! (a small change of drag shifts every later cycloid); these features change smoothly.

use crate::analysis::sweep::{Axis, grid_map};
use crate::physics::{Model, RunOptions, Simulation, StateVec, TurnKind};

/// What the data show, in model time (`t = frame dt`).
#[derive(Clone, Debug, Default)]
pub struct Features {
    /// `(kind, t, theta, sigma)` of the data's turning points after the start.
    pub turning_points: Vec<(TurnKind, f64, f64, f64)>,
    /// When the ring comes to rest, if it does in the recording.
    pub t_end: Option<f64>,
    /// The end's uncertainty (model time).
    pub t_end_sigma: f64,
}

/// Floor on a turning point's sigma: the model's envelope is not exact to the data's noise.
const THETA_SIGMA_FLOOR: f64 = 0.01;

/// Where the coarse runs start and stop.
#[derive(Clone, Copy, Debug)]
pub struct Span {
    pub t0: f64,
    pub y0: StateVec,
    /// Past the recording's end.
    pub t_stop: f64,
}

/// Sum of squared normalized differences between the model's features and the data's, for
/// a run over `span`. Infinite when the run cannot start.
pub fn feature_misfit(model: &Model, run: &RunOptions, span: &Span, data: &Features) -> f64 {
    let t_stop = span.t_stop;
    let opts = RunOptions { t_end: t_stop, sample_dt: None, track_validity: false, ..run.clone() };
    let Ok(sim) = Simulation::from_state(model.clone(), span.t0, span.y0, opts) else {
        return f64::INFINITY;
    };
    let summary = sim.run(&mut |_| {});
    let ended = summary.end_reason.is_natural();
    let envelope = |kind: TurnKind| -> Vec<(f64, f64)> {
        summary
            .turning_points
            .iter()
            .filter(|p| p.kind == kind)
            .map(|p| (p.sample.t, p.sample.theta()))
            .collect()
    };
    let (mins, maxs) = (envelope(TurnKind::ThetaMin), envelope(TurnKind::ThetaMax));
    let mut sum = 0.0;
    for &(kind, t, theta, sigma) in &data.turning_points {
        let env = if kind == TurnKind::ThetaMin { &mins } else { &maxs };
        let model_theta = if ended && t >= summary.t_end {
            run.theta_flat
        } else {
            interpolate(env, t).unwrap_or(summary.final_sample.theta())
        };
        let z = (model_theta - theta) / sigma.max(THETA_SIGMA_FLOOR);
        sum += z * z;
    }
    if let Some(t_end) = data.t_end {
        let model_end = if ended { summary.t_end } else { t_stop.max(summary.t_end) };
        let z = (model_end - t_end) / data.t_end_sigma;
        sum += z * z;
    }
    sum
}

/// Linear interpolation in `(t, value)` points sorted by `t`, clamped at the ends.
fn interpolate(points: &[(f64, f64)], t: f64) -> Option<f64> {
    let first = points.first()?;
    if t <= first.0 {
        return Some(first.1);
    }
    for w in points.windows(2) {
        if t <= w[1].0 {
            let f = (t - w[0].0) / (w[1].0 - w[0].0);
            return Some(w[0].1 + f * (w[1].1 - w[0].1));
        }
    }
    points.last().map(|p| p.1)
}

/// The grid point with the smallest feature misfit, and that misfit; a second, finer grid
/// around the first's best. `progress(done, total)`.
pub fn sweep(
    model: &Model,
    run: &RunOptions,
    span: &Span,
    data: &Features,
    axes: [Axis; 3],
    progress: &(dyn Fn(usize, usize) + Sync),
) -> ([f64; 3], f64) {
    let n1: usize = axes.iter().map(|a| a.n).product();
    let refine = |best: [f64; 3]| {
        let ratio = |a: &Axis| {
            if a.n > 1 && a.log { (a.hi / a.lo).powf(1.0 / (a.n - 1) as f64) } else { 1.0 }
        };
        let mut i = 0;
        axes.map(|a| {
            let r = ratio(&a);
            let b = best[i];
            i += 1;
            Axis { lo: b / r, hi: b * r, n: 5, log: true }
        })
    };
    let score = |c: [f64; 3]| {
        let mut m = model.clone();
        m.c_drag = c;
        (c, feature_misfit(&m, run, span, data))
    };
    let best_of = |rows: Vec<([f64; 3], f64)>| {
        rows.into_iter().fold(([0.0; 3], f64::INFINITY), |b, r| if r.1 < b.1 { r } else { b })
    };
    let first = best_of(grid_map(axes, &score, &|k| progress(k, n1 + 125)));
    if !first.1.is_finite() {
        return first;
    }
    let second = best_of(grid_map(refine(first.0), &score, &|k| progress(n1 + k, n1 + 125)));
    if second.1 < first.1 { second } else { first }
}
