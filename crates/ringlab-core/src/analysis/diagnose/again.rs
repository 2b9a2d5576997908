//! Fits made again from where a first walk ended: a side valley left by walking once more.

use super::candidates::{fit_baseline, fit_candidate, refit_from, with_budget, with_slip_start};
use super::in_order::in_order_until;
use super::options::DiagnoseError;
use super::rules::{CONSISTENT_RATIO, MIN_EXPLAINED, explained_share, settled};
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
/// stage of the path: a pinhole 373 mm away, tilted 6.5 degrees, was left at 5.0 px this way,
/// even from the true camera, and reached the noise (0.502 px, the distance and tilt to 0.02%)
/// from segments fitted through the camera of that first pass. The camera does not change the
/// motion, so the second multiple-shooting fit sees the motion as it was. Only for a camera
/// candidate that leads the candidates or explains at least [`MIN_EXPLAINED`] of the baseline's
/// excess: one that explains less imitates a little of another effect (with physics the
/// candidates lack, every recording has one), and its pass, a multiple-shooting fit and a
/// whole path, bought nothing there (docs/diagnosis.md).
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
        if first.cost >= baseline.cost || first.rms_px() <= CONSISTENT_RATIO * noise_px {
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
/// polishing of the last stage leaves (Reynolds drag with pivot friction: 0.91 px, unchanged
/// after four more rounds of the last stage; walked again, 0.57 px). Walked again up to
/// [`PAIR_WALKS`] times while each walk cuts its misfit by a tenth or more and it still misses
/// beyond the noise: a weak strength grows a little with each walk (translational drag beside
/// a pinhole, 0.085 drawn: 3.83 px at 0.006 after the first walk, 0.73 px at 0.073 after the
/// second). Not walked where it has settled the recording already ([`settled`]).
pub(super) fn walk_best_pair_again(
    again: &Again,
    ms: &Shooting,
    levels: &[Level],
    pairs: &mut [(EffectKind, EffectKind, Result<WholeFit, LmError>)],
    score: &dyn Fn(&WholeFit) -> f64,
    noise_px: f64,
) -> Result<(), DiagnoseError> {
    let Some(p) = best_pair(pairs, score) else { return Ok(()) };
    if settled(p.rms_px(), noise_px) {
        return Ok(());
    }
    for _ in 0..PAIR_WALKS {
        let before = p.cost;
        walk_again(again, ms, levels, p)?;
        if !(p.cost < 0.81 * before) || p.rms_px() <= CONSISTENT_RATIO * noise_px {
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
/// effect's first walk, from the baseline's drag, can end in a side valley too (rolling
/// friction alone at 1.70 px against 0.49 px of noise; walked again, 0.50 px), and then the
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
    todo.retain(|w| w.rms_px() > CONSISTENT_RATIO * noise_px);
    use rayon::prelude::*;
    todo.into_par_iter()
        .map(|w| {
            walk_again(again, ms, levels, w)?;
            if w.rms_px() > CONSISTENT_RATIO * noise_px
                && explained_share(baseline.rms_px(), w.rms_px(), noise_px) < MIN_EXPLAINED
            {
                scan_from_baseline(ms, baseline, w)?;
            }
            Ok(())
        })
        .collect()
}

/// Fit `w` (a physical effect but slip) refitted over the whole run from the baseline's own
/// solution at each of [`scan_strengths`], kept where one ends better. Its walks begin at the
/// strength that suits the baseline's segments best, and where those segments absorb the
/// effect (a tracker's noise correlated in time lends them freedom) that can be near zero, a
/// valley the walks do not leave: translational drag of 0.05 under noise correlated 0.6 frame
/// to frame stayed at 0.004 and 2.03 px against the baseline's 2.04; refitted from 0.01, 0.032
/// and 0.1 it ends at 1.75, 2.61 and 0.53 px (0.0485).
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
    // iterations on the way down (0.534 px after 20; 0.498 px after 10 more).
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
        with_budget(with_effects(&with_slip_start(ms, w.model.effects.slip_start), &kinds));
    sh.segments = vec![w.span.clone()];
    fit_whole(&sh, w.internal.clone(), &[w.start], &mut |_, _| {})
}

/// The strengths [`scan_from_baseline`] starts from: the ends and the middle (geometric) of
/// the effect's realistic range; none for slip (its own starts cover its range, and its runs
/// from the baseline's solution crawl) and the camera effects (fitted again through their
/// camera instead).
fn scan_strengths(kind: EffectKind) -> Vec<f64> {
    if kind == EffectKind::Slip || kind.is_camera() || kind == EffectKind::None {
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
    let sh = with_effects(&with_slip_start(&from, p.model.effects.slip_start), &kinds);
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

/// Slip beside the camera effects of `found` (the camera the segments see, or that of a
/// camera candidate that leads, or of a pair of slip with a camera that still misses), found
/// through that camera. Through the camera the baseline assumed, slip alone does not even
/// reach the baseline: the camera's error fills the first stage's segments and their least
/// squares drive `mu` up until nothing slides (a sliding ring filmed from 500 mm: slip alone
/// 15.7 px against the baseline's 12.7), so the forward selection, which pairs slip only where
/// it improved alone, never tries it; and a pair of slip with the pinhole walked from the
/// baseline's path can end at four times the noise. Even a camera confused by the slides,
/// 311 mm for 500, lets slip reach 1.8 px ([`effects_through_camera`]).
pub(super) fn slip_through_camera(
    again: &Again,
    ms: &Shooting,
    found: &FoundCamera,
    noise_px: f64,
) -> Result<Option<WholeFit>, DiagnoseError> {
    let fits = effects_through_camera(again, ms, found, &[EffectKind::Slip], noise_px)?;
    Ok(fits.into_iter().next())
}

/// Each effect of `asked` beside the camera effects of `found`, found through that camera:
/// the multiple-shooting fit and the baseline's path are made again through the camera found,
/// each effect is fitted on that path as a candidate is, and then the camera is set free
/// beside it for the last stage; `EffectKind::None` among them gives the camera alone
/// fitted that way. A pair walked from the baseline's path starts from segments fitted
/// through the wrong camera and can stay in the camera's valley with the physical effect at
/// zero (a pinhole 640 mm away beside translational drag: the pinhole alone fits as 805 mm and
/// 1.71 px, the pair with the drag stays there; through the 805 mm camera the drag alone
/// reaches 0.70 px). The other camera effect too: a pinhole 346 mm away found through a lens
/// it does not know leaves 1.77 px, and the pair walked from the baseline's path 5.4 px.
///
/// `asked` go most promising first, and those after the first that settles the recording
/// ([`settled`] against `noise_px`) are not fitted: nothing can then be told better. A fit
/// made before through the same camera (`again` keeps them) is not made again.
pub(super) fn effects_through_camera(
    again: &Again,
    ms: &Shooting,
    found: &FoundCamera,
    asked: &[EffectKind],
    noise_px: f64,
) -> Result<Vec<WholeFit>, DiagnoseError> {
    let cameras = &found.numbers;
    // Every effect asked for that the camera does not already hold (the other camera effect
    // too: a real camera is a pinhole with a lens).
    let mut kinds: Vec<EffectKind> = Vec::new();
    for &k in asked {
        if !cameras.iter().any(|(c, _)| *c == k) && !kinds.contains(&k) {
            kinds.push(k);
        }
    }
    if cameras.is_empty() || kinds.is_empty() {
        return Ok(Vec::new());
    }
    let settles = |w: &WholeFit| settled(w.rms_px(), noise_px);
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
        let alone = if kind == EffectKind::None {
            baseline.clone()
        } else {
            fit_candidate(&through, &levels, &baseline, kind, &mut |_, _| {})?
        };
        // Slip that left the baseline's valley even through this camera (its path stopped
        // beyond the ceiling) slides where the recording rolls, or the other way; the camera's
        // numbers move no slide, and its runs cost most (a lens beside slip at 257 px: 8.5 s
        // more to reach 219 px).
        if kind == EffectKind::Slip && alone.stopped_at.is_some() {
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
        let mut sh = with_budget(with_effects(&with_slip_start(&ms, start), &order));
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
