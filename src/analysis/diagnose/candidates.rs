//! The candidates: each effect refitted over the whole run with its strength free, next to
//! the baseline, all on the same misfit ([`super::whole`]).
//!
//! A candidate's path: its strength is first chosen from a few values spanning its
//! realistic range by the multiple-shooting cost at the baseline's segment states (cheap: one
//! run of the recording each); then the segments are merged down to one. Two safeguards keep
//! the comparison fair where a least-squares path ends in a side valley: a candidate nests
//! the baseline (at zero strength it IS the baseline), so one that ends worse than the
//! baseline is refitted from the baseline's solution; and the baseline is refitted from the
//! best candidate's drag and start, so that "before" is the baseline at its best, not a
//! baseline that happened to stop early.

use super::whole::{WholeFit, fit_whole, segment_cost, start_globals, with_effect};
use crate::analysis::fit::lm::LmError;
use crate::analysis::fit::shooting::Shooting;
use crate::physics::effects::EffectKind;
use crate::physics::slip::painleve_mu_limit;
use crate::physics::StateVec;
use rayon::prelude::*;
use std::sync::atomic::AtomicBool;

/// Strengths tried first for `kind`: half the realistic range's low end, its ends, its middle
/// and twice its high end (both signs for the lens, whose realistic range is barrel only but
/// whose sign the data decide). Slip: up to the Painleve limit `mu_max`.
pub fn trial_strengths(kind: EffectKind, mu_max: f64) -> Vec<f64> {
    let (lo, hi) = kind.realistic_range();
    match kind {
        EffectKind::None => vec![0.0],
        EffectKind::CameraDistortion => vec![-2.0 * lo.abs(), lo, 0.5 * (lo + hi), hi, -hi, -lo],
        EffectKind::Slip => {
            let mut v: Vec<f64> = [0.5 * lo, lo, (lo * hi).sqrt(), hi, 0.5 * (hi + mu_max), 0.98 * mu_max]
                .into_iter()
                .filter(|&m| m < 0.98 * mu_max + 1e-12)
                .collect();
            v.dedup_by(|a, b| (*a - *b).abs() < 1e-3);
            v
        }
        _ => vec![0.5 * lo, lo, (lo * hi).sqrt(), hi, 2.0 * hi],
    }
}

/// The strength that small: where a candidate starts from the baseline's own solution.
pub fn near_baseline_strength(kind: EffectKind, mu_max: f64) -> f64 {
    let (lo, _) = kind.realistic_range();
    match kind {
        EffectKind::Slip => 0.98 * mu_max,
        EffectKind::CameraDistortion => 0.1 * lo,
        _ => 0.1 * lo,
    }
}

/// The largest `mu` the sliding contact allows for this body (`slip.rs`).
pub fn mu_limit(sh: &Shooting) -> f64 {
    painleve_mu_limit(&sh.spec.base)
}

/// Fits one candidate along its path (see the module doc). `on_iteration(segments, cost)`.
pub fn fit_candidate(
    ms: &Shooting,
    states: &[StateVec],
    kind: EffectKind,
    on_iteration: &mut dyn FnMut(usize, f64),
    cancel: &AtomicBool,
) -> Result<WholeFit, LmError> {
    let sh = with_effect(ms, kind);
    let mu_max = mu_limit(ms);
    let trials = trial_strengths(kind, mu_max);
    let costs: Vec<f64> = trials.iter().map(|&s| segment_cost(&sh, &start_globals(&sh, s), states)).collect();
    let best = (0..trials.len()).min_by(|&a, &b| costs[a].total_cmp(&costs[b])).ok_or(LmError::BadStart)?;
    fit_whole(&sh, start_globals(&sh, trials[best]), states, on_iteration, cancel)
}

/// Refits `kind` over the whole run as one segment from `from`'s drag and start state (the
/// strength `strength`, for a candidate): the safeguards of the module doc.
pub fn refit_from(
    ms: &Shooting,
    kind: EffectKind,
    from: &WholeFit,
    strength: f64,
    cancel: &AtomicBool,
) -> Result<WholeFit, LmError> {
    let mut sh = with_effect(ms, kind);
    sh.segments = vec![from.span.clone()];
    let mut g = from.internal[..3].to_vec();
    if kind != EffectKind::None {
        g.push(strength);
    }
    fit_whole(&sh, g, &[from.start], &mut |_, _| {}, cancel)
}

/// The baseline and every candidate, fitted in parallel, with the safeguards applied.
/// `progress(kind, segments, cost)` as each path goes on; `done(kind)` when one is fitted.
pub fn fit_all(
    ms: &Shooting,
    states: &[StateVec],
    kinds: &[EffectKind],
    progress: &(dyn Fn(EffectKind, usize, f64) + Sync),
    done: &(dyn Fn(EffectKind) + Sync),
    cancel: &AtomicBool,
) -> Result<(WholeFit, Vec<(EffectKind, Result<WholeFit, LmError>)>), LmError> {
    let mut all: Vec<EffectKind> = vec![EffectKind::None];
    all.extend(kinds.iter().copied().filter(|&k| k != EffectKind::None));
    let fits: Vec<(EffectKind, Result<WholeFit, LmError>)> = all
        .par_iter()
        .map(|&k| {
            let r = fit_candidate(ms, states, k, &mut |segments, cost| progress(k, segments, cost), cancel);
            done(k);
            (k, r)
        })
        .collect();
    let mut fits = fits.into_iter();
    let mut baseline = match fits.next() {
        Some((_, r)) => r?,
        None => return Err(LmError::BadStart),
    };
    let mut candidates: Vec<(EffectKind, Result<WholeFit, LmError>)> = fits.collect();
    let mu_max = mu_limit(ms);
    if candidates.iter().any(|(_, r)| matches!(r, Err(LmError::Cancelled))) {
        return Err(LmError::Cancelled);
    }
    // A candidate that ended worse than the model it contains: again from the baseline.
    candidates.par_iter_mut().for_each(|(k, r)| {
        let worse = r.as_ref().map_or(true, |w| w.cost > baseline.cost);
        if worse && let Ok(w) = refit_from(ms, *k, &baseline, near_baseline_strength(*k, mu_max), cancel) {
            match r {
                Ok(old) if old.cost <= w.cost => {}
                _ => *r = Ok(w),
            }
        }
    });
    // The baseline from the best candidate's drag and start.
    let best = candidates.iter().filter_map(|(_, r)| r.as_ref().ok()).min_by(|a, b| a.cost.total_cmp(&b.cost));
    if let Some(best) = best
        && best.cost < baseline.cost
    {
        let again = refit_from(ms, EffectKind::None, best, 0.0, cancel)?;
        if again.cost < baseline.cost {
            baseline = again;
        }
    }
    Ok((baseline, candidates))
}
