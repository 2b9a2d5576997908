//! The candidates: each effect refitted over the whole run with its strength free, next to
//! the baseline, all on the same misfit ([`super::whole`]).
//!
//! Paths: the baseline walks from its multiple-shooting segments down to one; each candidate
//! starts where the baseline does, with its strength chosen there from values spanning its
//! realistic range by the cost at the baseline's states (one run of the recording each), and
//! walks the same way down to one segment. (Joining the baseline's path further down, at a
//! few long segments, is cheaper but fails: there the baseline's drag has absorbed so much of
//! an effect that the scan sees no effect as best, and from the baseline's valley the least
//! squares do not find the effect's.) Two safeguards keep the comparison fair where a least-squares path ends in a
//! side valley: the baseline is refitted from the best candidate's drag and start (and again
//! from where that fit ended while it still gains), so that "before" is the baseline at its best
//! and not one that stopped early; and a candidate nests
//! the baseline (at zero strength it IS the baseline), so one that ends worse than the
//! baseline is refitted from the baseline's solution. An effect without a baseline strength
//! (its descriptor's `baseline` is None) nests it only in the limit; where its run from the
//! baseline's solution starts above the path's ceiling, its path ends at its first stage
//! instead.

use super::result::{STAGE_CEILING, extras_of};
use super::whole::{
    FINAL_ITERATIONS, FINAL_REL_TOL, LEVEL_ITERATIONS, Level, WholeFit, fit_path, fit_whole,
    no_ceiling, segment_cost, stopped_at_stage, with_effect, with_effects,
};
use crate::analysis::fit::lm::{self, LmError, LmOptions};
use crate::analysis::fit::shooting::{Shooting, WorkBudget};
use crate::physics::effects::EffectKind;
use crate::physics::slip::painleve_mu_limit;
use crate::physics::{SlipStart, StateVec};
use rayon::prelude::*;
use std::sync::Arc;

/// Strengths tried first for `kind` (its descriptor's scan: nine log-spaced values from half
/// the realistic range's low end to twice its high end for most; the descriptor says where
/// another scan is needed, and `mu_max`, the contact's Painleve limit, bounds one). Not
/// zero: the baseline's drag and states absorb what they can of an effect, so at them no effect
/// always looks best.
pub fn trial_strengths(kind: EffectKind, mu_max: f64) -> Vec<f64> {
    let d = kind.descriptor();
    (d.scan)(d.realistic, mu_max)
}

/// The effect's free numbers tried first: each trial strength with every combination of its
/// extras' scan values (`Extra::scan`; an extra without one at its start).
pub fn trial_starts(kind: EffectKind, mu_max: f64) -> Vec<Vec<f64>> {
    if kind.free_count() == 0 {
        return vec![Vec::new()];
    }
    let mut starts: Vec<Vec<f64>> =
        trial_strengths(kind, mu_max).into_iter().map(|s| vec![s]).collect();
    for x in kind.descriptor().extras {
        let values = if x.scan.is_empty() { std::slice::from_ref(&x.start) } else { x.scan };
        starts = starts
            .into_iter()
            .flat_map(|p| {
                values.iter().map(move |&v| p.iter().copied().chain([v]).collect::<Vec<f64>>())
            })
            .collect();
    }
    starts
}

/// The strength at which a candidate starts from the baseline's own solution: the baseline
/// itself (its descriptor's baseline strength; where it has none, just below the contact's
/// limit `mu_max`, the nearest to the baseline). Not a small strength: over a whole run the
/// misfit is so sensitive that even a tenth of a realistic strength lands far up the valley's
/// side, and the least squares then crawl back.
pub fn near_baseline_strength(kind: EffectKind, mu_max: f64) -> f64 {
    match kind.baseline_strength() {
        Some(s) => s,
        None => 0.98 * mu_max,
    }
}

/// More starts for an effect the strength scan cannot see, tried beside the scan's pick (its
/// descriptor's `blind`: where the scan holds the baseline's segment states, which absorb
/// what the effect does). The first stage goes on from the start that ends lowest.
pub fn blind_starts(kind: EffectKind, mu_max: f64, start: SlipStart) -> Vec<f64> {
    let d = kind.descriptor();
    (d.blind)(d.realistic, mu_max, start == SlipStart::HeldRolling)
}

/// The effect's free numbers at `strength`, its extras where their descriptor starts them (the
/// paper's law where an extra shapes it, nothing in progress at the start).
pub fn effect_start(kind: EffectKind, strength: f64) -> Vec<f64> {
    if kind.free_count() == 0 {
        return Vec::new();
    }
    std::iter::once(strength).chain(kind.descriptor().extras.iter().map(|x| x.start)).collect()
}

/// The largest friction coefficient the sliding contact allows for this body (the Painleve
/// limit).
pub fn mu_limit(sh: &Shooting) -> f64 {
    painleve_mu_limit(&sh.spec.base)
}

/// Fits `kind` from the baseline's first stage (its multiple-shooting segments, `levels[0]`)
/// on down to one segment (see the module doc); from the baseline's own whole-run solution
/// `baseline` instead where the candidate, re-anchored at every segment of the first stage,
/// still fits worse than the baseline does over the whole run (then it cannot win: one
/// prediction over the whole run fits no better than many). A stage that fits
/// [`STAGE_CEILING`] times worse than the baseline's with as many segments ends the path.
/// `on_iteration(segments, cost)`.
pub fn fit_candidate(
    ms: &Shooting,
    levels: &[Level],
    baseline: &WholeFit,
    kind: EffectKind,
    on_iteration: &mut dyn FnMut(usize, f64),
) -> Result<WholeFit, LmError> {
    let clock = web_time::Instant::now();
    let join = levels.first().ok_or(LmError::BadStart)?;
    let ceiling = |segments: usize| {
        levels
            .iter()
            .find(|l| l.segments.len() == segments)
            .map_or(f64::INFINITY, |l| STAGE_CEILING * l.cost)
    };
    let mu_max = mu_limit(ms);
    // A first stage for each way the effect's run can begin ([`SlipStart`]); the path goes on
    // with the better. Only the first segment differs, and there the two part at once (a
    // held start rolls for seconds where the other slides).
    let stage = |start: SlipStart, on_iteration: &mut dyn FnMut(usize, f64)| {
        let mut sh = with_budget(with_effect(&with_contact_start(ms, start), kind));
        sh.segments = join.segments.clone();
        first_stage(&sh, join, kind, mu_max, on_iteration).map(|sol| (sol, sh))
    };
    let first = if kind.in_plan().two_starts {
        // The held start on another thread while this one reports the cone start's progress.
        let mut held = None;
        let cone = rayon::in_place_scope(|s| {
            s.spawn(|_| held = Some(stage(SlipStart::HeldRolling, &mut |_, _| {})));
            stage(SlipStart::Cone, on_iteration)
        })?;
        match held.ok_or(LmError::BadStart)?? {
            h if h.0.cost < cone.0.cost => h,
            _ => cone,
        }
    } else {
        stage(SlipStart::Cone, on_iteration)?
    };
    let (first, mut sh) = first;
    let segments = sh.segments.len();
    let mut fit = if segments > 1 && first.cost > baseline.cost {
        let strength = near_baseline_strength(kind, mu_max);
        // An effect without a baseline strength nests the baseline only where the baseline's
        // run never needs what the effect forbids; where it does, its run from the baseline's solution starts far
        // above the ceiling, and a single-shooting fit from there walks blind for seconds to
        // a misfit hundreds of noise levels up: the path ends at its first stage instead.
        if first.cost > ceiling(segments)
            && refit_start_cost(ms, kind, baseline, strength) > STAGE_CEILING * baseline.cost
        {
            stopped_at_stage(&sh, first)?
        } else {
            refit_from(ms, kind, baseline, strength)?
        }
    } else {
        if segments > 1 {
            sh.segments = sh.segments.chunks(2).map(|p| p[0].start..p[p.len() - 1].end).collect();
        }
        let step = if segments > 1 { 2 } else { 1 };
        let states: Vec<StateVec> = first
            .local
            .iter()
            .step_by(step)
            .map(|b| b.as_slice().try_into().unwrap_or([f64::NAN; 8]))
            .collect();
        fit_path(&sh, first.global, &states, &ceiling, on_iteration)?.0
    };
    fit.seconds = clock.elapsed().as_secs_f64();
    Ok(fit)
}

/// The least squares of `kind` at the baseline's first stage (`sh` holds its segments): from
/// the trial strength that fits best at the baseline's states, and from the blind starts.
fn first_stage(
    sh: &Shooting,
    join: &Level,
    kind: EffectKind,
    mu_max: f64,
    on_iteration: &mut dyn FnMut(usize, f64),
) -> Result<lm::LmSolution, LmError> {
    let trials = trial_starts(kind, mu_max);
    let globals: Vec<Vec<f64>> =
        trials.iter().map(|t| join.global.iter().chain(t).copied().collect()).collect();
    let costs: Vec<f64> = globals.iter().map(|g| segment_cost(sh, g, &join.states)).collect();
    let best = (0..trials.len())
        .min_by(|&a, &b| costs[a].total_cmp(&costs[b]))
        .ok_or(LmError::BadStart)?;
    let segments = sh.segments.len();
    let opts = LmOptions {
        max_iterations: LEVEL_ITERATIONS,
        rel_tol: 1e-4,
        covariance: false,
        exact_finish: false,
        ..LmOptions::default()
    };
    let locals: Vec<Vec<f64>> = join.states.iter().map(|y| y.to_vec()).collect();
    let mut starts = vec![globals[best].clone()];
    let start = sh.spec.base.effects.slip_start;
    let picked = trials[best].first().copied();
    for blind in blind_starts(kind, mu_max, start).into_iter().filter(|&m| Some(m) != picked) {
        starts.push(join.global.iter().copied().chain(effect_start(kind, blind)).collect());
    }
    let mut first: Option<lm::LmSolution> = None;
    for g in starts {
        let sol = lm::solve(
            sh,
            g,
            locals.clone(),
            &opts,
            &mut |_, c| on_iteration(segments, c),
            sh.cancel,
        )?;
        if first.as_ref().is_none_or(|f| sol.cost < f.cost) {
            first = Some(sol);
        }
    }
    first.ok_or(LmError::BadStart)
}

/// Integration steps a candidate's fit may spend per frame of the recording (see
/// [`WorkBudget`]): without a cap one trial step into a crawling corner ran for minutes
/// (docs/diagnosis-history.md has what the candidates spend).
pub const CANDIDATE_STEPS_PER_FRAME: u64 = 6_000;

/// `sh` with a budget of its own for one candidate's fit.
pub(super) fn with_budget(mut sh: Shooting<'_>) -> Shooting<'_> {
    let frames = sh.observed.len() as u64;
    sh.budget = Some(Arc::new(WorkBudget::new(CANDIDATE_STEPS_PER_FRAME * frames)));
    sh
}

/// `kind` over the whole run as one segment at `from`'s drag and start state (at `strength`,
/// for a candidate): the problem and its globals.
fn single_segment<'a>(
    ms: &Shooting<'a>,
    kind: EffectKind,
    from: &WholeFit,
    strength: f64,
) -> (Shooting<'a>, Vec<f64>) {
    let start = from.model.effects.slip_start;
    let mut sh = with_budget(with_effect(&with_contact_start(ms, start), kind));
    sh.segments = vec![from.span.clone()];
    let own = from.internal.len()
        - from.kind.free_count()
        - from.also.iter().map(|(k, _)| k.free_count()).sum::<usize>();
    let mut g = from.internal[..own].to_vec();
    g.extend(effect_start(kind, strength));
    (sh, g)
}

/// Refits `kind` over the whole run as one segment from `from`'s drag and start state (at
/// `strength`, for a candidate): the safeguards of the module doc.
pub fn refit_from(
    ms: &Shooting,
    kind: EffectKind,
    from: &WholeFit,
    strength: f64,
) -> Result<WholeFit, LmError> {
    let (sh, g) = single_segment(ms, kind, from, strength);
    fit_whole(&sh, g, &[from.start], &mut |_, _| {})
}

/// Fit `from` over the whole run as one segment without its effect `drop`: from its drag,
/// body, start state and the other effects' numbers.
pub fn refit_without(
    ms: &Shooting,
    from: &WholeFit,
    drop: EffectKind,
) -> Result<WholeFit, LmError> {
    let kinds: Vec<EffectKind> = from.also.iter().map(|(k, _)| *k).chain([from.kind]).collect();
    let own = from.internal.len() - kinds.iter().map(|k| k.free_count()).sum::<usize>();
    let mut global = from.internal[..own].to_vec();
    let (mut keep, mut at) = (Vec::new(), own);
    for k in kinds {
        let n = k.free_count();
        if k != drop {
            keep.push(k);
            global.extend_from_slice(&from.internal[at..at + n]);
        }
        at += n;
    }
    let start = from.model.effects.slip_start;
    let mut sh = with_budget(with_effects(&with_contact_start(ms, start), &keep));
    sh.segments = vec![from.span.clone()];
    fit_whole(&sh, global, &[from.start], &mut |_, _| {})
}

/// Fit `from` over the whole run as one segment with `add` beside its effects, from its drag,
/// body, start state and numbers and `add` at `strength`: the larger model starts where the
/// one it nests ended, so it can only fit better (a pair walked from the baseline's path can
/// end worse than its better effect alone).
pub fn refit_with(
    ms: &Shooting,
    from: &WholeFit,
    add: EffectKind,
    strength: f64,
) -> Result<WholeFit, LmError> {
    let mut kinds = from.kinds();
    kinds.push(add);
    let mut global = from.internal.clone();
    global.extend(effect_start(add, strength));
    let start = from.model.effects.slip_start;
    let mut sh = with_budget(with_effects(&with_contact_start(ms, start), &kinds));
    sh.segments = vec![from.span.clone()];
    fit_whole(&sh, global, &[from.start], &mut |_, _| {})
}

/// The misfit (sum of squares) where [`refit_from`] would start: one run.
pub fn refit_start_cost(ms: &Shooting, kind: EffectKind, from: &WholeFit, strength: f64) -> f64 {
    let (sh, g) = single_segment(ms, kind, from, strength);
    segment_cost(&sh, &g, &[from.start])
}

/// The baseline's path from the multiple-shooting fit (`ms`, its segment `states`).
pub fn fit_baseline(
    ms: &Shooting,
    states: &[StateVec],
    on_iteration: &mut dyn FnMut(usize, f64),
) -> Result<(WholeFit, Vec<Level>), LmError> {
    let sh = with_effect(ms, EffectKind::BASELINE);
    let g = sh.spec.to_internal(&sh.spec.initial_values());
    fit_path(&sh, g, states, &no_ceiling, on_iteration)
}

/// The candidates along the baseline's path (`baseline`, `levels`), fitted in parallel, and the
/// baseline with the safeguards applied. `progress(kind, segments, cost)` as each path goes
/// on; `done(kind)` when one is fitted.
pub fn fit_candidates(
    ms: &Shooting,
    baseline: WholeFit,
    levels: &[Level],
    kinds: &[EffectKind],
    progress: &(dyn Fn(EffectKind, usize, f64) + Sync),
    done: &(dyn Fn(EffectKind) + Sync),
) -> Result<(WholeFit, Vec<(EffectKind, Result<WholeFit, LmError>)>), LmError> {
    // The slowest first (sliding runs cost most), so that it does not finish alone.
    let mut order: Vec<EffectKind> = kinds.iter().copied().filter(|&k| !k.is_baseline()).collect();
    order.sort_by_key(|&k| !k.in_plan().costly);
    let mut candidates: Vec<(EffectKind, Result<WholeFit, LmError>)> = order
        .par_iter()
        .map(|&k| {
            let r = fit_candidate(ms, levels, &baseline, k, &mut |segments, cost| {
                progress(k, segments, cost)
            });
            done(k);
            (k, r)
        })
        .collect();
    if candidates.iter().any(|(_, r)| matches!(r, Err(LmError::Cancelled))) {
        return Err(LmError::Cancelled);
    }
    // The baseline from the best candidate's drag and start.
    let mut baseline = baseline;
    let best = candidates
        .iter()
        .filter_map(|(_, r)| r.as_ref().ok())
        .min_by(|a, b| a.cost.total_cmp(&b.cost));
    if let Some(best) = best
        && best.cost < baseline.cost
    {
        let again = baseline_from(ms, best)?;
        if again.cost < baseline.cost {
            baseline = again;
        }
    }
    // A candidate that ended worse than the model it contains: again from the baseline. Not
    // where that start misses by more than the candidate's own end: an effect without a
    // baseline strength never quite is the baseline, so at
    // the baseline's solution it can miss by thousands of times more, and the refit crawled
    // for 12 s from there to end worse than before (a concealed air drag on the travel).
    let mu_max = mu_limit(ms);
    candidates.par_iter_mut().for_each(|(k, r)| {
        let worse = r.as_ref().map_or(true, |w| w.cost > baseline.cost);
        if !worse {
            return;
        }
        let strength = near_baseline_strength(*k, mu_max);
        if let Ok(old) = r.as_ref()
            && !(refit_start_cost(ms, *k, &baseline, strength) < old.cost)
        {
            return;
        }
        let before = r.as_ref().map_or(0.0, |w| w.seconds);
        if let Ok(mut w) = refit_from(ms, *k, &baseline, strength) {
            match r {
                Ok(old) if old.cost <= w.cost => old.seconds += w.seconds,
                _ => {
                    w.seconds += before;
                    *r = Ok(w);
                }
            }
        }
    });
    Ok((baseline, candidates))
}

/// How many times [`baseline_from`] fits the baseline again from where its last fit ended.
const BASELINE_REFITS: usize = 3;

/// The baseline over the whole run from `from`'s drag and start state (a candidate's), fitted
/// again from where the fit ended while it took as many steps as its fresh Jacobians allow
/// (then it may have run out of them) and the refit still lowers its misfit by more than the
/// last stage's stopping gain: from a candidate's solution far from the baseline's (a slide's
/// drag and start), one fit can spend its iterations on the way down, and "before" would then
/// be a baseline short of its best. A fit that stopped sooner has settled: no refit.
fn baseline_from(ms: &Shooting, from: &WholeFit) -> Result<WholeFit, LmError> {
    let mut fit = refit_from(ms, EffectKind::BASELINE, from, 0.0)?;
    for _ in 0..BASELINE_REFITS {
        if fit.iterations < FINAL_ITERATIONS {
            break;
        }
        let again = refit_from(ms, EffectKind::BASELINE, &fit, 0.0)?;
        let gained = again.cost < (1.0 - FINAL_REL_TOL) * fit.cost;
        if again.cost < fit.cost {
            fit = WholeFit { seconds: fit.seconds + again.seconds, ..again };
        }
        if !gained {
            break;
        }
    }
    Ok(fit)
}

/// `ms` with runs whose contact begins as `start` says (an effect with two starts only; the
/// others ignore it).
pub fn with_contact_start<'a>(ms: &Shooting<'a>, start: SlipStart) -> Shooting<'a> {
    let mut sh = ms.clone();
    sh.spec.base.effects.slip_start = start;
    sh
}

/// A pair of the forward selection: `first` (fitted alone as `first_fit`) and `second` (fitted
/// alone as `second_fit`) together, on the baseline's path like a single candidate (see
/// [`fit_candidate`]): from the baseline's first stage, with `first` at its own fitted strength
/// and `second` at the best of its alone-fitted strength and its trial strengths, down to one
/// segment. A stage that fits [`STAGE_CEILING`] times worse than the baseline's ends the path.
///
/// Where `first` has an extra that shapes its law (its descriptor's `InPlan::shape`) and fitted
/// it alone away from the paper's law, the pair is also walked the other way round, `second`
/// leading and `first` from its trial starts at the paper's law, and the better kept: alone,
/// that shape can imitate part of the second effect, a valley the pair does not leave
/// (docs/diagnosis.md has the case).
pub fn fit_pair(
    ms: &Shooting,
    levels: &[Level],
    first_fit: &WholeFit,
    second_fit: &WholeFit,
    on_iteration: &mut dyn FnMut(usize, f64),
) -> Result<WholeFit, LmError> {
    let clock = web_time::Instant::now();
    let shaped = shaped(first_fit);
    let mut fit = pair_path(ms, levels, first_fit, second_fit, on_iteration);
    if shaped {
        let other = pair_path(ms, levels, second_fit, first_fit, &mut |_, _| {});
        fit = match (fit, other) {
            (Err(LmError::Cancelled), _) | (_, Err(LmError::Cancelled)) => Err(LmError::Cancelled),
            (Ok(a), Ok(b)) => Ok(if b.cost < a.cost { b } else { a }),
            (Err(_), b) => b,
            (a, Err(_)) => a,
        };
    }
    let mut fit = fit?;
    fit.seconds = clock.elapsed().as_secs_f64();
    Ok(fit)
}

/// [`fit_pair`] in one order: `lead` at its own numbers, `other` from the best of its own and
/// its trial strengths at the baseline's first stage.
fn pair_path(
    ms: &Shooting,
    levels: &[Level],
    lead_fit: &WholeFit,
    other_fit: &WholeFit,
    on_iteration: &mut dyn FnMut(usize, f64),
) -> Result<WholeFit, LmError> {
    let (first, second) = (lead_fit.kind, other_fit.kind);
    let join = levels.first().ok_or(LmError::BadStart)?;
    let ceiling = |segments: usize| {
        levels
            .iter()
            .find(|l| l.segments.len() == segments)
            .map_or(f64::INFINITY, |l| STAGE_CEILING * l.cost)
    };
    let mu_max = mu_limit(ms);
    let two = [lead_fit, other_fit].into_iter().find(|w| w.kind.in_plan().two_starts);
    let start = two.map_or(SlipStart::Cone, |w| w.model.effects.slip_start);
    let mut sh = with_budget(with_effects(&with_contact_start(ms, start), &[first, second]));
    sh.segments = join.segments.clone();
    let own = |w: &WholeFit| w.internal[w.internal.len() - w.kind.free_count()..].to_vec();
    let lead = own(lead_fit);
    let mut trials: Vec<Vec<f64>> = vec![own(other_fit)];
    trials.extend(trial_starts(second, mu_max));
    let globals: Vec<Vec<f64>> = trials
        .iter()
        .map(|t| join.global.iter().chain(&lead).chain(t).copied().collect())
        .collect();
    let costs: Vec<f64> = globals.iter().map(|g| segment_cost(&sh, g, &join.states)).collect();
    let best = (0..globals.len())
        .min_by(|&a, &b| costs[a].total_cmp(&costs[b]))
        .ok_or(LmError::BadStart)?;
    Ok(fit_path(&sh, globals[best].clone(), &join.states, &ceiling, on_iteration)?.0)
}

/// Whether fit `w` holds its effect's shaping extra (`InPlan::shape`) away from where a fit
/// starts it (the paper's law).
fn shaped(w: &WholeFit) -> bool {
    let d = w.kind.descriptor();
    d.plan.shape.is_some_and(|i| {
        let start = d.extras.get(i).map_or(0.0, |x| x.start);
        extras_of(&w.extras, w.kind).get(i).is_some_and(|(v, _)| *v != start)
    })
}
