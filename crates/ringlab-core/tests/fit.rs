//! The fit: the sample recording against its truth, synthesized recordings with known
//! parameters (other drag, the other spin, numbered the other way, marks missing, a lens),
//! progress and cancelling.

mod common;

use ringlab_core::analysis::diagnose::{DIAGNOSE_TOLERANCES, SLIP_TOLERANCES};
use ringlab_core::analysis::fit::last_runs::LastRuns;
use ringlab_core::analysis::fit::shooting::{
    NEVER_CANCELLED, PredictedMarks, Prediction, Shooting, StepChoice, predict_with_steps,
};
use ringlab_core::analysis::fit::{
    FitError, FitOptions, FitProgress, FitResult, FitStage, ModelSpec, StartReynolds, fit,
};
use ringlab_core::config::load_preset;
use ringlab_core::physics::integrator::{Tolerances, dp5_along};
use ringlab_core::physics::sample::top_centre;
use ringlab_core::physics::{
    EffectKind, Effects, Model, ReynoldsDrag, RunOptions, Sample, StateVec, TurnKind, paper,
};
use ringlab_core::recording::marks::{MarkGeometry, MarkOrder};
use ringlab_core::recording::synth::{SynthOptions, synthesize};
use ringlab_core::recording::{Camera, Recording, read_recording};
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};

fn run(rec: &Recording, opts: &FitOptions) -> FitResult {
    fit(rec, opts, &|_| {}, &AtomicBool::new(false)).expect("fit")
}

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

fn assert_recovers(r: &FitResult, c: [f64; 3], theta0: f64, phidot0: f64, what: &str) {
    for (i, &c) in c.iter().enumerate() {
        assert!(
            rel(r.c[i], c) < 0.10,
            "{what}: C{} = {} +- {}, truth {c}",
            i + 1,
            r.c[i],
            r.c_sigma[i]
        );
        assert!(
            r.c_sigma[i].is_finite() && r.c_sigma[i] > 0.0,
            "{what}: C{} sigma {}",
            i + 1,
            r.c_sigma[i]
        );
    }
    assert!(
        rel(r.start.theta, theta0) < 0.02,
        "{what}: theta0 = {}, truth {theta0}",
        r.start.theta
    );
    assert!(
        rel(r.start.phi_dot, phidot0) < 0.02,
        "{what}: phidot0 = {}, truth {phidot0}",
        r.start.phi_dot
    );
    // Every recording here has 0.5 px of noise: the misfit is that noise, no more.
    assert!(r.rms_px < 0.55 && r.rms_px > 0.45, "{what}: misfit {} px for noise 0.5 px", r.rms_px);
}

#[test]
fn fits_the_sample_recording() {
    let truth: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(common::test_data("sample-ring.truth.json")).unwrap(),
    )
    .unwrap();
    let c: Vec<f64> = truth["C"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    let rec = read_recording(&common::test_data("sample-ring.csv")).unwrap();
    let stages = Mutex::new(Vec::new());
    let r = fit(
        &rec,
        &FitOptions::default(),
        &|p: &FitProgress| {
            let mut s = stages.lock().unwrap();
            if s.last() != Some(&p.stage) {
                s.push(p.stage);
            }
        },
        &AtomicBool::new(false),
    )
    .unwrap();
    assert_recovers(
        &r,
        [c[0], c[1], c[2]],
        truth["theta0"].as_f64().unwrap(),
        truth["phidot0"].as_f64().unwrap(),
        "sample",
    );
    assert!((r.start.psi_dot - truth["psidot0"].as_f64().unwrap()).abs() < 0.02);
    assert_eq!(r.frames, 1884);
    assert!(r.start_frame.abs() < 0.5, "the sample starts at its first inner turning point");
    // The fitted model, run on from the start, follows the recorded point A for a while.
    let (_, samples) = r.model_run().unwrap();
    let motion = ringlab_core::recording::recover(&rec).unwrap();
    let (l, k) = (r.units.length_mm, rec.header.px_per_mm);
    let ss: f64 = samples
        .iter()
        .take(150)
        .zip(&motion.frames)
        .map(|(s, f)| {
            let a = f.a_mm.unwrap();
            (s.x_a * l - a[0]).powi(2) + (s.y_a * l - a[1]).powi(2)
        })
        .sum();
    let rms_px = (ss / 150.0).sqrt() * k;
    assert!(rms_px < 1.0, "the model's A is {rms_px} px rms from the data's over 150 frames");
    assert_eq!(
        *stages.lock().unwrap(),
        vec![
            FitStage::Recover,
            FitStage::StartState,
            FitStage::Sweep,
            FitStage::Segments,
            FitStage::Refine
        ]
    );
}

#[test]
fn fits_a_synthesized_disk_like_drag() {
    // The paper's disk-like drag (Fig. 4b) on its ring: a different regime, a short run.
    let case = load_preset("paper-disk-drag").unwrap().build().unwrap();
    let s = synthesize(&case, &SynthOptions { seed: 21, ..SynthOptions::default() }).unwrap();
    let r = run(&s.recording, &FitOptions::default());
    assert_recovers(
        &r,
        case.model.c_drag,
        case.initial.theta,
        case.initial.phi_dot,
        "disk-like drag",
    );
}

#[test]
fn fits_the_other_spin_other_numbering_and_missing_marks() {
    let mut f = load_preset("paper-ring").unwrap();
    f.drag.c = [0.05, 0.04, 0.12];
    f.initial.phi_dot = -4.2;
    f.initial.theta = 0.6;
    f.initial.psi_dot = 0.1;
    let case = f.build().unwrap();
    let opts = SynthOptions {
        seed: 22,
        mark_order: MarkOrder::Reverse,
        missing_fraction: 0.08,
        ..SynthOptions::default()
    };
    let s = synthesize(&case, &opts).unwrap();
    let r = run(&s.recording, &FitOptions::default());
    assert_recovers(&r, case.model.c_drag, 0.6, -4.2, "mirrored");
    assert!(r.start.phi_dot < 0.0);
}

/// A film's opening where the ring was lost leaves the recording's first frames empty, and the
/// first turning point after them may be a maximum of theta: the fit starts at the first frame
/// whose state the poses give (it failed before: no start state at frame 0).
#[test]
fn a_recording_whose_first_frames_are_empty_is_fitted_from_the_first_state() {
    let case = load_preset("paper-ring").unwrap().build().unwrap();
    let mut rec =
        synthesize(&case, &SynthOptions { seed: 23, ..SynthOptions::default() }).unwrap().recording;
    let turns = ringlab_core::recording::recover(&rec).unwrap().turning_points;
    let max = turns.iter().find(|p| p.kind == TurnKind::ThetaMax).expect("a maximum of theta");
    let blank = (max.at * 0.7) as usize;
    for f in &mut rec.frames[..blank] {
        *f = [None; 4];
    }
    let r = run(&rec, &FitOptions::default());
    assert!(r.start_frame >= blank as f64, "started at {} of {blank} blank", r.start_frame);
    assert!(r.rms_px < 0.55 && r.rms_px > 0.45, "misfit {} px for noise 0.5 px", r.rms_px);
    for (i, &c) in case.model.c_drag.iter().enumerate() {
        assert!(rel(r.c[i], c) < 0.10, "C{} = {}, truth {c}", i + 1, r.c[i]);
    }
}

#[test]
fn fits_a_lens_distortion_as_a_free_effect() {
    let mut f = load_preset("paper-ring").unwrap();
    f.initial.phi = 1.2;
    let case = f.build().unwrap();
    let k1 = 0.08;
    let s = synthesize(&case, &SynthOptions { seed: 23, lens_k1: k1, ..SynthOptions::default() })
        .unwrap();
    let opts =
        FitOptions { effect: Some((EffectKind::CameraDistortion, 0.0)), ..FitOptions::default() };
    let r = run(&s.recording, &opts);
    let (kind, value, sigma) = r.effect.unwrap();
    assert_eq!(kind, EffectKind::CameraDistortion);
    assert!((value - k1).abs() < 4.0 * sigma + 0.005, "k1 = {value} +- {sigma}, truth {k1}");
    assert_recovers(&r, case.model.c_drag, case.initial.theta, case.initial.phi_dot, "lens");
}

#[test]
fn cancelling_stops_the_fit_and_bad_input_is_an_error() {
    let rec = read_recording(&common::test_data("sample-ring.csv")).unwrap();
    let r = fit(&rec, &FitOptions::default(), &|_| {}, &AtomicBool::new(true));
    assert_eq!(r.unwrap_err(), FitError::Cancelled);
    let short = Recording { frames: rec.frames[..12].to_vec(), ..rec.clone() };
    assert!(matches!(
        fit(&short, &FitOptions::default(), &|_| {}, &AtomicBool::new(false)),
        Err(FitError::TooFewFrames { .. })
    ));
    let opts = FitOptions { segment_frames: 3, ..FitOptions::default() };
    assert!(matches!(
        fit(&rec, &opts, &|_| {}, &AtomicBool::new(false)),
        Err(FitError::Options(_))
    ));
    // Marks thrown at random: an answer or an error, never a panic.
    let mut rng = ringlab_core::recording::rng::Rng::new(3);
    let mut noise = rec.clone();
    noise.frames.truncate(300);
    for f in &mut noise.frames {
        for m in f.iter_mut() {
            *m = Some([rng.uniform() * 1280.0, rng.uniform() * 1024.0]);
        }
    }
    let _ = fit(&noise, &FitOptions::default(), &|_| {}, &AtomicBool::new(false));
    // A recording whose marks never form a pose.
    let mut blind = rec.clone();
    for f in &mut blind.frames {
        f[1] = None;
        f[3] = None;
    }
    assert!(fit(&blind, &FitOptions::default(), &|_| {}, &AtomicBool::new(false)).is_err());
}

#[test]
fn the_projection_sees_the_marks_heights_through_a_pinhole() {
    // The fit's prediction of synthesized marks (noise 0) from the run that made them, through
    // the camera the header describes: orthographic, and pinholes that magnify the marks by
    // their heights (off by pixels if the heights were left out).
    let case = load_preset("paper-ring").unwrap().build().unwrap();
    for (distance, tilt) in [(None, 0.0), (Some(450.0), 0.0), (Some(600.0), 25.0)] {
        let opts = SynthOptions {
            noise_px: 0.0,
            camera_distance_mm: distance,
            camera_tilt_deg: tilt,
            camera_in_header: true,
            ..SynthOptions::default()
        };
        let s = synthesize(&case, &opts).unwrap();
        let rec = &s.recording;
        let camera = Camera::for_recording(&rec.header, &rec.frames);
        let spec = ModelSpec {
            base: case.model.clone(),
            camera,
            free: Vec::new(),
            re_start: StartReynolds { centre: 1.0, rim: 1.0 },
            strength_ranges: Vec::new(),
        };
        let sh = Shooting {
            observed: &rec.frames,
            segments: vec![0..rec.frames.len()],
            dt: 1.0 / opts.fps / s.time_s,
            spec,
            run: RunOptions::default(),
            geometry: MarkGeometry::of_body(&case.model.body, MarkOrder::Forward),
            length_mm: s.length_mm,
            budget: None,
            last_runs: LastRuns::default(),
            cancel: &NEVER_CANCELLED,
        };
        let predicted: PredictedMarks =
            s.samples.iter().map(|x| sh.project(&sh.geometry, &camera, x)).collect();
        let worst = sh.residuals_of(0, &predicted).iter().fold(0.0f64, |m, r| m.max(r.abs()));
        assert!(worst < 0.0051, "{distance:?} mm, {tilt} deg: {worst} px");
        if distance.is_some() {
            let flat = Camera { distance_mm: None, tilt_rad: 0.0, ..camera };
            let predicted: PredictedMarks =
                s.samples.iter().map(|x| sh.project(&sh.geometry, &flat, x)).collect();
            let worst = sh.residuals_of(0, &predicted).iter().fold(0.0f64, |m, r| m.max(r.abs()));
            assert!(
                worst > 5.0,
                "{distance:?} mm, {tilt} deg: orthographic misses by only {worst} px"
            );
        }
    }
}

/// Max over the frames of |forward difference - reference derivative| of the centre's x, and
/// the reference's largest |derivative|.
fn derivative_error(a: &[Sample], b: &[Sample], reference: &[f64], h: f64) -> (f64, f64) {
    let err = a.iter().zip(b).zip(reference).map(|((a, b), d)| ((b.x_a - a.x_a) / h - d).abs());
    (err.fold(0.0, f64::max), reference.iter().fold(0.0, |m, d| m.max(d.abs())))
}

#[test]
fn runs_that_follow_a_kept_runs_steps_difference_smoothly() {
    // A forward difference of two adaptive runs carries the tolerance's jitter over the step;
    // the perturbed run taken at the kept run's step ends differs smoothly (steps.rs).
    let model = paper::ring_model(paper::C_RING);
    let with_reynolds = |n: f64| {
        let mut m = model.clone();
        m.effects.reynolds_drag =
            Some(ReynoldsDrag { re_ref: 500.0, exponent: n, max_factor: 10.0, rim_share: 0.0 });
        m
    };
    let y0 = paper::initial().to_state();
    let (dt, frames) = (0.01, 0..800);
    let opts = |tol: Tolerances| RunOptions { tol, ..RunOptions::default() };
    let run = |m: &Model, opts: &RunOptions, choice| {
        predict_with_steps(m, opts, dt, &y0, frames.clone(), choice)
    };
    // The Reynolds exponent from the paper's drag (0) by 1e-6, its derivative from runs at
    // 1e-13.
    let h = 1e-6;
    let m1 = with_reynolds(h);
    let tight = opts(Tolerances { rtol: 1e-13, atol: 1e-15 });
    let t0 = run(&model, &tight, StepChoice::Adaptive).samples.expect("a run");
    let t1 = run(&m1, &tight, StepChoice::Adaptive).samples.expect("a run");
    let reference: Vec<f64> = t0.iter().zip(&t1).map(|(a, b)| (b.x_a - a.x_a) / h).collect();
    // The errors of the followed and of the adaptive difference at `loose`, and the size.
    let errors = |loose: &RunOptions| {
        let kept = run(&model, loose, StepChoice::Keep);
        let ends: Arc<[f64]> = Arc::from(kept.step_ends.clone());
        assert_eq!(ends.len() as u64, kept.steps);
        let base = kept.samples.expect("the paper's run");
        // Followed at the same parameters, the same run.
        let follow = |m: &Model| {
            predict_with_steps(m, loose, dt, &y0, frames.clone(), StepChoice::Follow(&ends))
                .samples
                .expect("a run")
        };
        let same = follow(&model);
        let moved = base.iter().zip(&same).map(|(a, b)| (a.x_a - b.x_a).abs()).fold(0.0, f64::max);
        assert!(moved < 1e-12, "{moved}");
        let followed = follow(&m1);
        let adaptive = run(&m1, loose, StepChoice::Adaptive).samples.expect("a run");
        let (e_followed, size) = derivative_error(&base, &followed, &reference, h);
        let (e_adaptive, _) = derivative_error(&base, &adaptive, &reference, h);
        assert!(size > 0.5, "the exponent moves the path: {size}");
        (e_followed, e_adaptive, size)
    };
    let (e_followed, e_adaptive, size) = errors(&opts(Tolerances { rtol: 1e-8, atol: 1e-10 }));
    assert!(e_followed < 1e-3 * size, "followed: {e_followed} of {size}");
    assert!(e_adaptive > 10.0 * e_followed, "adaptive {e_adaptive}, followed {e_followed}");
    // At the diagnosis's own tolerance the followed difference is as good (an adaptive one
    // there is right or wrong by the luck of its steps).
    let (e_followed, _, size) = errors(&opts(DIAGNOSE_TOLERANCES));
    assert!(
        e_followed < 1e-3 * size,
        "followed at the diagnosis's tolerance: {e_followed} of {size}"
    );
}

#[test]
fn a_fifth_order_run_along_the_kept_steps_differences_within_a_percent() {
    // The least squares' integrated columns of a rolling run are runs of Dormand and Prince's
    // fifth-order formula along the kept run's steps, differenced against that formula's own
    // run at the point (`dp5_along`): half of DOP853's work a step. Their derivative, the
    // Reynolds exponent moved from 0 by 1e-6 over 8 s of the paper's ring, against runs at
    // 1e-13.
    let model = paper::ring_model(paper::C_RING);
    let mut m1 = model.clone();
    let h = 1e-6;
    m1.effects.reynolds_drag =
        Some(ReynoldsDrag { re_ref: 500.0, exponent: h, max_factor: 10.0, rim_share: 0.0 });
    let y0 = paper::initial().to_state();
    let (dt, n) = (0.01, 800);
    let run = |m: &Model, tol: Tolerances, choice| {
        let opts = RunOptions { tol, ..RunOptions::default() };
        predict_with_steps(m, &opts, dt, &y0, 0..n, choice)
    };
    let tight = Tolerances { rtol: 1e-13, atol: 1e-15 };
    let t0 = run(&model, tight, StepChoice::Adaptive).samples.expect("a run");
    let t1 = run(&m1, tight, StepChoice::Adaptive).samples.expect("a run");
    let reference: Vec<f64> = t0.iter().zip(&t1).map(|(a, b)| (b.x_a - a.x_a) / h).collect();
    let size = reference.iter().fold(0.0, |m: f64, d| m.max(d.abs()));
    assert!(size > 0.5, "the exponent moves the path: {size}");
    let kept = run(&model, DIAGNOSE_TOLERANCES, StepChoice::Keep);
    let ends: Arc<[f64]> = Arc::from(kept.step_ends.clone());
    let along = |m: &Model| -> Vec<f64> {
        let (states, steps) = dp5_along(m, 0.0, y0, &ends, dt, n).expect("a run along the ends");
        assert!(steps <= kept.steps);
        states.iter().map(|y| top_centre(&m.body, y).0).collect()
    };
    let (a, b) = (along(&model), along(&m1));
    let e_along = a
        .iter()
        .zip(&b)
        .zip(&reference)
        .map(|((a, b), d)| ((b - a) / h - d).abs())
        .fold(0.0, f64::max);
    let base = kept.samples.expect("the paper's run");
    let followed = run(&m1, DIAGNOSE_TOLERANCES, StepChoice::Follow(&ends)).samples.expect("a run");
    let (e_followed, _) = derivative_error(&base, &followed, &reference, h);
    // Measured: 0.8% of the size along, 0.05% followed. Coarser, so the fits finish on
    // DOP853's columns where their misfit is compared (`lm::LmOptions::exact_finish`).
    assert!(e_followed < 1e-3 * size, "followed: {e_followed} of {size}");
    assert!(e_along < 1.5e-2 * size, "along: {e_along} of {size}");
}

#[test]
fn sliding_runs_difference_smoothly_at_the_slip_tolerances() {
    // A sliding run switches between rolling and sliding; followed at the diagnosis's rolling
    // tolerance its difference in mu erred by 1.1e-3 and 2.5e-3 of its size (mu 0.25, 0.35),
    // so slip's fits run at SLIP_TOLERANCES.
    let with_mu = |mu: f64| {
        let m = paper::ring_model(paper::C_RING);
        let e = Effects { slip_mu: Some(mu), ..m.effects };
        m.with_effects(e).expect("a valid mu")
    };
    let y0 = paper::initial().to_state();
    let h = 1e-6;
    fn run(m: &Model, tol: Tolerances, y0: &StateVec, choice: StepChoice) -> Prediction {
        let opts = RunOptions { tol, ..RunOptions::default() };
        predict_with_steps(m, &opts, 0.01, y0, 0..1200, choice)
    }
    let tight = Tolerances { rtol: 1e-12, atol: 1e-14 };
    for mu in [0.25, 0.35] {
        let (m0, m1) = (with_mu(mu), with_mu(mu + h));
        let t0 = run(&m0, tight, &y0, StepChoice::Adaptive).samples.expect("a run");
        let t1 = run(&m1, tight, &y0, StepChoice::Adaptive).samples.expect("a run");
        assert!(t0.iter().filter(|s| s.sliding).count() > 100, "mu {mu}: it must slide");
        let reference: Vec<f64> = t0.iter().zip(&t1).map(|(a, b)| (b.x_a - a.x_a) / h).collect();
        let kept = run(&m0, SLIP_TOLERANCES, &y0, StepChoice::Keep);
        let ends: Arc<[f64]> = Arc::from(kept.step_ends.clone());
        let base = kept.samples.expect("a run");
        let followed =
            run(&m1, SLIP_TOLERANCES, &y0, StepChoice::Follow(&ends)).samples.expect("a run");
        let (error, size) = derivative_error(&base, &followed, &reference, h);
        assert!(size > 1.0, "mu {mu}: mu moves the path: {size}");
        assert!(error < 1e-3 * size, "mu {mu}: followed {error} of {size}");
    }
}
