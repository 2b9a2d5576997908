//! The pairs of the forward selection: the best single candidates paired on the baseline's
//! path ([`pairs_stage`]), and each other effect added to the best one's solution
//! ([`added_to_best`]). Both run as a queue, most promising first on every thread, until one
//! settles the recording (`in_order.rs`).

use super::again::{Again, walk_best_pair_again};
use super::candidates::{fit_pair, refit_with};
use super::in_order::in_order_until;
use super::options::DiagnoseError;
use super::progress::Reporter;
use super::result::Candidate;
use super::rules::{MIN_EXPLAINED, Reach, explained_share, reached};
use super::whole::{Level, WholeFit};
use crate::analysis::fit::lm::LmError;
use crate::analysis::fit::shooting::Shooting;
use crate::physics::effects::EffectKind;
use std::sync::Mutex;
use std::sync::atomic::AtomicBool;

/// A pair of the forward selection: its two effects and its fit.
pub(super) type PairFit = (EffectKind, EffectKind, Result<WholeFit, LmError>);

/// The pairs fitted, as their models.
fn models(pair_fits: &[PairFit]) -> impl Iterator<Item = &WholeFit> {
    pair_fits.iter().filter_map(|(_, _, r)| r.as_ref().ok())
}

/// How many of the best single candidates (by BIC, better than the baseline) the forward
/// selection pairs with each other. Pairs among the best few and not only with the one named:
/// where two effects are in a recording, the one named alone is often a third that imitates
/// both; and four, not three, because a camera candidate can imitate part of a physical effect
/// and push one of the pair out of the best three.
const PAIRED: usize = 4;

/// How many of the best single candidates are each paired with every other candidate, also
/// those that did nothing alone. An effect can be invisible alone where another is at work:
/// the baseline's drag absorbs it, or it only shows once the other is in the model. Three, not
/// one, because the best alone can itself be the imitator of a pair's member, and a pair's
/// member alone can end in a side valley that ranks it third (docs/diagnosis.md).
const LEADS: usize = 3;

/// The pairs of the forward selection, each fitted on the baseline's path: every pair among
/// the [`PAIRED`] best single candidates, and each of the [`LEADS`] best with every other
/// candidate (a costly one only where it improved on the baseline alone: its runs cost most,
/// and what the recording shows of it moves the misfit alone by far); the second and third
/// leads' pairs
/// only where none of the others reaches the noise. Fitted most promising first, on every
/// thread, until one settles the recording ([`in_order_until`]). Returns the pairs fitted and
/// those walked again.
pub(super) fn pairs_stage(
    again: &Again,
    ms: &Shooting,
    levels: &[Level],
    ranked: &[(Candidate, Option<&WholeFit>)],
    noise_px: f64,
    progress: &Reporter,
) -> Result<(Vec<PairFit>, Vec<Vec<EffectKind>>), DiagnoseError> {
    let fitted: Vec<(&Candidate, &WholeFit)> = ranked
        .iter()
        .filter(|(c, _)| !c.effect.is_baseline())
        .filter(|(c, _)| !c.effect.in_plan().costly || c.delta_score < 0.0)
        .filter_map(|(c, w)| w.map(|w| (c, w)))
        .collect();
    let rounds = pair_rounds(&fitted);
    let best_single_px = fitted.iter().map(|(_, w)| w.rms_px()).fold(f64::INFINITY, f64::min);
    let mut out: Vec<PairFit> = Vec::new();
    let walked: Mutex<Vec<Vec<EffectKind>>> = Mutex::new(Vec::new());
    for (n, round) in rounds.iter().enumerate() {
        if reached(models(&out), Reach::Consistent, noise_px) || round.is_empty() {
            break;
        }
        progress.pairs_planned(n, round.len());
        let one = |&(i, j): &(usize, usize), stop: &AtomicBool| -> PairFit {
            let (a, b) = (fitted[i].1, fitted[j].1);
            let ms = &ms.stopped_by(stop);
            let mut fit = fit_pair(ms, levels, a, b, &mut |_, _| {});
            // A pair that explains most of what the best effect alone leaves is walked again
            // at once: a right pair's first walk often stops short of the noise, and walked
            // it settles the recording, so the pairs after it are spared.
            if fit.as_ref().is_ok_and(|p| {
                explained_share(best_single_px, p.rms_px(), noise_px) >= MIN_EXPLAINED
            }) {
                let mut one = [(a.kind, b.kind, fit)];
                let walk = walk_best_pair_again(again, ms, levels, &mut one, &|w| w.cost, noise_px);
                let [(_, _, walked_fit)] = one;
                fit = walked_fit;
                match (walk, &fit) {
                    (Ok(()), Ok(p)) => {
                        walked.lock().unwrap_or_else(|e| e.into_inner()).push(p.kinds())
                    }
                    _ => fit = Err(LmError::Cancelled),
                }
            }
            let rms = fit.as_ref().map_or(f64::NAN, |w| w.rms_px());
            progress.pair_fitted(a.kind, b.kind, rms);
            (a.kind, b.kind, fit)
        };
        let is_settled =
            |(_, _, r): &PairFit| r.as_ref().is_ok_and(|w| Reach::Settled.by(w.rms_px(), noise_px));
        out.extend(in_order_until(round, &one, &is_settled, ms.cancel));
        if ms.cancel.load(std::sync::atomic::Ordering::Relaxed) {
            return Err(DiagnoseError::Cancelled);
        }
        if reached(models(&out), Reach::Settled, noise_px) {
            break;
        }
    }
    let walked = walked.into_inner().unwrap_or_else(|e| e.into_inner());
    Ok((out, walked))
}

/// The pairs [`pairs_stage`] fits, as indices into `fitted`, in two rounds, most promising
/// first: the best candidate with every other and the pairs among the best few first; the
/// other leads only where no pair of the first round reaches the noise (a pair that does
/// leaves nothing for another to explain).
fn pair_rounds(fitted: &[(&Candidate, &WholeFit)]) -> [Vec<(usize, usize)>; 2] {
    let improving: Vec<usize> = (0..fitted.len())
        .filter(|&i| fitted[i].0.delta_score < 0.0 && fitted[i].1.stopped_at.is_none())
        .collect();
    let mut rounds: [Vec<(usize, usize)>; 2] = [Vec::new(), Vec::new()];
    let mut add = |round: usize, i: usize, j: usize| {
        let (i, j) = (i.min(j), i.max(j));
        // Two camera effects are a pair too: a real camera has both.
        if i != j && !rounds.iter().any(|r| r.contains(&(i, j))) {
            rounds[round].push((i, j));
        }
    };
    let best: Vec<usize> = improving.iter().copied().take(PAIRED).collect();
    for (n, &i) in best.iter().enumerate() {
        for &j in &best[n + 1..] {
            add(0, i, j);
        }
    }
    for (n, &i) in improving.iter().take(LEADS).enumerate() {
        for j in 0..fitted.len() {
            add(n.min(1), i, j);
        }
    }
    // Most promising first: by the two effects' BIC gains alone, summed (stable for ties).
    let promise = |&(i, j): &(usize, usize)| fitted[i].0.delta_score + fitted[j].0.delta_score;
    for round in &mut rounds {
        round.sort_by(|a, b| promise(a).total_cmp(&promise(b)));
    }
    rounds
}

/// Forward selection from where the best single candidate ended: each of `others` (but the
/// best itself) added at its baseline strength to that candidate's solution and fitted over
/// the whole run ([`refit_with`]), on every thread until one settles the recording. The pairs
/// of [`pairs_stage`] are walked from the baseline's path, and where the best effect alone
/// sits in a valley of its own they can end worse than it. A fit that beats the same pair
/// fitted before takes its place.
pub(super) fn added_to_best(
    ms: &Shooting,
    ranked: &[(Candidate, Option<&WholeFit>)],
    others: &[EffectKind],
    pair_fits: &mut Vec<PairFit>,
    noise_px: f64,
) -> Result<(), DiagnoseError> {
    let Some(lead) = ranked
        .iter()
        .filter(|(c, _)| !c.effect.is_baseline() && c.delta_score < 0.0)
        .find_map(|(_, w)| w.filter(|w| w.stopped_at.is_none()))
    else {
        return Ok(());
    };
    let added: Vec<EffectKind> = others.iter().copied().filter(|&k| k != lead.kind).collect();
    let one = |&k: &EffectKind, stop: &AtomicBool| {
        let zero = k.baseline_strength().unwrap_or(0.0);
        (k, refit_with(&ms.stopped_by(stop), lead, k, zero))
    };
    let is_settled = |(_, r): &(EffectKind, Result<WholeFit, LmError>)| {
        r.as_ref().is_ok_and(|w| Reach::Settled.by(w.rms_px(), noise_px))
    };
    let fits = in_order_until(&added, &one, &is_settled, ms.cancel);
    if ms.cancel.load(std::sync::atomic::Ordering::Relaxed) {
        return Err(DiagnoseError::Cancelled);
    }
    for (k, fit) in fits {
        let Ok(fit) = fit else { continue };
        let same = |(a, b, _): &PairFit| (*a, *b) == (lead.kind, k) || (*a, *b) == (k, lead.kind);
        match pair_fits.iter_mut().find(|p| same(p)) {
            Some((_, _, r)) if r.as_ref().is_ok_and(|w| w.cost <= fit.cost) => {}
            Some(p) => *p = (lead.kind, k, Ok(fit)),
            None => pair_fits.push((lead.kind, k, Ok(fit))),
        }
    }
    Ok(())
}
