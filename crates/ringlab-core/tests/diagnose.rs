//! The diagnosis on recordings with a concealed effect (`analysis::diagnose::concealed`: the
//! paper's ring with a random start state and drag, the effect at a random strength within
//! its realistic range, 0.5 px of noise, made by `synth`, the header telling nothing): it must
//! name the effect and lower the misfit; on a recording without one it must say none. One
//! recording each (the first seed, not chosen) to keep the test time short; `ringlab
//! diagnose-bench` runs many per family for the table in `docs/diagnosis.md`. The sample
//! recording: see `cli_diagnose.rs`.

use ringlab_core::analysis::diagnose::concealed::{Family, concealed_recording, family_recording};
use ringlab_core::analysis::diagnose::{
    DiagnoseError, DiagnoseOptions, DiagnoseProgress, DiagnoseStage, Diagnosis, Finding,
    MIN_EXPLAINED, diagnose, explained_share,
};
use ringlab_core::physics::EffectKind;
use ringlab_core::recording::Recording;
use std::sync::Mutex;
use std::sync::atomic::AtomicBool;

const SEED: u64 = 1;
/// The pixel noise the concealed recordings are made with.
const NOISE_PX: f64 = 0.5;

/// The diagnosis of the bench's recording `seed` of the pair family `a + b`.
fn diagnose_pair(a: EffectKind, b: EffectKind, seed: u64) -> Diagnosis {
    let rec = family_recording(Family::Pair(a, b), seed).expect("a concealed pair");
    diagnose(&rec, &DiagnoseOptions::default(), &|_| {}, &AtomicBool::new(false))
        .expect("a diagnosis")
}

/// That the effects named are `expected` (by name), with the diagnosis's words where not.
fn assert_named(d: &Diagnosis, expected: &[EffectKind]) {
    let mut named = d.finding.named().to_vec();
    named.sort_by_key(|k| k.name());
    assert_eq!(named, expected, "{}", d.explanation);
}

/// The diagnosis of the concealed recording of `kind`, the strength concealed, and the
/// progress messages it sent.
fn run(kind: EffectKind) -> (Diagnosis, f64, Vec<String>) {
    let (rec, truth) = concealed_recording(kind, SEED).expect("a concealed recording");
    assert!(rec.header.extra.is_empty(), "the header must not tell");
    let (d, messages) = diagnose_with_messages(&rec);
    (d, truth.strength, messages)
}

/// The diagnosis of `rec` and the progress messages it sent.
fn diagnose_with_messages(rec: &Recording) -> (Diagnosis, Vec<String>) {
    diagnose_with_options_and_messages(rec, &DiagnoseOptions::default())
}

/// The diagnosis of `rec` with `opts` and the progress messages it sent.
fn diagnose_with_options_and_messages(
    rec: &Recording,
    opts: &DiagnoseOptions,
) -> (Diagnosis, Vec<String>) {
    let messages = Mutex::new(Vec::new());
    let d = diagnose(
        rec,
        opts,
        &|p: &DiagnoseProgress| messages.lock().unwrap().push(p.message.clone()),
        &AtomicBool::new(false),
    )
    .expect("a diagnosis");
    (d, messages.into_inner().unwrap())
}

/// What every diagnosis must hold, whatever it names. The noise is estimated from each mark's
/// track alone, so a lens does not move it (it did when it came from the marks' circle).
fn consistent(d: &Diagnosis, lens: bool) {
    assert_eq!(
        d.candidates.len(),
        EffectKind::ALL.len(),
        "every effect and the baseline are ranked"
    );
    assert!(d.candidates.windows(2).all(|w| w[0].score <= w[1].score), "ranked by score");
    let none =
        d.candidates.iter().find(|c| c.effect == EffectKind::None).expect("the baseline is ranked");
    assert_eq!(none.delta_score, 0.0);
    assert!(
        (none.rms_px - d.before.rms_px).abs() < 1e-12,
        "the ranking and 'before' are the same misfit"
    );
    assert_eq!(
        d.before.residual_count, d.after.residual_count,
        "before and after over the same residuals"
    );
    assert!(d.after.rms_px <= d.before.rms_px + 1e-9);
    let n = d.frames_fitted;
    assert_eq!(
        (d.residuals.t_s.len(), d.residuals.before_px.len(), d.residuals.after_px.len()),
        (n, n, n)
    );
    assert_eq!((d.trace.before_px.len(), d.trace.after_px.len(), d.trace.data_px.len()), (n, n, n));
    assert_eq!(d.residuals.window_s.len(), d.residuals.window_before_px.len());
    let noise_ok = (d.noise_px - NOISE_PX).abs() < if lens { 0.04 } else { 0.03 };
    assert!(d.noise_from_marks && noise_ok, "noise {}", d.noise_px);
    assert!(!d.explanation.is_empty());
    // A candidate whose whole-run path stopped early says where, and claims no uncertainty.
    for c in d.candidates.iter().filter(|c| c.stopped_at_segments.is_some()) {
        assert!(c.stopped_at_segments.is_some_and(|n| n > 1), "{c:?}");
        assert!(
            c.effect != d.finding.first() && c.strength.is_none_or(|s| s.1.is_infinite()),
            "{c:?}"
        );
    }
    if let Some(m) = &d.mismatch {
        let (t0, t1) = (d.residuals.t_s[0], d.residuals.t_s[n - 1]);
        assert!(
            m.start_s >= t0 && m.end_s <= t1 + 1.0 / d.fps + 1e-9 && m.start_s < m.end_s,
            "{m:?} outside {t0}..{t1}"
        );
    }
}

/// `to_noise`: the improved model must also reach the recording's noise and the concealed
/// strength (every effect now: slip too, since its fit also starts inside mu's range).
fn names(kind: EffectKind, to_noise: bool) -> Vec<String> {
    let (d, truth, messages) = run(kind);
    consistent(&d, kind == EffectKind::CameraDistortion);
    assert_eq!(
        d.finding.first(),
        kind,
        "concealed {kind} at {truth}; diagnosis: {}",
        d.explanation
    );
    // The effect found and most of the misfit beyond the noise gone (not "2x lower": a lens
    // of the realistic range leaves the baseline at 0.79 px for 0.5 px of noise, where 2x
    // cannot be had), then the misfit down to the noise and the strength the one concealed.
    let share = explained_share(d.before.rms_px, d.after.rms_px, NOISE_PX);
    assert!(share > 0.75, "{kind}: {} -> {} px explains {share}", d.before.rms_px, d.after.rms_px);
    let mismatch = d.mismatch.as_ref().expect("where the baseline departs");
    assert!(mismatch.rms_px > d.noise_px, "{mismatch:?}");
    assert!(d.explanation.contains(kind.name()) || d.explanation.contains("Left out"));
    if !to_noise {
        return messages;
    }
    assert!(
        d.after.rms_px < 1.1 * NOISE_PX,
        "{kind}: left {} px for noise {NOISE_PX}",
        d.after.rms_px
    );
    let (value, sigma) = d.after.strength.expect("a fitted strength");
    assert!(sigma.is_finite() && sigma > 0.0);
    assert!(
        (value - truth).abs() < 0.05 * truth.abs() + 5.0 * sigma,
        "{kind}: {value} +- {sigma}, concealed {truth}"
    );
    messages
}

#[test]
fn names_reynolds_drag() {
    names(EffectKind::ReynoldsDrag, true);
}

#[test]
fn names_rolling_friction() {
    names(EffectKind::RollingFriction, true);
}

#[test]
fn names_pivot_friction() {
    // Pivot friction's first walk settles this recording, so no candidate is fitted again
    // (before, the lens and the pinhole were, through their cameras, and two physical effects
    // walked again: a third of the diagnosis's time).
    let messages = names(EffectKind::PivotFriction, true);
    let again: Vec<&String> = messages.iter().filter(|m| m.contains("fitting again")).collect();
    assert!(again.is_empty(), "{again:?}");
}

#[test]
fn names_slip() {
    // From the scan's pick alone (no sliding) it stopped at 4.5 px here; from the middle of
    // mu's range it reaches the noise and mu.
    names(EffectKind::Slip, true);
}

#[test]
fn names_translational_drag() {
    names(EffectKind::TranslationalDrag, true);
}

#[test]
fn names_camera_distortion() {
    names(EffectKind::CameraDistortion, true);
}

#[test]
fn says_none_without_an_effect_and_reports_its_progress() {
    let (rec, _) = concealed_recording(EffectKind::None, SEED).unwrap();
    let seen = Mutex::new(Vec::new());
    let d = diagnose(
        &rec,
        &DiagnoseOptions::default(),
        &|p: &DiagnoseProgress| seen.lock().unwrap().push((p.stage, p.fraction)),
        &AtomicBool::new(false),
    )
    .unwrap();
    consistent(&d, false);
    assert_eq!(d.finding, ringlab_core::analysis::diagnose::Finding::Nothing, "{}", d.explanation);
    assert_eq!(d.after.rms_px, d.before.rms_px);
    assert!(d.mismatch.is_none() && d.windows.is_empty(), "{:?}", d.mismatch);
    assert!(d.before.rms_px < 1.05 * d.noise_px);
    assert!(d.candidates.iter().all(|c| c.delta_score > -d.evidence), "{:?}", d.candidates);
    // Slip does not nest this baseline (its rolling run needs more friction than any `mu`
    // allows): its path ends at its first stage, not in a blind refit over the whole run.
    let slip = d.candidates.iter().find(|c| c.effect == EffectKind::Slip).expect("slip ranked");
    assert!(slip.stopped_at_segments.is_some(), "{slip:?}");
    let seen = seen.into_inner().unwrap();
    assert!(seen.iter().all(|(_, f)| (0.0..=1.0).contains(f)));
    assert!(matches!(seen.first(), Some((DiagnoseStage::BaselineFit(_), _))));
    assert!(seen.iter().any(|(s, _)| *s == DiagnoseStage::Candidates));
    assert_eq!(seen.last().map(|s| s.0), Some(DiagnoseStage::Explain));
}

#[test]
fn cancelling_and_bad_input_are_errors() {
    let (rec, _) = concealed_recording(EffectKind::None, SEED).unwrap();
    let cancelled = diagnose(&rec, &DiagnoseOptions::default(), &|_| {}, &AtomicBool::new(true));
    assert!(matches!(cancelled, Err(DiagnoseError::Cancelled)), "{cancelled:?}");
    let opts = DiagnoseOptions { evidence: f64::NAN, ..DiagnoseOptions::default() };
    assert!(matches!(
        diagnose(&rec, &opts, &|_| {}, &AtomicBool::new(false)),
        Err(DiagnoseError::Options(_))
    ));
    let short = ringlab_core::recording::Recording { frames: rec.frames[..20].to_vec(), ..rec };
    let e = diagnose(&short, &DiagnoseOptions::default(), &|_| {}, &AtomicBool::new(false))
        .unwrap_err();
    assert!(e.to_string().contains("too few frames"), "{e}");
}

#[test]
fn cancelling_while_the_fits_through_a_camera_run_stops_them() {
    // The fits through the camera the segments see run as a queue on every thread, each with
    // its own stop flag; the caller's cancel, set seconds into them (seed 12: they take about
    // ten), must reach them, not be lost there.
    use std::sync::atomic::Ordering;
    let rec = family_recording(Family::Pair(EffectKind::Slip, EffectKind::CameraPerspective), 12)
        .expect("a concealed pair");
    let (cancel, reached) = (AtomicBool::new(false), AtomicBool::new(false));
    let r = std::thread::scope(|scope| {
        scope.spawn(|| {
            while !reached.load(Ordering::SeqCst) && !cancel.load(Ordering::SeqCst) {
                std::thread::sleep(std::time::Duration::from_millis(10));
            }
            std::thread::sleep(std::time::Duration::from_secs(4));
            cancel.store(true, Ordering::SeqCst);
        });
        let progress = |p: &DiagnoseProgress| {
            if p.message.contains("every effect through the camera the segments see") {
                reached.store(true, Ordering::SeqCst);
            }
        };
        let r = diagnose(&rec, &DiagnoseOptions::default(), &progress, &cancel);
        cancel.store(true, Ordering::SeqCst);
        r
    });
    assert!(reached.load(Ordering::SeqCst), "the fits through the camera were never reached");
    assert!(matches!(r, Err(DiagnoseError::Cancelled)), "{:?}", r.map(|d| d.finding));
}

#[test]
fn a_path_that_fits_worse_than_its_ceiling_stops_there() {
    // `fit_path`'s ceiling (a candidate far worse than the baseline at as many segments ends
    // its path): with a ceiling of zero the path stops after its first stage, and what it
    // returns is that stage's model run over the whole span from its first state, without
    // uncertainties; with none it walks down to one segment.
    use ringlab_core::analysis::diagnose::whole::{fit_path, no_ceiling, with_effect};
    use ringlab_core::analysis::fit::{FitOptions, fit};
    let (rec, _) = concealed_recording(EffectKind::None, SEED).expect("a concealed recording");
    let cancel = AtomicBool::new(false);
    let base = fit(&rec, &FitOptions::default(), &|_| {}, &cancel).expect("a fit");
    let ms = base.shooting(&rec.frames, &cancel);
    let sh = with_effect(&ms, EffectKind::None);
    let g = sh.spec.to_internal(&sh.spec.initial_values());
    let span = ms.segments[0].start..ms.segments[ms.segments.len() - 1].end;
    let (stopped, levels) =
        fit_path(&sh, g.clone(), &base.segment_states, &|_| 0.0, &mut |_, _| {}).expect("a path");
    assert_eq!(levels.len(), 1, "stopped after the first stage");
    assert_eq!(stopped.span, span);
    assert!(
        stopped.cost.is_finite() && stopped.cost > levels[0].cost,
        "one run over the whole span fits worse than the segments"
    );
    assert!(stopped.c_sigma.iter().all(|s| s.is_infinite()));
    let (whole, all) =
        fit_path(&sh, g, &base.segment_states, &no_ceiling, &mut |_, _| {}).expect("a path");
    assert_eq!(all.last().map(|l| l.segments.len()), Some(1));
    assert_eq!(whole.span, span);
    assert!(whole.rms_px() < 0.6 && whole.cost < stopped.cost, "{} px", whole.rms_px());
    assert!(whole.c_sigma.iter().all(|s| s.is_finite()));
}

/// Reynolds drag beside pivot friction (the bench's `pair:reynolds_drag+pivot_friction`, seed
/// 3, chosen because it shows this): alone, Reynolds drag explains a third of the baseline's
/// excess (the baseline's drag absorbs the rest), too little to be named alone (half). The
/// forward selection pairs the best one with every other candidate, and names both.
#[test]
fn a_pair_whose_second_effect_explains_little_alone_is_named() {
    let d = diagnose_pair(EffectKind::ReynoldsDrag, EffectKind::PivotFriction, 3);
    let reynolds =
        d.candidates.iter().find(|c| c.effect == EffectKind::ReynoldsDrag).expect("ranked");
    let share = explained_share(d.before.rms_px, reynolds.rms_px, d.noise_px);
    assert!(
        share < MIN_EXPLAINED,
        "Reynolds drag alone must be too weak to name here, else this test shows nothing: {share}"
    );
    assert_named(&d, &[EffectKind::PivotFriction, EffectKind::ReynoldsDrag]);
    assert!(d.after.rms_px < 1.1 * NOISE_PX, "left {} px", d.after.rms_px);
}

/// Reynolds drag beside pivot friction (the bench's `pair:reynolds_drag+pivot_friction`, seed
/// 13, chosen because it shows this): Reynolds drag alone leaves 1.42 px against 0.51 px of
/// noise, and the pair walked from the baseline's path ended worse than that (2.37 px), so the
/// answer was `unexplained`. Pivot friction added to Reynolds drag's own solution reaches the
/// noise, and both are named.
#[test]
fn a_pair_is_fitted_from_where_its_better_effect_alone_ended() {
    let d = diagnose_pair(EffectKind::ReynoldsDrag, EffectKind::PivotFriction, 13);
    let reynolds =
        d.candidates.iter().find(|c| c.effect == EffectKind::ReynoldsDrag).expect("ranked");
    assert!(
        reynolds.rms_px > 2.0 * d.noise_px,
        "Reynolds drag alone must leave a misfit, else this test shows nothing: {} px",
        reynolds.rms_px
    );
    assert_named(&d, &[EffectKind::PivotFriction, EffectKind::ReynoldsDrag]);
    assert!(d.after.rms_px < 1.05 * d.noise_px, "left {} px", d.after.rms_px);
}

/// A pinhole camera beside translational drag (the bench's
/// `pair:translational_drag+camera_perspective`, seed 1, chosen because it shows this): the
/// pinhole alone fits at the wrong distance and translational drag alone hardly at all, and the
/// pair walked from the baseline's path (segments fitted through the orthographic camera)
/// keeps the drag at zero. Fitted through the camera the pinhole found, the drag shows, and
/// both are named at the noise.
#[test]
fn a_physical_effect_hidden_behind_a_pinhole_is_found_through_its_camera() {
    let d = diagnose_pair(EffectKind::TranslationalDrag, EffectKind::CameraPerspective, 1);
    let drag =
        d.candidates.iter().find(|c| c.effect == EffectKind::TranslationalDrag).expect("ranked");
    // Alone, even refitted from across its range, the drag leaves most of the excess (2.34 of
    // 2.64 px against 0.50 px of noise).
    assert!(
        explained_share(d.before.rms_px, drag.rms_px, d.noise_px) < 0.5
            && drag.rms_px > 4.0 * d.noise_px,
        "translational drag alone must explain little here, else this test shows nothing: {} px",
        drag.rms_px
    );
    assert_named(&d, &[EffectKind::CameraPerspective, EffectKind::TranslationalDrag]);
    assert!(d.after.rms_px < 1.1 * NOISE_PX, "left {} px", d.after.rms_px);
}

/// A pinhole whose distance the missing drag hides from every whole-run fit (the bench's
/// `pair:translational_drag+camera_perspective`, seed 7, drawn at 336.9 mm, chosen because it
/// shows this): the pinhole alone fits as 378 mm over the whole run and the drag through that
/// camera stays at 1.7 px, so the answer was `unexplained`. The baseline's segments, refitted
/// with the camera free, see 337 mm, and through that camera both are named at the noise.
#[test]
fn a_pinhole_the_drag_hides_from_the_whole_run_is_found_through_the_camera_the_segments_see() {
    let d = diagnose_pair(EffectKind::TranslationalDrag, EffectKind::CameraPerspective, 7);
    assert_named(&d, &[EffectKind::CameraPerspective, EffectKind::TranslationalDrag]);
    assert!(d.after.rms_px < 1.05 * d.noise_px, "left {} px", d.after.rms_px);
    let distance = d.after.camera.distance_mm.expect("a pinhole");
    assert!((distance / 336.89 - 1.0).abs() < 0.01, "{distance} mm");
}

/// A pinhole with a lens (the bench's `pair:camera_distortion+camera_perspective`, seed 4,
/// chosen because it shows this): the pinhole alone, fitted through a lens it does not know,
/// leaves several noise levels, and the pair walked from the baseline's path ends worse still.
/// Fitted through the camera the pinhole found, the lens shows, and both are named at the noise.
#[test]
fn a_lens_beside_a_pinhole_is_found_through_the_pinhole() {
    let d = diagnose_pair(EffectKind::CameraDistortion, EffectKind::CameraPerspective, 4);
    let pinhole =
        d.candidates.iter().find(|c| c.effect == EffectKind::CameraPerspective).expect("ranked");
    assert!(
        pinhole.rms_px > 3.0 * NOISE_PX,
        "the pinhole alone must leave several noise levels, else this test shows nothing: {} px",
        pinhole.rms_px
    );
    assert_named(&d, &[EffectKind::CameraDistortion, EffectKind::CameraPerspective]);
    assert!(d.after.rms_px < 1.1 * NOISE_PX, "left {} px", d.after.rms_px);
}

/// Rolling friction withheld from the candidates (the bench's `withheld:rolling_friction`,
/// seed 1, chosen because it shows this): pivot friction imitates it in part, removing most of
/// the squared excess but leaving several noise levels. Naming it would name an effect that is
/// not there; the diagnosis must say `unexplained` with pivot friction as the partial answer.
#[test]
fn an_effect_withheld_and_imitated_in_part_is_unexplained() {
    let family = Family::Withheld(EffectKind::RollingFriction);
    let rec = family_recording(family, 1).expect("a concealed recording");
    let opts = DiagnoseOptions { candidates: family.candidates(), ..DiagnoseOptions::default() };
    let d = diagnose(&rec, &opts, &|_| {}, &AtomicBool::new(false)).expect("a diagnosis");
    let pivot =
        d.candidates.iter().find(|c| c.effect == EffectKind::PivotFriction).expect("ranked");
    let share = explained_share(d.before.rms_px, pivot.rms_px, d.noise_px);
    assert!(
        share > 0.5 && pivot.delta_score < -100.0,
        "pivot friction must explain most of the excess by the share alone, else this test shows nothing: {share}"
    );
    match &d.finding {
        Finding::Unexplained { partial: Some(p) } => {
            assert_eq!(p.effects[0], EffectKind::PivotFriction, "{}", d.explanation);
            assert!(d.excess_px(p.rms_px) > 2.0 * d.noise_px, "{}", d.explanation);
        }
        f => panic!("must be unexplained with a partial candidate, said {f:?}: {}", d.explanation),
    }
    assert!(d.explanation.contains("at most part of the answer"), "{}", d.explanation);
}

/// Translational drag withheld (the bench's `withheld:translational_drag`, seed 4, chosen
/// because it shows this): a lens leads the candidates but explains about a tenth of the
/// excess, and slip did not improve alone. Slip is fitted through a leading camera's view only
/// where that camera explains at least half of the excess; through this lens it was the
/// slowest fit of the diagnosis and never changed an answer. The answer stays `unexplained`.
#[test]
fn slip_is_not_fitted_through_a_leading_camera_that_explains_little() {
    let family = Family::Withheld(EffectKind::TranslationalDrag);
    let rec = family_recording(family, 4).expect("a concealed recording");
    // Without the table's slope, which leads here (a force on the centre of mass as the drag
    // withheld is) and would leave no camera to lead.
    let candidates =
        family.candidates().into_iter().filter(|&k| k != EffectKind::TableSlope).collect();
    let opts = DiagnoseOptions { candidates, ..DiagnoseOptions::default() };
    let (d, messages) = diagnose_with_options_and_messages(&rec, &opts);
    let lead = d.candidates.iter().find(|c| c.effect != EffectKind::None).expect("ranked");
    let slip = d.candidates.iter().find(|c| c.effect == EffectKind::Slip).expect("ranked");
    let share = explained_share(d.before.rms_px, lead.rms_px, d.noise_px);
    assert!(
        lead.effect.is_camera() && lead.delta_score < 0.0 && slip.delta_score >= 0.0,
        "a camera must lead and slip fit no better alone, else this test shows nothing: {:?} {}, slip {}",
        lead.effect,
        lead.delta_score,
        slip.delta_score
    );
    assert!(share < MIN_EXPLAINED, "the lead must explain little: {share}");
    let through: Vec<&String> = messages
        .iter()
        .filter(|m| m.contains("the costly effects through the leading camera"))
        .collect();
    assert!(through.is_empty(), "slip fitted through the leading camera: {through:?}");
    assert!(matches!(d.finding, Finding::Unexplained { .. }), "{}", d.explanation);
}

/// A ring already sliding where the fit begins (the bench's `pair:slip+camera_perspective`,
/// seed 2, chosen because it shows this: its drawn run slides from its first instant to 8.0
/// time units, and the fit starts at the first inner turning point, 1.44). From zero slip there
/// the slide cannot be made (slip alone, even through the drawn camera, ended at 2.0 px and
/// the diagnosis said `unexplained`); with the slip velocity at the start free, the pair is
/// named at the noise and the model begins mid-slide.
#[test]
fn a_slide_in_progress_where_the_fit_begins_is_found() {
    let d = diagnose_pair(EffectKind::Slip, EffectKind::CameraPerspective, 2);
    assert_named(&d, &[EffectKind::CameraPerspective, EffectKind::Slip]);
    assert!(d.after.rms_px < 1.05 * d.noise_px, "left {} px", d.after.rms_px);
    let [along, across] = d.after.model.effects.slip_start_velocity;
    assert!(along.hypot(across) > 1e-3, "no slide in progress: {along}, {across}");
    let mu = d.after.model.effects.slip_mu.expect("slip");
    assert!((mu / 0.283 - 1.0).abs() < 0.02, "mu {mu}");
}

/// A slide that begins seconds after the fit starts (the bench's `single:slip` seed 15: held
/// rolling at the start, `mu` 0.321). Started from the middle of slip's realistic range alone
/// the least squares stopped at `mu` 0.446, where the model lacks the recording's first slides
/// and nothing pulls it down to them (13.8 px, `unexplained`); from the range's low end every
/// slide too many pulls `mu` up to the recording's.
#[test]
fn a_slide_that_begins_after_the_fit_starts_is_found_from_below() {
    let opts = DiagnoseOptions { candidates: vec![EffectKind::Slip], ..DiagnoseOptions::default() };
    assert_slip_found_at_its_mu(15, &opts);
}

/// That `single:slip` recording `seed` is named slip at the noise, `mu` within 1% of the drawn.
fn assert_slip_found_at_its_mu(seed: u64, opts: &DiagnoseOptions) {
    let (rec, truth) = concealed_recording(EffectKind::Slip, seed).expect("a concealed slip");
    let d = diagnose(&rec, opts, &|_| {}, &AtomicBool::new(false)).expect("a diagnosis");
    assert_named(&d, &[EffectKind::Slip]);
    assert!(d.after.rms_px < 1.05 * d.noise_px, "left {} px", d.after.rms_px);
    let mu = d.after.model.effects.slip_mu.expect("slip");
    assert!((mu / truth.strength - 1.0).abs() < 0.01, "mu {mu} for {}", truth.strength);
}

/// A short sliding recording (the bench's `single:slip` seed 7: 383 frames, held start, `mu`
/// 0.260) whose first stage ends unconverged wherever it starts: from the low end of slip's
/// range alone it stops at `mu` 0.282 and the path down to one segment is lost (35 px,
/// `unexplained`); from the middle at 0.272 and a lower cost, and the path reaches the noise.
#[test]
fn a_short_slide_goes_on_from_the_start_that_fits_the_segments_best() {
    assert_slip_found_at_its_mu(7, &DiagnoseOptions::default());
}

/// Slip and a pinhole (the bench's `pair:slip+camera_perspective`, seed 12), where the segments
/// see the pinhole: slip is fitted through that camera before any pair is walked from the
/// baseline's path, settles the recording, and no such pair is fitted (they took 40 s here).
/// The seed was chosen because slip alone fitted worse than the baseline there (13.1 px against
/// 9.8); since its still end is found where the ring stops (1b49f28), its last frames fitted,
/// slip alone fits better (7.4 px against 9.8), and the path through the camera is tested
/// without that case.
#[test]
fn slip_is_fitted_through_the_camera_the_segments_see_before_the_pairs() {
    let rec = family_recording(Family::Pair(EffectKind::Slip, EffectKind::CameraPerspective), 12)
        .expect("a concealed pair");
    let reports = Mutex::new(Vec::new());
    let progress = |p: &DiagnoseProgress| reports.lock().unwrap().push((p.message.clone(), p.pass));
    let d = diagnose(&rec, &DiagnoseOptions::default(), &progress, &AtomicBool::new(false))
        .expect("a diagnosis");
    let reports = reports.into_inner().unwrap();
    let messages: Vec<String> = reports.iter().map(|(m, _)| m.clone()).collect();
    assert!(d.candidates.iter().any(|c| c.effect == EffectKind::Slip), "slip ranked");
    assert_named(&d, &[EffectKind::CameraPerspective, EffectKind::Slip]);
    assert!(d.after.rms_px < 1.05 * d.noise_px, "left {} px", d.after.rms_px);
    // The progress names the plan's pass under way, the bar's message with it.
    let through = "fitting again: every effect through the camera the segments see";
    assert!(
        reports.iter().any(|(m, p)| m == through && *p == Some(through)),
        "{:?}",
        reports.iter().filter_map(|(_, p)| *p).collect::<std::collections::BTreeSet<_>>()
    );
    assert!(reports.iter().all(|(m, p)| p.is_none_or(|p| !m.is_empty() && !p.is_empty())));
    // Slip goes second among the effects through that camera (after the best alone), the
    // camera alone first: once it settles the recording, the rest are not fitted.
    assert!(d.pairs.len() <= 3, "pairs fitted after one settled: {:?}", d.pairs);
    let walked: Vec<&String> = messages.iter().filter(|m| m.contains(" px)")).collect();
    assert!(walked.is_empty(), "pairs walked from the baseline's path: {walked:?}");
}

/// A tracker's scale through a near camera (the film tracker's `px_per_mm_from`), here 1%
/// too large: a pinhole whose marks ride above the table tells the table's scale only through
/// the camera's distance, so the pinhole's fit corrects the scale with it and names the camera
/// at the noise. A scale the header gives without saying so stays as it is.
#[test]
fn a_near_cameras_tracked_scale_is_corrected_with_the_camera() {
    let (mut rec, _) =
        concealed_recording(EffectKind::CameraPerspective, SEED).expect("a concealed recording");
    rec.header.px_per_mm *= 1.01;
    rec.header.extra.push((
        "px_per_mm_from".into(),
        format!("{}, +-0.03, about 440 mm away", ringlab_core::film::NEAR_RING_SCALE),
    ));
    let d = diagnose(&rec, &DiagnoseOptions::default(), &|_| {}, &AtomicBool::new(false))
        .expect("a diagnosis");
    assert_named(&d, &[EffectKind::CameraPerspective]);
    let correction = d
        .after
        .extras
        .iter()
        .find(|x| x.kind == EffectKind::CameraPerspective && x.index == 1)
        .expect("the scale's correction is fitted")
        .value
        .0;
    let truth = 100.0 * (1.0 / 1.01 - 1.0);
    assert!((correction - truth).abs() < 0.1, "{correction}% against {truth}%");
    assert!(d.after.rms_px < 1.1 * d.noise_px, "left {} px", d.after.rms_px);
    assert!(d.explanation.contains("corrected by"), "{}", d.explanation);
}

/// A pinhole 450 mm away and Reynolds drag (the bench's `single:reynolds_drag` seed 1, the
/// path moved towards the image's corner), a lens too weak to tell (`k1` -0.004) and, beside
/// the 0.5 px of white noise, a tracker's drift: AR(1) noise of 0.45 px correlated 0.99 from
/// frame to frame, too long for a tracker's correlation (`noise_correlation`), so that the
/// noise reads white. The segments see the pinhole and the lens, and the three effects fit
/// 1.4% better than the pair; by BIC on every coordinate that is worth the lens's number, but
/// the residual counts as one independent residual in about 80, and on those the lens explains
/// no more than the drift does: the pair is named, each effect with its share of the
/// improvement. (Before the parsimony test the three were named: docs/diagnosis.md.)
#[test]
fn an_effect_the_correlated_noise_explains_as_well_is_not_named() {
    use ringlab_core::analysis::diagnose::concealed::concealed_case;
    use ringlab_core::recording::rng::Rng;
    use ringlab_core::recording::synth::synthesize;
    let (mut case, mut opts, _) = concealed_case(EffectKind::ReynoldsDrag, 1).unwrap();
    (case.initial.x_c, case.initial.y_c) = (4.0, 3.0);
    (opts.camera_distance_mm, opts.lens_k1) = (Some(450.0), -0.004);
    let mut rec = synthesize(&case, &opts).unwrap().recording;
    rec.header.extra.clear();
    let (rho, drift_px) = (0.99, 0.45);
    let mut rng = Rng::new(1 ^ 0x5eed);
    let mut e = [[0.0; 2]; 4];
    for c in e.iter_mut().flatten() {
        *c = drift_px * rng.normal();
    }
    for frame in &mut rec.frames {
        for (mark, e) in frame.iter_mut().zip(&mut e) {
            for c in e.iter_mut() {
                *c = rho * *c + (1.0 - rho * rho).sqrt() * drift_px * rng.normal();
            }
            if let Some(p) = mark.as_mut() {
                (p[0], p[1]) = (p[0] + e[0], p[1] + e[1]);
            }
        }
    }
    let candidates =
        vec![EffectKind::ReynoldsDrag, EffectKind::CameraPerspective, EffectKind::CameraDistortion];
    let opts = DiagnoseOptions { candidates, ..DiagnoseOptions::default() };
    let d = diagnose(&rec, &opts, &|_| {}, &AtomicBool::new(false)).expect("a diagnosis");
    assert!(d.noise_correlation.is_none(), "the drift must read as white noise here");
    assert_named(&d, &[EffectKind::CameraPerspective, EffectKind::ReynoldsDrag]);
    let with_lens = d.pairs.iter().map(|p| p.rms_px).fold(f64::INFINITY, f64::min);
    assert!(with_lens < d.after.rms_px - 0.005, "the three must fit better: {:?}", d.pairs);
    // Each named effect's share of the improvement: the pinhole's is the part the drag
    // alone does not reach, the drag's most of it.
    let shares: Vec<(EffectKind, f64)> = d.shares.iter().map(|s| (s.effect, s.share)).collect();
    assert_eq!(shares.len(), 2, "{shares:?}");
    for s in &d.shares {
        assert!(s.share > 0.0 && s.share <= 1.0, "{shares:?}");
        assert!(s.rms_without_px > d.after.rms_px && s.rms_without_px < d.before.rms_px);
    }
    assert!(d.explanation.contains("share of the improvement"), "{}", d.explanation);
}
