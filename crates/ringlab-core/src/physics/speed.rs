//! The integrator's speed, measured: what `ringlab bench` and the core's example
//! `integrator_speed` print (`docs/speed.md`). Each figure is the fastest of several blocks,
//! which on a shared machine is the one least disturbed by the others.

use super::integrator::System;
use super::model::{Initial, Model, StateVec, ix};
use super::run::{RunError, RunOptions, RunSummary, Simulation};
use super::trig::sin_cos;
use std::hint::black_box;
use web_time::Instant;

/// Blocks the evaluations are timed in.
const BLOCKS: usize = 20;

/// Nanoseconds per right-hand-side evaluation at states near `y0` (the tilt varied by 1e-9 so
/// that nothing is hoisted), over about `evaluations` of them.
pub fn rhs_ns(model: &Model, y0: &StateVec, evaluations: usize) -> f64 {
    let per_block = (evaluations / BLOCKS).max(1);
    let mut dy = [0.0; 8];
    let mut y = *y0;
    fastest_block(per_block, || {
        for i in 0..per_block {
            y[ix::THETA] = y0[ix::THETA] + 1e-9 * (i & 1023) as f64;
            model.rhs(0.0, black_box(&y), &mut dy);
            black_box(&dy);
        }
    })
}

/// Nanoseconds per [`sin_cos`] (a sine and a cosine of one angle, as the right-hand side
/// takes them), the unit of the right-hand side's floor.
pub fn sin_cos_ns(evaluations: usize) -> f64 {
    let per_block = (evaluations / BLOCKS).max(1);
    fastest_block(per_block, || {
        let mut acc = 0.0;
        for i in 0..per_block {
            let (s, c) = sin_cos(black_box(0.55 + 1e-9 * (i & 1023) as f64));
            acc += s + c;
        }
        black_box(acc);
    })
}

fn fastest_block(per_block: usize, mut block: impl FnMut()) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..BLOCKS {
        let clock = Instant::now();
        block();
        best = best.min(clock.elapsed().as_secs_f64() * 1e9 / per_block as f64);
    }
    best
}

/// `repeats` runs from `initial` to their end, each timed in milliseconds (building the run
/// included), and the last run's summary.
pub fn time_runs(
    model: &Model,
    initial: &Initial,
    opts: &RunOptions,
    repeats: usize,
) -> Result<(Vec<f64>, RunSummary), RunError> {
    let mut times = Vec::with_capacity(repeats.max(1));
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let clock = Instant::now();
        let sim = Simulation::new(model.clone(), initial, opts.clone())?;
        let summary = sim.run(&mut |s| {
            black_box(s);
        });
        times.push(clock.elapsed().as_secs_f64() * 1e3);
        last = Some(summary);
    }
    let last = last.ok_or(RunError::Unsupported("no run timed"))?;
    Ok((times, last))
}

/// The median of `v` (the upper one of an even count); NaN for none.
pub fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

/// The smallest of `v`; infinite for none.
pub fn fastest(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::paper;

    #[test]
    fn the_timed_runs_are_the_paper_run() {
        let opts = RunOptions { sample_dt: None, track_validity: false, ..RunOptions::default() };
        let model = paper::ring_model(paper::C_RING);
        let (times, summary) = time_runs(&model, &paper::initial(), &opts, 2).expect("runs");
        assert_eq!(times.len(), 2);
        assert_eq!(summary.end_reason, crate::physics::EndReason::Flat);
        assert!((summary.t_end - 126.102).abs() < 1e-3, "ends at {}", summary.t_end);
        assert_eq!((median(&[3.0, 1.0, 2.0]), fastest(&[3.0, 1.0, 2.0])), (2.0, 1.0));
        assert!(median(&[]).is_nan());
    }
}
