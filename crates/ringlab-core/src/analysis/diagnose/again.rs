//! Fits made again from where a first walk ended: a side valley left by walking once more,
//! and the passes of the plan's singles phase ([`Singles`], `plan.rs`).

use super::candidates::{fit_baseline, fit_candidate, refit_from, with_budget, with_contact_start};
use super::in_order::in_order_until;
use super::options::DiagnoseError;
use super::progress::Reporter;
use super::ranking::{Fits, rank, through_seen_kinds};
use super::rules::{MIN_EXPLAINED, Reach, explained_share};
use super::seen_camera::FoundCamera;
use super::whole::{Level, WholeFit, fit_path, fit_whole, no_ceiling, with_effect, with_effects};
use crate::analysis::fit::lm::LmError;
use crate::analysis::fit::shooting::Shooting;
use crate::analysis::fit::{FitError, FitOptions, fit};
use crate::physics::effects::EffectKind;
use crate::recording::{Camera, Recording};
use std::sync::Mutex;
use std::sync::atomic::AtomicBool;
use web_time::Instant;

/// A camera candidate that improved on the baseline but still misses beyond the noise is
/// fitted again from a multiple-shooting fit made with the camera it found. The baseline's
/// segments were fitted through the wrong camera, and its drag and states carry that into every
/// stage of the path, so that even from the true camera the path can stay far from the noise;
/// the camera does not change the motion, so segments fitted through the camera of that first
/// pass see the motion as it was. Only for a camera candidate that leads the candidates or
/// explains at least [`MIN_EXPLAINED`] of the baseline's excess: one that explains less
/// imitates a little of another effect (with physics the candidates lack, every recording has
/// one), and its pass, a multiple-shooting fit and a whole path, buys nothing there
/// (docs/diagnosis.md).
pub(super) fn camera_second_pass(
    again: &Again,
    ms: &Shooting,
    baseline: &WholeFit,
    fits: &mut [(EffectKind, Result<WholeFit, LmError>)],
    noise_px: f64,
) -> Result<(), DiagnoseError> {
    let (rec, fit_opts) = (again.rec, again.fit_opts);
    let best_cost = fits
        .iter()
        .filter_map(|(_, r)| r.as_ref().ok())
        .map(|w| w.cost)
        .fold(f64::INFINITY, f64::min);
    for (kind, r) in fits.iter_mut().filter(|(k, _)| k.is_camera()) {
        let Ok(first) = r.as_ref() else { continue };
        if first.cost >= baseline.cost || Reach::Consistent.by(first.rms_px(), noise_px) {
            continue;
        }
        if first.cost > best_cost
            && explained_share(baseline.rms_px(), first.rms_px(), noise_px) < MIN_EXPLAINED
        {
            continue;
        }
        let clock = Instant::now();
        let base = match fit(rec, &through_camera_of(&first.camera, fit_opts), &|_| {}, ms.cancel) {
            Ok(b) => b,
            Err(FitError::Cancelled) => return Err(DiagnoseError::Cancelled),
            Err(_) => continue,
        };
        let through = base.shooting(&rec.frames, ms.cancel);
        let sh = with_effect(&through, *kind);
        let global = sh.spec.to_internal(&sh.spec.initial_values());
        match fit_path(&sh, global, &base.segment_states, &no_ceiling, &mut |_, _| {}) {
            Ok((mut again, _)) if again.cost < first.cost => {
                again.seconds = first.seconds + clock.elapsed().as_secs_f64();
                *r = Ok(again);
            }
            Err(LmError::Cancelled) => return Err(DiagnoseError::Cancelled),
            _ => {}
        }
    }
    Ok(())
}

/// The best pair by score walked down its path again ([`walk_again`]): its first walk began
/// at the baseline's drag, and with two strengths free it often ends in a side valley that no
/// polishing of the last stage leaves. Walked again up to [`PAIR_WALKS`] times while each walk
/// cuts its misfit by a tenth or more and it still misses beyond the noise: a weak strength
/// grows a little with each walk (docs/diagnosis.md). Not walked where it has settled the
/// recording already.
pub(super) fn walk_best_pair_again(
    again: &Again,
    ms: &Shooting,
    levels: &[Level],
    pairs: &mut [(EffectKind, EffectKind, Result<WholeFit, LmError>)],
    score: &dyn Fn(&WholeFit) -> f64,
    noise_px: f64,
) -> Result<(), DiagnoseError> {
    let Some(p) = best_pair(pairs, score) else { return Ok(()) };
    if Reach::Settled.by(p.rms_px(), noise_px) {
        return Ok(());
    }
    for _ in 0..PAIR_WALKS {
        let before = p.cost;
        walk_again(again, ms, levels, p)?;
        if !(p.cost < 0.81 * before) || Reach::Consistent.by(p.rms_px(), noise_px) {
            break;
        }
    }
    Ok(())
}

/// How many times [`walk_best_pair_again`] walks the best pair at most.
const PAIR_WALKS: usize = 3;

/// The pair fitted with the best (lowest) `score`.
pub(super) fn best_pair<'a>(
    pairs: &'a mut [(EffectKind, EffectKind, Result<WholeFit, LmError>)],
    score: &dyn Fn(&WholeFit) -> f64,
) -> Option<&'a mut WholeFit> {
    pairs
        .iter_mut()
        .filter_map(|(_, _, r)| r.as_mut().ok())
        .min_by(|a, b| score(a).total_cmp(&score(b)))
}

/// The [`WALKED_AGAIN`] best physical candidates that improved on the baseline but still miss
/// beyond the noise, each walked down its path again ([`walk_again`]), in parallel. A single
/// effect's first walk, from the baseline's drag, can end in a side valley too, and then the
/// pairs are fitted for nothing and its imitators rank beside it. One still beyond the noise
/// that explains less than [`MIN_EXPLAINED`] of the baseline's excess is then refitted from the
/// baseline's solution across its range ([`scan_from_baseline`]): the valley that scan leaves
/// is one at nearly zero strength, where the effect explains next to nothing.
pub(super) fn walk_best_singles_again(
    again: &Again,
    ms: &Shooting,
    levels: &[Level],
    baseline: &WholeFit,
    fits: &mut [(EffectKind, Result<WholeFit, LmError>)],
    noise_px: f64,
) -> Result<(), DiagnoseError> {
    let mut todo: Vec<&mut WholeFit> = fits
        .iter_mut()
        .filter(|(k, _)| !k.is_camera())
        .filter_map(|(_, r)| r.as_mut().ok())
        .filter(|w| w.cost < baseline.cost && w.stopped_at.is_none())
        .collect();
    todo.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    todo.truncate(WALKED_AGAIN);
    todo.retain(|w| !Reach::Consistent.by(w.rms_px(), noise_px));
    use rayon::prelude::*;
    todo.into_par_iter()
        .map(|w| {
            walk_again(again, ms, levels, w)?;
            if !Reach::Consistent.by(w.rms_px(), noise_px)
                && explained_share(baseline.rms_px(), w.rms_px(), noise_px) < MIN_EXPLAINED
            {
                scan_from_baseline(ms, baseline, w)?;
            }
            Ok(())
        })
        .collect()
}

/// Fit `w` (a physical effect, not a costly one) refitted over the whole run from the
/// baseline's own solution at each of [`scan_strengths`], kept where one ends better. Its walks
/// begin at the strength that suits the baseline's segments best, and where those segments
/// absorb the effect (a tracker's noise correlated in time lends them freedom) that can be near
/// zero, a valley the walks do not leave; from the ends and the middle of its range it reaches
/// its own (docs/diagnosis.md, "A tracker's noise correlated in time").
fn scan_from_baseline(
    ms: &Shooting,
    baseline: &WholeFit,
    w: &mut WholeFit,
) -> Result<(), DiagnoseError> {
    use rayon::prelude::*;
    // The candidate's time counts the whole scan, every start and the polish, kept or not.
    let clock = Instant::now();
    let fits: Vec<Result<WholeFit, LmError>> =
        scan_strengths(w.kind).par_iter().map(|&s| refit_from(ms, w.kind, baseline, s)).collect();
    let mut best: Option<WholeFit> = None;
    for f in fits {
        match f {
            Ok(scanned) if scanned.cost < best.as_ref().map_or(w.cost, |b| b.cost) => {
                best = Some(scanned);
            }
            Err(LmError::Cancelled) => return Err(DiagnoseError::Cancelled),
            _ => {}
        }
    }
    let Some(mut best) = best else {
        w.seconds += clock.elapsed().as_secs_f64();
        return Ok(());
    };
    // Once more from where it ended: from so far up a valley's side one fit can run out of
    // iterations on the way down.
    match polish(ms, &best) {
        Ok(p) if p.cost < best.cost => best = p,
        Err(LmError::Cancelled) => return Err(DiagnoseError::Cancelled),
        _ => {}
    }
    *w = WholeFit { seconds: w.seconds + clock.elapsed().as_secs_f64(), ..best };
    Ok(())
}

/// Fit `w` over its whole span once more, from its own numbers.
fn polish(ms: &Shooting, w: &WholeFit) -> Result<WholeFit, LmError> {
    let kinds: Vec<EffectKind> = w.also.iter().map(|(k, _)| *k).chain([w.kind]).collect();
    let mut sh =
        with_budget(with_effects(&with_contact_start(ms, w.model.effects.slip_start), &kinds));
    sh.segments = vec![w.span.clone()];
    fit_whole(&sh, w.internal.clone(), &[w.start], &mut |_, _| {})
}

/// The strengths [`scan_from_baseline`] starts from: the ends and the middle (geometric) of
/// the effect's realistic range; none for a costly effect (its own starts cover its range, and
/// its runs from the baseline's solution crawl), the camera effects (fitted again through their
/// camera instead) and the baseline.
fn scan_strengths(kind: EffectKind) -> Vec<f64> {
    if kind.in_plan().costly || kind.is_camera() || kind.is_baseline() {
        return Vec::new();
    }
    let (lo, hi) = kind.realistic_range();
    vec![lo, (lo * hi).sqrt(), hi]
}

/// How many of the best single candidates [`walk_best_singles_again`] walks again: two, as
/// many as run at once on two cores, because the best one can be an imitator of the truth
/// left in its side valley second.
const WALKED_AGAIN: usize = 2;

/// Fit `p` walked down its path again from its own solution's drag and strengths, kept where
/// it ends better. A fit with a camera effect walks from segments fitted through its camera,
/// for the reason [`camera_second_pass`] gives.
pub(super) fn walk_again(
    again: &Again,
    ms: &Shooting,
    levels: &[Level],
    p: &mut WholeFit,
) -> Result<(), DiagnoseError> {
    let kinds: Vec<EffectKind> = p.also.iter().map(|(k, _)| *k).chain([p.kind]).collect();
    let camera_base = if kinds.iter().any(|k| k.is_camera()) {
        match fit(again.rec, &through_camera_of(&p.camera, again.fit_opts), &|_| {}, ms.cancel) {
            Ok(b) => Some(b),
            Err(FitError::Cancelled) => return Err(DiagnoseError::Cancelled),
            Err(_) => None,
        }
    } else {
        None
    };
    let (from, states) = match &camera_base {
        Some(b) => (b.shooting(&again.rec.frames, ms.cancel), b.segment_states.clone()),
        None => {
            let join = levels.first().ok_or(DiagnoseError::Baseline)?;
            let mut from = ms.clone();
            from.segments = join.segments.clone();
            (from, join.states.clone())
        }
    };
    let sh = with_effects(&with_contact_start(&from, p.model.effects.slip_start), &kinds);
    match fit_whole(&sh, p.internal.clone(), &states, &mut |_, _| {}) {
        Ok(mut walked) if walked.cost < p.cost => {
            walked.seconds += p.seconds;
            *p = walked;
        }
        Err(LmError::Cancelled) => return Err(DiagnoseError::Cancelled),
        _ => {}
    }
    Ok(())
}

/// `kind` beside the camera effects of `found` (the camera the segments see, or that of a
/// camera candidate that leads, or of a pair that still misses), found through that camera
/// ([`effects_through_camera`]). Through the camera the baseline assumed, a costly effect alone
/// may not even reach the baseline (the camera's error fills its first stage's segments), so
/// the forward selection, which pairs it only where it improved alone, would never try it.
pub(super) fn effect_through_camera(
    again: &Again,
    ms: &Shooting,
    found: &FoundCamera,
    kind: EffectKind,
    noise_px: f64,
) -> Result<Option<WholeFit>, DiagnoseError> {
    let fits = effects_through_camera(again, ms, found, &[kind], noise_px)?;
    Ok(fits.into_iter().next())
}

/// Each effect of `asked` beside the camera effects of `found`, found through that camera:
/// the multiple-shooting fit and the baseline's path are made again through the camera found,
/// each effect is fitted on that path as a candidate is, and then the camera is set free
/// beside it for the last stage; the baseline among them gives the camera alone fitted that
/// way. A pair walked from the baseline's path starts from segments fitted through the wrong
/// camera and can stay in the camera's valley with the other effect at zero; the other camera
/// effect too is fitted this way (a real camera has both).
///
/// `asked` go most promising first, and those after the first that settles the recording
/// are not fitted: nothing can then be told better. A fit made before through the same camera
/// (`again` keeps them) is not made again.
pub(super) fn effects_through_camera(
    again: &Again,
    ms: &Shooting,
    found: &FoundCamera,
    asked: &[EffectKind],
    noise_px: f64,
) -> Result<Vec<WholeFit>, DiagnoseError> {
    let cameras = &found.numbers;
    // Every effect asked for that the camera does not already hold (the other camera effect
    // too: a real camera has both).
    let mut kinds: Vec<EffectKind> = Vec::new();
    for &k in asked {
        if !cameras.iter().any(|(c, _)| *c == k) && !kinds.contains(&k) {
            kinds.push(k);
        }
    }
    if cameras.is_empty() || kinds.is_empty() {
        return Ok(Vec::new());
    }
    let settles = |w: &WholeFit| Reach::Settled.by(w.rms_px(), noise_px);
    if let Some(i) =
        kinds.iter().position(|&k| again.made(found, k).flatten().is_some_and(|w| settles(&w)))
    {
        kinds.truncate(i + 1);
    }
    let missing: Vec<EffectKind> =
        kinds.iter().copied().filter(|&k| again.made(found, k).is_none()).collect();
    if !missing.is_empty() {
        let fits = fit_through_camera(again, ms, found, &missing, &settles)?;
        for (k, fit) in missing.into_iter().zip(fits) {
            again.keep(found, k, fit);
        }
    }
    // Up to the first not made: the fits after the first that settled were not.
    Ok(kinds.into_iter().map_while(|k| again.made(found, k)).flatten().collect())
}

/// [`effects_through_camera`] made for `kinds`, in order until one is `done`
/// ([`in_order_until`]): each one's fit, None where it failed.
fn fit_through_camera(
    again: &Again,
    ms: &Shooting,
    found: &FoundCamera,
    kinds: &[EffectKind],
    done: &(dyn Fn(&WholeFit) -> bool + Sync),
) -> Result<Vec<Option<WholeFit>>, DiagnoseError> {
    let clock = Instant::now();
    let cameras = &found.numbers;
    let failed = || Ok(vec![None; kinds.len()]);
    let base =
        match fit(again.rec, &through_camera_of(&found.camera, again.fit_opts), &|_| {}, ms.cancel)
        {
            Ok(b) => b,
            Err(FitError::Cancelled) => return Err(DiagnoseError::Cancelled),
            Err(_) => return failed(),
        };
    let through = base.shooting(&again.rec.frames, ms.cancel);
    let Some((baseline, levels)) =
        (match fit_baseline(&through, &base.segment_states, &mut |_, _| {}) {
            Ok(b) => Some(b),
            Err(LmError::Cancelled) => return Err(DiagnoseError::Cancelled),
            Err(_) => None,
        })
    else {
        return failed();
    };
    // Each pair's time: the fits through the camera that all share, and its own.
    let shared_seconds = clock.elapsed().as_secs_f64();
    let one = |&kind: &EffectKind, stop: &AtomicBool| -> Result<WholeFit, LmError> {
        let own = Instant::now();
        let (through, ms) = (through.stopped_by(stop), ms.stopped_by(stop));
        let alone = if kind.is_baseline() {
            baseline.clone()
        } else {
            fit_candidate(&through, &levels, &baseline, kind, &mut |_, _| {})?
        };
        // A costly effect that left the baseline's valley even through this camera (its path
        // stopped beyond the ceiling) is far from the recording (a slide where it rolls); the
        // camera's numbers cannot bring it back, and its runs cost most.
        if kind.in_plan().costly && alone.stopped_at.is_some() {
            return Err(LmError::BadStart);
        }
        // The pair's numbers: the drag and body of the effect's fit, the camera's, the effect's.
        let shared = alone.internal.len() - kind.free_count();
        let mut global = alone.internal[..shared].to_vec();
        let mut order = Vec::new();
        for (camera, numbers) in cameras {
            order.push(*camera);
            global.extend(numbers);
        }
        global.extend_from_slice(&alone.internal[shared..]);
        order.push(kind);
        let start = alone.model.effects.slip_start;
        let mut sh = with_budget(with_effects(&with_contact_start(&ms, start), &order));
        sh.segments = vec![alone.span.clone()];
        let mut pair = fit_whole(&sh, global, &[alone.start], &mut |_, _| {})?;
        pair.seconds = shared_seconds + own.elapsed().as_secs_f64();
        Ok(pair)
    };
    let is_done = |r: &Result<WholeFit, LmError>| r.as_ref().is_ok_and(done);
    let fits = in_order_until(kinds, &one, &is_done, ms.cancel);
    if ms.cancel.load(std::sync::atomic::Ordering::Relaxed) {
        return Err(DiagnoseError::Cancelled);
    }
    Ok(fits.into_iter().map(Result::ok).collect())
}

/// What a fit made again from the recording needs (a multiple-shooting fit through another
/// camera).
pub(super) struct Again<'a> {
    pub(super) rec: &'a Recording,
    pub(super) fit_opts: &'a FitOptions,
    /// The camera the baseline's segments see ([`super::seen_camera`]), where they see one.
    pub(super) seen: Option<&'a FoundCamera>,
    /// The fits through a camera made so far, by camera and effect (None: it failed): several
    /// stages ask for the same ones (the stage before the decision, and the decision made
    /// again for a tracker's correlated noise), and each costs a multiple-shooting fit and
    /// whole paths.
    made: Mutex<Vec<(FoundCamera, EffectKind, Option<WholeFit>)>>,
}

impl<'a> Again<'a> {
    pub(super) fn new(
        rec: &'a Recording,
        fit_opts: &'a FitOptions,
        seen: Option<&'a FoundCamera>,
    ) -> Again<'a> {
        Again { rec, fit_opts, seen, made: Mutex::new(Vec::new()) }
    }

    /// The fit of `kind` through `camera` made before (`Some(None)`: it failed).
    fn made(&self, camera: &FoundCamera, kind: EffectKind) -> Option<Option<WholeFit>> {
        let made = self.made.lock().unwrap_or_else(|e| e.into_inner());
        made.iter().find(|(c, k, _)| c == camera && *k == kind).map(|(_, _, w)| w.clone())
    }

    fn keep(&self, camera: &FoundCamera, kind: EffectKind, fit: Option<WholeFit>) {
        let mut made = self.made.lock().unwrap_or_else(|e| e.into_inner());
        made.push((camera.clone(), kind, fit));
    }
}

/// The multiple-shooting fit's options with `camera` held fixed.
fn through_camera_of(camera: &Camera, fit_opts: &FitOptions) -> FitOptions {
    FitOptions {
        lens_k1: camera.k1,
        camera_distance_mm: camera.distance_mm,
        camera_tilt_deg: Some(camera.tilt_rad.to_degrees()),
        ..fit_opts.clone()
    }
}

/// What the plan's singles phase works on: the single candidates fitted along the baseline's
/// path, fitted again where none has settled the recording (`plan.rs`).
pub(super) struct Singles<'a> {
    pub(super) again: &'a Again<'a>,
    pub(super) ms: &'a Shooting<'a>,
    pub(super) levels: &'a [Level],
    pub(super) baseline: &'a WholeFit,
    pub(super) fits: Fits,
    /// The fits through the camera the segments see (kept in `again` for the selection too).
    pub(super) through_seen: Vec<WholeFit>,
    pub(super) noise_px: f64,
    /// The noise's dependence from frame to frame, for the ranking.
    pub(super) dependence: f64,
    pub(super) progress: &'a Reporter<'a>,
}

/// A pass that runs wherever nothing has settled the recording.
pub(super) fn always(_: &Singles) -> bool {
    true
}

/// Whether the segments see a camera.
pub(super) fn camera_seen(w: &Singles) -> bool {
    w.again.seen.is_some()
}

/// The camera candidates fitted again through the camera each found ([`camera_second_pass`]).
pub(super) fn cameras_second_pass(w: &mut Singles) -> Result<(), DiagnoseError> {
    camera_second_pass(w.again, w.ms, w.baseline, &mut w.fits, w.noise_px)
}

/// Every effect through the camera the segments see (the camera alone too), in the order the
/// selection will ask for them (`select.rs::through_seen_kinds`), until one settles the
/// recording; where one does, the physical candidates need no second walk (on a camera's
/// recordings those walks were of effects the camera imitated). Kept for the selection.
pub(super) fn through_seen_camera(w: &mut Singles) -> Result<(), DiagnoseError> {
    let Some(seen) = w.again.seen else { return Ok(()) };
    let ranked = rank(w.baseline, &w.fits, w.dependence);
    let kinds: Vec<EffectKind> =
        [EffectKind::BASELINE].into_iter().chain(through_seen_kinds(&ranked)).collect();
    let through = effects_through_camera(w.again, w.ms, seen, &kinds, w.noise_px)?;
    w.through_seen = through;
    Ok(())
}

/// The best physical candidates walked again ([`walk_best_singles_again`]).
pub(super) fn walk_singles_again(w: &mut Singles) -> Result<(), DiagnoseError> {
    walk_best_singles_again(w.again, w.ms, w.levels, w.baseline, &mut w.fits, w.noise_px)
}
