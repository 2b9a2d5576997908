//! The decision and the forward selection: which single effect, or pair, is named. The
//! selection is the plan's second phase ([`Choosing`]; its passes are below, their order and
//! conditions in `plan.rs`); the decision before it ([`decide`]) and the naming after it
//! ([`Selection::name`]) use one test of "worth its numbers" ([`Selection::worth`]).

use super::again::{
    Again, best_pair, effect_through_camera, effects_through_camera, walk_best_pair_again,
};
use super::candidates::refit_without;
use super::noise_correlation::residual_dependence;
use super::options::DiagnoseError;
use super::pairs::{self, PairFit, pairs_stage};
use super::progress::Reporter;
use super::ranking::{others_through_camera, through_seen_kinds};
use super::result::{Candidate, Finding, NamedShare, PairCandidate, Partial};
use super::rules::{MIN_EXPLAINED, Reach, bic, explained_share, explains};
use super::seen_camera::FoundCamera;
use super::whole::{Level, WholeFit};
use crate::analysis::fit::lm::LmError;
use crate::analysis::fit::shooting::Shooting;
use crate::physics::effects::EffectKind;

/// What the forward selection works with: the problem, the baseline's path and solution, the
/// noise and the evidence asked, the progress bar (the cancel flag travels with `ms`).
pub(super) struct Selection<'a> {
    pub(super) again: &'a Again<'a>,
    pub(super) ms: &'a Shooting<'a>,
    pub(super) levels: &'a [Level],
    pub(super) baseline: &'a WholeFit,
    pub(super) noise_px: f64,
    /// The noise's dependence from frame to frame (`Noise::dependence`), for the BIC.
    pub(super) dependence: f64,
    pub(super) evidence: f64,
    pub(super) progress: &'a Reporter<'a>,
}

/// The pairs (and larger models) fitted so far, and those walked again.
#[derive(Default)]
pub(super) struct Pairs {
    pub(super) fits: Vec<PairFit>,
    walked: Vec<Vec<EffectKind>>,
}

impl Pairs {
    /// Fits of several effects, each as a pair of its first and last effect.
    fn extend(&mut self, fits: Vec<WholeFit>) {
        for p in fits {
            let first = p.also.first().map_or(p.kind, |x| x.0);
            self.fits.push((first, p.kind, Ok(p)));
        }
    }
}

/// What the plan's selection phase works on: the model chosen by the decision, the ranked
/// candidates, and the larger models fitted so far.
pub(super) struct Choosing<'a> {
    pub(super) sel: &'a Selection<'a>,
    ranked: &'a [(Candidate, Option<&'a WholeFit>)],
    chosen: &'a WholeFit,
    pub(super) pairs: Pairs,
}

/// The finding, the model that stands for it (`None`: the baseline), each named effect's share
/// of the improvement and the pairs tried.
pub(super) type Selected = (Finding, Option<WholeFit>, Vec<NamedShare>, Vec<PairCandidate>);

/// The finding, the model that stands for it and that model fitted without each of its
/// effects (empty for one effect: without it, it is the baseline).
type Named = (Finding, Option<WholeFit>, Vec<WholeFit>);

/// The decision ([`decide`]), then forward selection (the plan's selection phase): where the
/// named effect, or no single one, leaves the misfit beyond the noise, larger models of the
/// candidates; one is named only where it beats every effect alone ([`Selection::name`]).
/// `run_plan` runs the plan's selection phase (`plan::run`, given by the caller: the plan
/// lists this file's passes, so this file does not name it).
pub(super) fn forward_selection(
    sel: &Selection,
    ranked: &mut [(Candidate, Option<&WholeFit>)],
    run_plan: impl FnOnce(&mut Choosing) -> Result<(), DiagnoseError>,
) -> Result<Selected, DiagnoseError> {
    let (finding, chosen) = decide(sel, ranked);
    let chosen = chosen.unwrap_or(sel.baseline);
    let mut work = Choosing { sel, ranked, chosen, pairs: Pairs::default() };
    run_plan(&mut work)?;
    let pairs = work.pairs;
    let trimmed = sel.trimmed(&pairs)?;
    let best_pair = trimmed.as_ref().or_else(|| sel.best_of(&pairs));
    let (finding, chosen, without) = sel.name(finding, chosen, best_pair, ranked)?;
    let shares = match (&finding, &chosen) {
        (Finding::Named(_), Some(m)) => sel.shares(m, &without, ranked),
        _ => Vec::new(),
    };
    Ok((finding, chosen, shares, sel.pair_candidates(&pairs)))
}

impl Selection<'_> {
    fn score(&self, w: &WholeFit) -> f64 {
        bic(w.cost, self.baseline.residual_count, w.parameter_count, self.dependence)
    }

    /// Whether model `with` is worth its numbers over `without` (the same model with fewer
    /// effects, or the model it would replace): the one test the decision and the naming make.
    /// A BIC test, its BIC below `without`'s by the evidence asked, on the residuals that count
    /// as independent: the noise's dependence from frame to frame, or that of `with`'s own
    /// residual where larger ([`residual_dependence`]: a tracker's correlated noise that the
    /// noise's test did not take for one, or motion the model misses). On white residuals the
    /// two are the same; where the residual is correlated, a number that takes up a little of it
    /// would otherwise buy many BIC points for nothing the recording can tell (docs/diagnosis.md,
    /// "Parsimony").
    pub(super) fn worth(&self, with: &WholeFit, without: &WholeFit) -> bool {
        let dependence = self.dependence.max(self.residual_dependence(with));
        let n = self.baseline.residual_count;
        let score = |w: &WholeFit| bic(w.cost, n, w.parameter_count, dependence);
        score(with) < score(without) - self.evidence
    }

    /// The dependence of `w`'s residual from frame to frame (1 where it cannot be run).
    fn residual_dependence(&self, w: &WholeFit) -> f64 {
        let Some(pred) = w.marks(self.ms) else { return 1.0 };
        residual_dependence(self.ms.observed, w.span.start, &pred)
    }

    /// Each effect of `named`'s share of its improvement on the baseline: how much of the cost
    /// it removes comes back without that effect. Without it is the best of the models fitted
    /// that hold every other effect of `named` and not it: `named` refitted without it
    /// (`without`), the single candidate of the other effect, the baseline (each nests the
    /// baseline, so none ends worse than it).
    fn shares(
        &self,
        named: &WholeFit,
        without: &[WholeFit],
        ranked: &[(Candidate, Option<&WholeFit>)],
    ) -> Vec<NamedShare> {
        let gain = self.baseline.cost - named.cost;
        let kinds = named.kinds();
        let share_of = |effect: EffectKind| {
            let others: Vec<EffectKind> = kinds.iter().copied().filter(|&k| k != effect).collect();
            let holds_others = |w: &WholeFit| {
                let held = w.kinds();
                !held.contains(&effect) && others.iter().all(|k| held.contains(k))
            };
            let singles = ranked.iter().filter_map(|(_, w)| *w);
            let less = without
                .iter()
                .chain(singles.filter(|w| others.len() == 1 && w.kind == others[0]))
                .filter(|w| holds_others(w))
                .chain([self.baseline])
                .min_by(|a, b| a.cost.total_cmp(&b.cost))
                .unwrap_or(self.baseline);
            let share =
                if gain > 0.0 { ((less.cost - named.cost) / gain).clamp(0.0, 1.0) } else { 0.0 };
            NamedShare { effect, share, rms_without_px: less.rms_px() }
        };
        kinds.iter().map(|&k| share_of(k)).collect()
    }

    /// The best pair fitted.
    fn best_of<'p>(&self, pairs: &'p Pairs) -> Option<&'p WholeFit> {
        pairs
            .fits
            .iter()
            .filter_map(|(_, _, r)| r.as_ref().ok())
            .min_by(|a, b| self.score(a).total_cmp(&self.score(b)))
    }

    /// A model of three effects (an effect through a camera of two the segments see) is named
    /// only where each is worth its numbers: else the best of it with one left out stands for
    /// it.
    fn trimmed(&self, pairs: &Pairs) -> Result<Option<WholeFit>, DiagnoseError> {
        match self.best_of(pairs) {
            Some(p) if p.also.len() > 1 => {
                let fewer = drop_each(self.ms, p)?;
                Ok(fewer
                    .into_iter()
                    .min_by(|a, b| self.score(a).total_cmp(&self.score(b)))
                    .filter(|r| !self.worth(p, r)))
            }
            _ => Ok(None),
        }
    }

    /// The finding after the pairs: the best pair where it beats the model chosen and neither
    /// of its effects alone does as well (each fitted alone from the pair's solution: a single
    /// fit can end in a side valley the pair's extra number lets the least squares leave); that
    /// effect alone where it does; else the pair as the better partial answer where it removes
    /// at least half of what the best single one leaves beyond the noise.
    /// Returns the finding, the model that stands for it (`None`: the baseline) and, where that
    /// is a larger model, it fitted without each of its effects.
    fn name(
        &self,
        mut finding: Finding,
        chosen: &WholeFit,
        best_pair: Option<&WholeFit>,
        ranked: &mut [(Candidate, Option<&WholeFit>)],
    ) -> Result<Named, DiagnoseError> {
        let noise_px = self.noise_px;
        let none_score = self.score(self.baseline);
        let pair_wins = best_pair.is_some_and(|p| {
            self.worth(p, chosen) && explains(chosen.rms_px(), p.rms_px(), noise_px)
        });
        let alone = match best_pair.filter(|_| pair_wins) {
            Some(p) => drop_each(self.ms, p)?,
            None => Vec::new(),
        };
        let best_alone = alone.iter().min_by(|a, b| self.score(a).total_cmp(&self.score(b)));
        let alone_enough = best_alone.zip(best_pair).is_some_and(|(a, p)| !self.worth(p, a));
        if let (Some(p), false) = (best_pair.filter(|_| pair_wins), alone_enough) {
            let named = p.also.iter().map(|(k, _)| *k).chain([p.kind]).collect();
            return Ok((Finding::Named(named), Some(p.clone()), alone));
        }
        if let Some(a) = best_alone.filter(|a| {
            alone_enough
                && self.score(a) < self.score(chosen)
                && self.worth(a, self.baseline)
                && explains(self.baseline.rms_px(), a.rms_px(), noise_px)
        }) {
            if let Some((c, _)) = ranked.iter_mut().find(|(c, _)| c.effect == a.kind) {
                (c.rms_px, c.score, c.delta_score, c.strength) =
                    (a.rms_px(), self.score(a), self.score(a) - none_score, a.strength);
            }
            return Ok((Finding::Named(vec![a.kind]), Some(a.clone()), Vec::new()));
        }
        if let (Finding::Unexplained { partial }, Some(p)) = (&mut finding, best_pair) {
            let share = explained_share(self.baseline.rms_px(), p.rms_px(), noise_px);
            if partial
                .as_ref()
                .is_none_or(|q| explained_share(q.rms_px, p.rms_px(), noise_px) >= MIN_EXPLAINED)
            {
                *partial = Some(Partial {
                    effects: p.also.iter().map(|(k, _)| *k).chain([p.kind]).collect(),
                    share,
                    rms_px: p.rms_px(),
                });
            }
        }
        let model = (!std::ptr::eq(chosen, self.baseline)).then(|| chosen.clone());
        Ok((finding, model, Vec::new()))
    }

    /// The pairs tried, as the diagnosis reports them, best first.
    fn pair_candidates(&self, pairs: &Pairs) -> Vec<PairCandidate> {
        let none_score = self.score(self.baseline);
        let mut v: Vec<PairCandidate> = pairs
            .fits
            .iter()
            .map(|(a, b, r)| match r {
                // The fit's own order (a pair fitted again may hold its effects the other way).
                Ok(w) => PairCandidate {
                    first: w.also.first().map_or(*a, |x| x.0),
                    second: w.kind,
                    rms_px: w.rms_px(),
                    delta_score: self.score(w) - none_score,
                    strengths: [
                        w.also.first().map_or((f64::NAN, f64::NAN), |x| x.1),
                        w.strength.unwrap_or((f64::NAN, f64::NAN)),
                    ],
                    error: None,
                    seconds: w.seconds,
                },
                Err(e) => PairCandidate {
                    first: *a,
                    second: *b,
                    rms_px: f64::NAN,
                    delta_score: f64::INFINITY,
                    strengths: [(f64::NAN, f64::NAN); 2],
                    error: Some(e.to_string()),
                    seconds: 0.0,
                },
            })
            .collect();
        v.sort_by(|a, b| a.delta_score.total_cmp(&b.delta_score));
        v
    }
}

/// The effect of `kind` with the camera left to the camera fitted: `None` for a camera
/// effect (the camera alone, fitted through the camera found).
fn camera_free(kind: EffectKind) -> EffectKind {
    if kind.is_camera() { EffectKind::BASELINE } else { kind }
}

impl<'a> Choosing<'a> {
    /// Whether the model chosen still misses beyond the noise's margin: then larger models
    /// are fitted.
    fn misses(&self) -> bool {
        !Reach::Consistent.by(self.chosen.rms_px(), self.sel.noise_px)
    }

    fn seen(&self) -> Option<&'a FoundCamera> {
        self.sel.again.seen
    }

    /// Each of `kinds` beside the camera effects of `camera` ([`effects_through_camera`]).
    fn extend_through(
        &mut self,
        camera: &FoundCamera,
        kinds: &[EffectKind],
    ) -> Result<(), DiagnoseError> {
        let s = self.sel;
        self.pairs.extend(effects_through_camera(s.again, s.ms, camera, kinds, s.noise_px)?);
        Ok(())
    }
}

/// Where the model chosen misses beyond the noise's margin.
pub(super) fn misses(w: &Choosing) -> bool {
    w.misses()
}

/// Where it misses and the segments see a camera.
pub(super) fn misses_with_seen(w: &Choosing) -> bool {
    w.misses() && w.seen().is_some()
}

/// Every effect through the camera the segments see: the chosen one with the camera free,
/// then the others, most promising first ([`through_seen_kinds`]). A pair walked from the
/// baseline's path starts from segments fitted through the wrong camera.
pub(super) fn through_seen(w: &mut Choosing) -> Result<(), DiagnoseError> {
    let Some(seen) = w.seen() else { return Ok(()) };
    let kinds: Vec<EffectKind> =
        [camera_free(w.chosen.kind)].into_iter().chain(through_seen_kinds(w.ranked)).collect();
    w.extend_through(seen, &kinds)
}

/// The pairs of the best candidates on the baseline's path ([`pairs_stage`]).
pub(super) fn pairs(w: &mut Choosing) -> Result<(), DiagnoseError> {
    let s = w.sel;
    let (more, walked) = pairs_stage(s.again, s.ms, s.levels, w.ranked, s.noise_px, s.progress)?;
    w.pairs.fits.extend(more);
    w.pairs.walked = walked;
    Ok(())
}

/// Each other effect (not a costly one) added to the best one's solution
/// ([`pairs::added_to_best`]).
pub(super) fn added_to_best(w: &mut Choosing) -> Result<(), DiagnoseError> {
    let others = others_through_camera(w.ranked, false);
    pairs::added_to_best(w.sel.ms, w.ranked, &others, &mut w.pairs.fits, w.sel.noise_px)
}

/// Where the chosen model ends within the noise's margin and the segments see a camera it
/// lacks (part of): tried even then (a weak camera effect beside a physical one, or beside
/// the other camera effect).
pub(super) fn seen_lacked(w: &Choosing) -> bool {
    let held = w.chosen.kinds();
    !w.misses() && w.seen().is_some_and(|seen| seen.numbers.iter().any(|(k, _)| !held.contains(k)))
}

/// The chosen model's effect fitted through the camera the segments see, the camera then free
/// beside it, as a pair.
pub(super) fn chosen_through_seen(w: &mut Choosing) -> Result<(), DiagnoseError> {
    let Some(seen) = w.seen() else { return Ok(()) };
    w.extend_through(seen, &[camera_free(w.chosen.kind)])
}

/// The best single candidate's fit where it is a camera effect that improved on the baseline.
fn camera_lead<'a>(ranked: &[(Candidate, Option<&'a WholeFit>)]) -> Option<&'a WholeFit> {
    let (lead, w) = ranked.iter().find(|(c, _)| !c.effect.is_baseline())?;
    (lead.effect.is_camera() && lead.delta_score < 0.0).then_some(*w).flatten()
}

/// The costly candidates offered that did not improve on the baseline alone.
fn costly_not_improved(ranked: &[(Candidate, Option<&WholeFit>)]) -> Vec<EffectKind> {
    let costly = ranked.iter().filter(|(c, _)| c.effect.in_plan().costly && c.delta_score >= 0.0);
    costly.map(|(c, _)| c.effect).collect()
}

/// Where it misses, the segments see no camera, pairs were fitted, a costly candidate did not
/// improve alone, and a camera effect leads that explains at least [`MIN_EXPLAINED`] of the
/// baseline's excess. A camera that explains less imitates a little of some other effect, and
/// a costly effect through it, the slowest fit there is, buys nothing (docs/diagnosis.md).
pub(super) fn camera_leads_without_costly(w: &Choosing) -> bool {
    let (before, noise_px) = (w.sel.baseline.rms_px(), w.sel.noise_px);
    w.misses()
        && w.seen().is_none()
        && !w.pairs.fits.is_empty()
        && !costly_not_improved(w.ranked).is_empty()
        && camera_lead(w.ranked)
            .is_some_and(|lead| explained_share(before, lead.rms_px(), noise_px) >= MIN_EXPLAINED)
}

/// Each costly candidate that did not improve alone, fitted through the camera the leading
/// camera effect found ([`effect_through_camera`]).
pub(super) fn costly_through_lead(w: &mut Choosing) -> Result<(), DiagnoseError> {
    let Some(lead) = camera_lead(w.ranked) else { return Ok(()) };
    let (s, found) = (w.sel, FoundCamera::of(lead));
    for kind in costly_not_improved(w.ranked) {
        if let Some(p) = effect_through_camera(s.again, s.ms, &found, kind, s.noise_px)? {
            w.pairs.fits.push((lead.kind, kind, Ok(p)));
        }
    }
    Ok(())
}

/// Where it misses, pairs were fitted and a camera effect leads (the plan skips it where a
/// pair has come within the noise's margin).
pub(super) fn camera_leads_missing(w: &Choosing) -> bool {
    w.misses() && !w.pairs.fits.is_empty() && camera_lead(w.ranked).is_some()
}

/// Every other candidate (the other camera effect among them) through the camera the leading
/// camera effect found: a weak strength can stay in the baseline's valley through the
/// baseline's camera.
pub(super) fn others_through_lead(w: &mut Choosing) -> Result<(), DiagnoseError> {
    let Some(lead) = camera_lead(w.ranked) else { return Ok(()) };
    let kinds = others_through_camera(w.ranked, w.seen().is_some());
    w.extend_through(&FoundCamera::of(lead), &kinds)
}

/// Where the best pair has not settled the recording and was not walked again by the pairs.
pub(super) fn best_pair_unwalked(w: &Choosing) -> bool {
    w.sel.best_of(&w.pairs).is_some_and(|p| {
        !w.pairs.walked.contains(&p.kinds()) && !Reach::Settled.by(p.rms_px(), w.sel.noise_px)
    })
}

/// The best pair walked down its path again ([`walk_best_pair_again`]).
pub(super) fn walk_best_pair(w: &mut Choosing) -> Result<(), DiagnoseError> {
    let s = w.sel;
    let score = |x: &WholeFit| s.score(x);
    walk_best_pair_again(s.again, s.ms, s.levels, &mut w.pairs.fits, &score, s.noise_px)
}

/// Where the best pair holds a costly effect beside a camera effect and still misses beyond the
/// noise's margin.
pub(super) fn best_pair_costly_with_camera(w: &Choosing) -> bool {
    w.sel.best_of(&w.pairs).is_some_and(|p| {
        let kinds = p.kinds();
        kinds.iter().any(|k| k.in_plan().costly)
            && kinds.iter().any(|k| k.is_camera())
            && !Reach::Consistent.by(p.rms_px(), w.sel.noise_px)
    })
}

/// The best pair's costly effect fitted again through the pair's camera
/// ([`effect_through_camera`]), kept where better.
pub(super) fn costly_through_pair_camera(w: &mut Choosing) -> Result<(), DiagnoseError> {
    let s = w.sel;
    let score = |x: &WholeFit| s.score(x);
    let Some(p) = best_pair(&mut w.pairs.fits, &score) else { return Ok(()) };
    let Some(kind) = p.kinds().into_iter().find(|k| k.in_plan().costly) else { return Ok(()) };
    if let Some(again) =
        effect_through_camera(s.again, s.ms, &FoundCamera::of(p), kind, s.noise_px)?
        && again.cost < p.cost
    {
        let seconds = p.seconds + again.seconds;
        *p = WholeFit { seconds, ..again };
    }
    Ok(())
}

/// What the ranked candidates say (see the module doc): the best by BIC of those worth their
/// numbers over the baseline ([`Selection::worth`]) that explain its misfit beyond the noise
/// ([`explains`]) is named; else nothing is missing when the baseline is within
/// [`Reach::Consistent`] of the noise, and something unexplained when it is not. BIC alone is
/// not enough: where the baseline misses by far more than the noise its residuals are no white
/// noise, and any extra parameter that bends the path a little buys thousands of BIC points.
pub(super) fn decide<'a>(
    sel: &Selection,
    ranked: &[(Candidate, Option<&'a WholeFit>)],
) -> (Finding, Option<&'a WholeFit>) {
    let (baseline, noise_px) = (sel.baseline, sel.noise_px);
    let before = baseline.rms_px();
    let effects = || {
        ranked
            .iter()
            .filter(|(c, w)| !c.effect.is_baseline() && w.is_some() && c.rms_px.is_finite())
    };
    let named = effects().find(|(c, w)| {
        explains(before, c.rms_px, noise_px) && w.is_some_and(|w| sel.worth(w, baseline))
    });
    if let Some((c, w)) = named {
        return (Finding::Named(vec![c.effect]), *w);
    }
    if Reach::Consistent.by(before, noise_px) {
        return (Finding::Nothing, None);
    }
    let share = |c: &Candidate| explained_share(before, c.rms_px, noise_px);
    let partial = effects()
        .map(|(c, _)| Partial { effects: vec![c.effect], share: share(c), rms_px: c.rms_px })
        .filter(|p| p.share > 0.0)
        .max_by(|a, b| a.share.total_cmp(&b.share));
    (Finding::Unexplained { partial }, None)
}

/// Model `p` fitted again without each of its effects in turn ([`refit_without`]).
fn drop_each(ms: &Shooting, p: &WholeFit) -> Result<Vec<WholeFit>, DiagnoseError> {
    let kinds: Vec<EffectKind> = p.also.iter().map(|(k, _)| *k).chain([p.kind]).collect();
    let fits: Vec<Result<WholeFit, LmError>> = {
        use rayon::prelude::*;
        kinds.par_iter().map(|&k| refit_without(ms, p, k)).collect()
    };
    let mut out = Vec::new();
    for f in fits {
        match f {
            Ok(w) => out.push(w),
            Err(LmError::Cancelled) => return Err(DiagnoseError::Cancelled),
            Err(_) => {}
        }
    }
    Ok(out)
}
