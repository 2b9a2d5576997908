//! The decision and the forward selection: which single effect, or pair, is named.

use super::again::{
    Again, best_pair, effects_through_camera, slip_through_camera, walk_best_pair_again,
};
use super::candidates::{fit_pair, refit_with, refit_without};
use super::in_order::in_order_until;
use super::options::DiagnoseError;
use super::progress::Reporter;
use super::result::{Candidate, Finding, PairCandidate, Partial};
use super::rules::{CONSISTENT_RATIO, MIN_EXPLAINED, bic, explained_share, explains, settled};
use super::seen_camera::FoundCamera;
use super::whole::{Level, WholeFit};
use crate::analysis::fit::lm::LmError;
use crate::analysis::fit::shooting::Shooting;
use crate::physics::effects::EffectKind;
use std::sync::Mutex;
use std::sync::atomic::AtomicBool;

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
struct Pairs {
    fits: Vec<PairFit>,
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

/// The finding, the model that stands for it (`None`: the baseline) and the pairs tried.
pub(super) type Selected = (Finding, Option<WholeFit>, Vec<PairCandidate>);

/// Stage 5: the decision ([`decide`]), then forward selection: where the named effect, or no
/// single one, leaves the misfit beyond the noise, pairs of the candidates that improved on
/// the baseline; a pair is named only when it beats every effect alone. Where the segments see
/// a camera, every effect through that camera first, and the pairs only where none of those
/// settles the recording (a pair walked from the baseline's path starts from segments fitted
/// through the wrong camera). Each step runs only where none before it has settled it.
pub(super) fn forward_selection(
    sel: &Selection,
    ranked: &mut [(Candidate, Option<&WholeFit>)],
) -> Result<Selected, DiagnoseError> {
    let (finding, chosen) = decide(sel.baseline, ranked, sel.noise_px, sel.evidence);
    let chosen = chosen.unwrap_or(sel.baseline);
    let pairs_fitted = chosen.rms_px() > CONSISTENT_RATIO * sel.noise_px;
    let through_seen = sel.again.seen.filter(|_| pairs_fitted);
    let mut pairs = Pairs::default();
    if pairs_fitted {
        sel.through_seen_camera(through_seen, chosen, ranked, &mut pairs)?;
        sel.pairs_then_added(ranked, &mut pairs)?;
    }
    sel.chosen_through_seen_camera(through_seen, chosen, &mut pairs)?;
    if pairs_fitted && through_seen.is_none() {
        sel.slip_through_lead_camera(ranked, &mut pairs)?;
    }
    if pairs_fitted {
        sel.others_through_cameras(through_seen, ranked, &mut pairs)?;
    }
    sel.walk_best_pair_again(&mut pairs)?;
    let trimmed = sel.trimmed(&pairs)?;
    let best_pair = trimmed.as_ref().or_else(|| sel.best_of(&pairs));
    let (finding, chosen) = sel.name(finding, chosen, best_pair, ranked)?;
    Ok((finding, chosen, sel.pair_candidates(&pairs)))
}

impl Selection<'_> {
    fn score(&self, w: &WholeFit) -> f64 {
        bic(w.cost, self.baseline.residual_count, w.parameter_count, self.dependence)
    }

    /// Every effect through the camera the segments see (`through_seen`): the chosen one with
    /// the camera free, then the others, most promising first.
    fn through_seen_camera(
        &self,
        through_seen: Option<&FoundCamera>,
        chosen: &WholeFit,
        ranked: &[(Candidate, Option<&WholeFit>)],
        pairs: &mut Pairs,
    ) -> Result<(), DiagnoseError> {
        let Some(seen) = through_seen else { return Ok(()) };
        self.progress.pair_again("every effect through the camera the segments see", false);
        let kinds: Vec<EffectKind> =
            [camera_free(chosen.kind)].into_iter().chain(through_seen_kinds(ranked)).collect();
        pairs.extend(effects_through_camera(self.again, self.ms, seen, &kinds, self.noise_px)?);
        Ok(())
    }

    /// The pairs ([`pairs_stage`]), then each other effect added to the best one's solution
    /// ([`added_to_best`]), each where nothing before it settled the recording.
    fn pairs_then_added(
        &self,
        ranked: &[(Candidate, Option<&WholeFit>)],
        pairs: &mut Pairs,
    ) -> Result<(), DiagnoseError> {
        if !settles(&pairs.fits, self.noise_px) {
            let (more, walked) = pairs_stage(
                self.again,
                self.ms,
                self.levels,
                ranked,
                self.noise_px,
                self.progress,
            )?;
            pairs.fits.extend(more);
            pairs.walked = walked;
        }
        if !settles(&pairs.fits, self.noise_px) {
            self.progress.pair_again("each other effect added to the best one's solution", false);
            added_to_best(self.ms, ranked, &mut pairs.fits, self.noise_px)?;
        }
        Ok(())
    }

    /// A camera the segments see that the model chosen so far lacks (part of): that model's
    /// effect fitted through it, the camera then free beside it, as a pair; tried even where
    /// the model ends within the noise's margin (a weak lens beside rolling friction, a lens
    /// beside a pinhole).
    fn chosen_through_seen_camera(
        &self,
        through_seen: Option<&FoundCamera>,
        chosen: &WholeFit,
        pairs: &mut Pairs,
    ) -> Result<(), DiagnoseError> {
        let Some(seen) = self.again.seen.filter(|_| through_seen.is_none()) else { return Ok(()) };
        let held = chosen.kinds();
        if seen.numbers.iter().any(|(k, _)| !held.contains(k)) {
            self.progress.pair_again("the chosen model through the camera the segments see", false);
            let kinds = [camera_free(chosen.kind)];
            pairs.extend(effects_through_camera(self.again, self.ms, seen, &kinds, self.noise_px)?);
        }
        Ok(())
    }

    /// The camera a fit found: the one the segments see, else its own.
    fn found(&self, lead: &WholeFit) -> FoundCamera {
        self.again.seen.cloned().unwrap_or_else(|| FoundCamera::of(lead))
    }

    /// Where a camera effect leads and slip did not improve alone, slip through that camera
    /// ([`slip_through_camera`]).
    fn slip_through_lead_camera(
        &self,
        ranked: &[(Candidate, Option<&WholeFit>)],
        pairs: &mut Pairs,
    ) -> Result<(), DiagnoseError> {
        if settles(&pairs.fits, self.noise_px) {
            return Ok(());
        }
        let seen = self.again.seen.is_some();
        let Some(lead) =
            camera_lead_without_slip(ranked, &pairs.fits, self.baseline, self.noise_px, seen)
        else {
            return Ok(());
        };
        self.progress.pair_again(&format!("slip through the camera {} found", lead.kind), true);
        if let Some(p) = slip_through_camera(self.again, self.ms, &self.found(lead), self.noise_px)?
        {
            pairs.fits.push((lead.kind, EffectKind::Slip, Ok(p)));
        }
        Ok(())
    }

    /// Where a camera effect leads and every pair still misses, every other effect through
    /// the camera the segments see, then through the one the leading camera effect found: a
    /// weak strength can stay in the baseline's valley through either.
    fn others_through_cameras(
        &self,
        through_seen: Option<&FoundCamera>,
        ranked: &[(Candidate, Option<&WholeFit>)],
        pairs: &mut Pairs,
    ) -> Result<(), DiagnoseError> {
        let seen = self.again.seen.is_some();
        let Some(lead) = camera_lead_still_missing(ranked, &pairs.fits, self.noise_px, seen) else {
            return Ok(());
        };
        let mut cameras: Vec<FoundCamera> =
            self.again.seen.filter(|_| through_seen.is_none()).cloned().into_iter().collect();
        if lead.kind.is_camera() && !cameras.contains(&FoundCamera::of(lead)) {
            cameras.push(FoundCamera::of(lead));
        }
        self.progress.pair_again("the other effects through the camera found", false);
        let kinds = others_through_camera(ranked, seen);
        for camera in cameras {
            if reaches_noise(&pairs.fits, self.noise_px) {
                break;
            }
            pairs.extend(effects_through_camera(
                self.again,
                self.ms,
                &camera,
                &kinds,
                self.noise_px,
            )?);
        }
        Ok(())
    }

    /// The best pair walked down its path again (not twice: the pairs stage may have walked
    /// it already), then, where it is slip beside a camera, slip through that camera.
    fn walk_best_pair_again(&self, pairs: &mut Pairs) -> Result<(), DiagnoseError> {
        if !pairs.fits.is_empty() {
            self.progress.pair_again("the best pair fitted again", false);
        }
        let score = |w: &WholeFit| self.score(w);
        if best_pair(&mut pairs.fits, &score).is_none_or(|p| !pairs.walked.contains(&p.kinds())) {
            walk_best_pair_again(
                self.again,
                self.ms,
                self.levels,
                &mut pairs.fits,
                &score,
                self.noise_px,
            )?;
        }
        slip_pair_through_its_camera(
            self.again,
            self.ms,
            &mut pairs.fits,
            &score,
            self.noise_px,
            self.progress,
        )
    }

    /// The best pair fitted.
    fn best_of<'p>(&self, pairs: &'p Pairs) -> Option<&'p WholeFit> {
        pairs
            .fits
            .iter()
            .filter_map(|(_, _, r)| r.as_ref().ok())
            .min_by(|a, b| self.score(a).total_cmp(&self.score(b)))
    }

    /// A model of three effects (slip through a camera of two the segments see) is named only
    /// where each is needed: else the best of it with one left out stands for it.
    fn trimmed(&self, pairs: &Pairs) -> Result<Option<WholeFit>, DiagnoseError> {
        match self.best_of(pairs) {
            Some(p) if p.also.len() > 1 => {
                let fewer = drop_each(self.ms, p)?;
                Ok(fewer
                    .into_iter()
                    .min_by(|a, b| self.score(a).total_cmp(&self.score(b)))
                    .filter(|r| self.score(r) <= self.score(p) + self.evidence))
            }
            _ => Ok(None),
        }
    }

    /// The finding after the pairs: the best pair where it beats the model chosen and neither
    /// of its effects alone does as well (each fitted alone from the pair's solution: a single
    /// fit can end in a side valley the pair's extra number lets the least squares leave); that
    /// effect alone where it does; else the pair as the better partial answer where it removes
    /// at least half of what the best single one leaves beyond the noise.
    /// Returns the finding and the model that stands for it (`None`: the baseline).
    fn name(
        &self,
        mut finding: Finding,
        chosen: &WholeFit,
        best_pair: Option<&WholeFit>,
        ranked: &mut [(Candidate, Option<&WholeFit>)],
    ) -> Result<(Finding, Option<WholeFit>), DiagnoseError> {
        let (noise_px, evidence) = (self.noise_px, self.evidence);
        let none_score = self.score(self.baseline);
        let pair_wins = best_pair.is_some_and(|p| {
            self.score(p) < self.score(chosen) - evidence
                && explains(chosen.rms_px(), p.rms_px(), noise_px)
        });
        let alone = match best_pair.filter(|_| pair_wins) {
            Some(p) => drop_each(self.ms, p)?,
            None => Vec::new(),
        };
        let best_alone = alone.iter().min_by(|a, b| self.score(a).total_cmp(&self.score(b)));
        let alone_enough = best_alone
            .zip(best_pair)
            .is_some_and(|(a, p)| self.score(a) <= self.score(p) + evidence);
        if let (Some(p), false) = (best_pair.filter(|_| pair_wins), alone_enough) {
            let named = p.also.iter().map(|(k, _)| *k).chain([p.kind]).collect();
            return Ok((Finding::Named(named), Some(p.clone())));
        }
        if let Some(a) = best_alone.filter(|a| {
            alone_enough
                && self.score(a) < self.score(chosen)
                && self.score(a) < none_score - evidence
                && explains(self.baseline.rms_px(), a.rms_px(), noise_px)
        }) {
            if let Some((c, _)) = ranked.iter_mut().find(|(c, _)| c.effect == a.kind) {
                (c.rms_px, c.score, c.delta_score, c.strength) =
                    (a.rms_px(), self.score(a), self.score(a) - none_score, a.strength);
            }
            return Ok((Finding::Named(vec![a.kind]), Some(a.clone())));
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
        Ok((finding, (!std::ptr::eq(chosen, self.baseline)).then(|| chosen.clone())))
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
    if kind.is_camera() { EffectKind::None } else { kind }
}

/// The effects fitted through the camera the segments see, most promising first: by their
/// score alone, but slip, where it did not improve alone, second. Through the wrong camera it
/// cannot improve ([`slip_through_camera`]), so its score says nothing; its runs take longest,
/// so begun early they run beside the others' (the pairs, where nothing settles, wait for the
/// last of them), and where it settles the recording the others are not fitted.
pub(super) fn through_seen_kinds(ranked: &[(Candidate, Option<&WholeFit>)]) -> Vec<EffectKind> {
    let mut kinds = others_through_camera(ranked, true);
    if ranked.iter().any(|(c, _)| c.effect == EffectKind::Slip)
        && !kinds.contains(&EffectKind::Slip)
    {
        kinds.insert(kinds.len().min(1), EffectKind::Slip);
    }
    kinds
}

/// The candidates fitted through a camera found: every effect but slip, which has its own step
/// ([`slip_through_camera`]) where it did not improve alone; where it did, and the segments see
/// a camera (`camera_seen`), it is one of the others.
fn others_through_camera(
    ranked: &[(Candidate, Option<&WholeFit>)],
    camera_seen: bool,
) -> Vec<EffectKind> {
    ranked
        .iter()
        .filter(|(c, _)| c.effect != EffectKind::None)
        .filter(|(c, _)| c.effect != EffectKind::Slip || (camera_seen && c.delta_score < 0.0))
        .map(|(c, _)| c.effect)
        .collect()
}

/// The best pair where it is slip beside a camera effect and still misses beyond the noise:
/// slip fitted again through the pair's camera ([`slip_through_camera`]), kept where better.
fn slip_pair_through_its_camera(
    again: &Again,
    ms: &Shooting,
    pairs: &mut [PairFit],
    score: &dyn Fn(&WholeFit) -> f64,
    noise_px: f64,
    progress: &Reporter,
) -> Result<(), DiagnoseError> {
    let Some(p) = best_pair(pairs, score) else { return Ok(()) };
    let kinds: Vec<EffectKind> = p.also.iter().map(|(k, _)| *k).chain([p.kind]).collect();
    let slip_with_camera = kinds.contains(&EffectKind::Slip) && kinds.iter().any(|k| k.is_camera());
    if !slip_with_camera || p.rms_px() <= CONSISTENT_RATIO * noise_px {
        return Ok(());
    }
    progress.pair_again("slip fitted again through the best pair's camera", true);
    if let Some(again) = slip_through_camera(again, ms, &FoundCamera::of(p), noise_px)?
        && again.cost < p.cost
    {
        let seconds = p.seconds + again.seconds;
        *p = WholeFit { seconds, ..again };
    }
    Ok(())
}

/// The best single candidate where it is a camera effect that explains at least
/// [`MIN_EXPLAINED`] of the baseline's excess, and slip was offered but not paired (it did
/// not improve on the baseline alone): then slip is fitted through that camera
/// ([`slip_through_camera`]). Only where the pairs were fitted at all. A camera that explains
/// less imitates a little of some other effect, and slip through it, the slowest fit there
/// is, bought nothing there (withheld translational drag: a lens explaining 4% of the excess,
/// slip through it 40 s and 120.8 px against the baseline's 1.34; docs/diagnosis.md).
fn camera_lead_without_slip<'a>(
    ranked: &[(Candidate, Option<&'a WholeFit>)],
    pair_fits: &[PairFit],
    baseline: &WholeFit,
    noise_px: f64,
    camera_seen: bool,
) -> Option<&'a WholeFit> {
    if pair_fits.is_empty() {
        return None;
    }
    let slip = ranked.iter().find(|(c, _)| c.effect == EffectKind::Slip)?;
    if slip.0.delta_score < 0.0 {
        return None;
    }
    camera_lead(ranked, camera_seen)
        .filter(|lead| explained_share(baseline.rms_px(), lead.rms_px(), noise_px) >= MIN_EXPLAINED)
}

/// The best single candidate where it is a camera effect that improved on the baseline and
/// no pair reaches the noise: then the other candidates (slip has its own step), the other
/// camera effect among them, are fitted through that camera ([`effects_through_camera`]). Only where the pairs were fitted at all.
fn camera_lead_still_missing<'a>(
    ranked: &[(Candidate, Option<&'a WholeFit>)],
    pair_fits: &[PairFit],
    noise_px: f64,
    camera_seen: bool,
) -> Option<&'a WholeFit> {
    if pair_fits.is_empty() || reaches_noise(pair_fits, noise_px) {
        return None;
    }
    camera_lead(ranked, camera_seen)
}

/// The best single candidate's fit where it improved on the baseline and is a camera effect,
/// or any effect where the segments see a camera (`camera_seen`: a physical effect can lead
/// where the camera imitates part of it).
fn camera_lead<'a>(
    ranked: &[(Candidate, Option<&'a WholeFit>)],
    camera_seen: bool,
) -> Option<&'a WholeFit> {
    let (lead, w) = ranked.iter().find(|(c, _)| c.effect != EffectKind::None)?;
    ((camera_seen || lead.effect.is_camera()) && lead.delta_score < 0.0).then_some(*w).flatten()
}

/// A pair of the forward selection: its two effects and its fit.
type PairFit = (EffectKind, EffectKind, Result<WholeFit, LmError>);

/// Whether a pair fitted reaches [`CONSISTENT_RATIO`] times the noise (then no other pair is
/// needed to explain what is left).
fn reaches_noise(pair_fits: &[PairFit], noise_px: f64) -> bool {
    pair_fits
        .iter()
        .any(|(_, _, r)| r.as_ref().is_ok_and(|w| w.rms_px() <= CONSISTENT_RATIO * noise_px))
}

/// What the ranked candidates say (see the module doc): the best by BIC of those that beat the
/// baseline by `evidence` and explain its misfit beyond the noise ([`explains`]) is named; else nothing is missing when the baseline is within [`CONSISTENT_RATIO`]
/// of the noise, and something unexplained when it is not. BIC alone is not enough: where the
/// baseline misses by far more than the noise its residuals are no white noise, and any extra
/// parameter that bends the path a little buys thousands of BIC points (a lens fitted to a
/// sliding ring's recording: -735 for a misfit from 14.6 to 14.2 px).
pub(super) fn decide<'a>(
    baseline: &WholeFit,
    ranked: &[(Candidate, Option<&'a WholeFit>)],
    noise_px: f64,
    evidence: f64,
) -> (Finding, Option<&'a WholeFit>) {
    let before = baseline.rms_px();
    let effects = || {
        ranked
            .iter()
            .filter(|(c, w)| c.effect != EffectKind::None && w.is_some() && c.rms_px.is_finite())
    };
    if let Some((c, w)) =
        effects().find(|(c, _)| c.delta_score < -evidence && explains(before, c.rms_px, noise_px))
    {
        return (Finding::Named(vec![c.effect]), *w);
    }
    if before <= CONSISTENT_RATIO * noise_px {
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

/// How many of the best single candidates (by BIC, better than the baseline) the forward
/// selection pairs with each other. Pairs among the best few and not only with the one named:
/// where two effects are in a recording, the one named alone is often a third that imitates
/// both (Reynolds drag and pivot friction together are named rolling friction alone); and
/// four, not three, because a camera candidate can imitate part of a physical effect and push
/// one of the pair out of the best three.
const PAIRED: usize = 4;

/// How many of the best single candidates are each paired with every other candidate, also
/// those that did nothing alone. An effect can be invisible alone where another is at work:
/// the baseline's drag absorbs it, or it only shows once the other is in the model (a lens
/// beside rolling friction: alone 13.70 px against the baseline's 13.72; Reynolds drag beside
/// pivot friction: alone no better than the baseline at all). Three, not one, because the best
/// alone can itself be the imitator of a pair's member, and a pair's member alone can end in a
/// side valley that ranks it third (rolling friction beside a lens: 7.3 px alone, where it
/// reaches 4.6 px; with it the lens then reaches the noise).
const LEADS: usize = 3;

/// The pairs of the forward selection, each fitted on the baseline's path: every pair among
/// the [`PAIRED`] best single candidates, and each of the [`LEADS`] best with every other
/// candidate (slip only where it improved on the baseline alone: its runs cost most, and a
/// slide the recording shows moves the misfit alone by far); the second and third leads' pairs
/// only where none of the others reaches the noise. Fitted most promising first, on every
/// thread, until one settles the recording ([`in_order_until`]). Returns the pairs fitted and
/// those walked again.
fn pairs_stage(
    again: &Again,
    ms: &Shooting,
    levels: &[Level],
    ranked: &[(Candidate, Option<&WholeFit>)],
    noise_px: f64,
    progress: &Reporter,
) -> Result<(Vec<PairFit>, Vec<Vec<EffectKind>>), DiagnoseError> {
    let fitted: Vec<(&Candidate, &WholeFit)> = ranked
        .iter()
        .filter(|(c, _)| c.effect != EffectKind::None)
        .filter(|(c, _)| c.effect != EffectKind::Slip || c.delta_score < 0.0)
        .filter_map(|(c, w)| w.map(|w| (c, w)))
        .collect();
    let rounds = pair_rounds(&fitted);
    let best_single_px = fitted.iter().map(|(_, w)| w.rms_px()).fold(f64::INFINITY, f64::min);
    let mut out: Vec<PairFit> = Vec::new();
    let walked: Mutex<Vec<Vec<EffectKind>>> = Mutex::new(Vec::new());
    for (n, round) in rounds.iter().enumerate() {
        if reaches_noise(&out, noise_px) || round.is_empty() {
            break;
        }
        progress.pairs_planned(n, round.len());
        let one = |&(i, j): &(usize, usize), stop: &AtomicBool| -> PairFit {
            let (a, b) = (fitted[i].1, fitted[j].1);
            let ms = &ms.stopped_by(stop);
            let mut fit = fit_pair(ms, levels, a, b, &mut |_, _| {});
            // A pair that explains most of what the best effect alone leaves is walked again
            // at once: a right pair's first walk often stops short of the noise (Reynolds
            // drag beside pivot friction: 0.79 px, walked again 0.50 px against 0.49 px of
            // noise), and walked it settles the recording, so the pairs after it are spared.
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
            |(_, _, r): &PairFit| r.as_ref().is_ok_and(|w| settled(w.rms_px(), noise_px));
        out.extend(in_order_until(round, &one, &is_settled, ms.cancel));
        if ms.cancel.load(std::sync::atomic::Ordering::Relaxed) {
            return Err(DiagnoseError::Cancelled);
        }
        if settles(&out, noise_px) {
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
        // A lens beside a pinhole is a pair too: a real camera has both (a pinhole 450 mm away
        // with k1 = -0.05 from a third simulator: either alone leaves 1.2 px or more, the two
        // reach the noise).
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

/// Forward selection from where the best single candidate ended: each other effect (slip
/// aside, as in the pairs) added at its baseline strength to that candidate's solution and
/// fitted over the whole run ([`refit_with`]), on every thread until one settles the recording.
/// The pairs of [`pairs_stage`] are walked from the baseline's path, and where the best effect
/// alone sits in a valley of its own they can end worse than it (Reynolds drag beside pivot
/// friction: the pair at 2.37 px, Reynolds drag alone at 1.42). A fit that beats the same pair
/// fitted before takes its place.
fn added_to_best(
    ms: &Shooting,
    ranked: &[(Candidate, Option<&WholeFit>)],
    pair_fits: &mut Vec<PairFit>,
    noise_px: f64,
) -> Result<(), DiagnoseError> {
    let Some(lead) = ranked
        .iter()
        .filter(|(c, _)| c.effect != EffectKind::None && c.delta_score < 0.0)
        .find_map(|(_, w)| w.filter(|w| w.stopped_at.is_none()))
    else {
        return Ok(());
    };
    let added: Vec<EffectKind> =
        others_through_camera(ranked, false).into_iter().filter(|&k| k != lead.kind).collect();
    let one = |&k: &EffectKind, stop: &AtomicBool| {
        let zero = k.baseline_strength().unwrap_or(0.0);
        (k, refit_with(&ms.stopped_by(stop), lead, k, zero))
    };
    let is_settled = |(_, r): &(EffectKind, Result<WholeFit, LmError>)| {
        r.as_ref().is_ok_and(|w| settled(w.rms_px(), noise_px))
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

/// Whether a pair fitted has settled the recording ([`settled`]): then the pairs still
/// planned are not fitted (a pinhole beside translational drag reached 0.499 px against
/// 0.495 px of noise as the first pair; the 18 others fitted after it took 100 s of CPU).
fn settles(pair_fits: &[PairFit], noise_px: f64) -> bool {
    pair_fits.iter().any(|(_, _, r)| r.as_ref().is_ok_and(|w| settled(w.rms_px(), noise_px)))
}
