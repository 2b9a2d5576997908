//! The paper's ring against the independent reference solution (`tests/data`).

mod common;

use common::Reference;
use ringlab_core::physics::integrator::Tolerances;
use ringlab_core::physics::{EndReason, RunOptions, Sample, Simulation, paper, simulate};

fn run_paper(dt: f64, rtol: f64) -> (ringlab_core::physics::RunSummary, Vec<Sample>) {
    let opts = RunOptions {
        sample_dt: Some(dt),
        tol: Tolerances { rtol, atol: 1e-12 },
        ..Default::default()
    };
    simulate(paper::ring_model(paper::C_RING), &paper::initial(), opts).expect("runs")
}

#[test]
fn theta_matches_reference_to_1e6_up_to_t50() {
    let r = Reference::load();
    let (t_ref, th_ref) = (r.col("t"), r.col("theta"));
    let (_, samples) = run_paper(0.05, 1e-10);
    let mut worst: f64 = 0.0;
    let mut compared = 0;
    for (t, th) in t_ref.iter().zip(&th_ref).filter(|(t, _)| **t <= 50.0) {
        let k = (t / 0.05).round() as usize;
        let s = &samples[k];
        assert!((s.t - t).abs() < 1e-9, "sample grid off: {} vs {}", s.t, t);
        worst = worst.max((s.theta() - th).abs());
        compared += 1;
    }
    assert!(compared >= 1000, "compared only {compared} rows");
    assert!(worst < 1e-6, "max |theta - reference| for t <= 50 is {worst:e}");
}

#[test]
fn other_columns_match_reference_up_to_t50() {
    let r = Reference::load();
    let (_, samples) = run_paper(0.05, 1e-10);
    let t = r.col("t");
    for (name, get, tol) in [
        ("x_a", (|s: &Sample| s.x_a) as fn(&Sample) -> f64, 1e-6),
        ("y_a", |s: &Sample| s.y_a, 1e-6),
        ("w3", |s: &Sample| s.y[5], 1e-6),
        ("f_f", |s: &Sample| s.f_f, 1e-5),
        ("f_n", |s: &Sample| s.f_n, 1e-5),
        ("energy", |s: &Sample| s.energy, 1e-7),
    ] {
        let col = r.col(name);
        let worst = t
            .iter()
            .zip(&col)
            .filter(|(t, _)| **t <= 50.0)
            .map(|(t, v)| (get(&samples[(t / 0.05).round() as usize]) - v).abs())
            .fold(0.0, f64::max);
        assert!(worst < tol, "{name}: max deviation {worst:e} > {tol:e}");
    }
}

#[test]
fn end_time_matches_reference_to_0_1_percent() {
    let r = Reference::load();
    let t_ref = r.end_time();
    for rtol in [1e-8, 1e-10, 1e-12] {
        let (summary, _) = run_paper(0.05, rtol);
        assert_eq!(summary.end_reason, EndReason::Flat);
        let rel = (summary.t_end - t_ref).abs() / t_ref;
        assert!(rel < 1e-3, "rtol {rtol}: end {} vs reference {t_ref} ({rel:e})", summary.t_end);
        let theta_end = summary.final_sample.theta();
        assert!((theta_end - (std::f64::consts::FRAC_PI_2 - 0.02)).abs() < 1e-9);
    }
}

#[test]
fn dense_output_is_right_at_coarse_and_fine_spacing() {
    // PHYSICS.md: a dense output that is wrong across steps gave theta(20) = 1.47501 at
    // spacing 1.0 instead of 1.40569.
    let r = Reference::load();
    let t = r.col("t");
    let th = r.col("theta");
    let k20 = t.iter().position(|&x| (x - 20.0).abs() < 1e-9).expect("t = 20 in reference");
    for dt in [0.01, 0.05, 1.0, 2.5] {
        let (_, samples) = run_paper(dt, 1e-10);
        let s = samples.iter().find(|s| (s.t - 20.0).abs() < 1e-9).expect("sample at t = 20");
        assert!(
            (s.theta() - th[k20]).abs() < 1e-7,
            "dt {dt}: theta(20) = {} vs {}",
            s.theta(),
            th[k20]
        );
    }
}

#[test]
fn theta_first_reaches_1_5_at_48_163() {
    let (_, samples) = run_paper(0.001, 1e-10);
    let first = samples
        .windows(2)
        .find(|w| w[0].theta() < 1.5 && w[1].theta() >= 1.5)
        .expect("theta reaches 1.5");
    let (a, b) = (&first[0], &first[1]);
    let t = a.t + (1.5 - a.theta()) / (b.theta() - a.theta()) * (b.t - a.t);
    assert!((t - 48.163).abs() < 2e-3, "theta first reaches 1.5 at {t}");
}

#[test]
fn lift_off_found_early_as_in_the_reference() {
    // The reference finds F_N < 0 for t in about [0.14, 1.77].
    let (summary, _) = run_paper(0.05, 1e-10);
    let lift = &summary.lift_off;
    assert!(!lift.is_empty(), "no lift-off found");
    assert!((lift[0].start - 0.14).abs() < 0.02, "first lift-off starts at {}", lift[0].start);
    let last = lift.last().expect("one");
    assert!((last.end - 1.77).abs() < 0.02, "last lift-off ends at {}", last.end);
    assert!(lift.iter().all(|i| i.end < 2.0), "lift-off after t = 2: {lift:?}");
    // Slip is reported too (it includes every lift-off interval).
    for i in lift {
        assert!(
            summary.slip.iter().any(|s| s.start <= i.start && s.end >= i.end),
            "lift-off {i:?} not within slip"
        );
    }
}

#[test]
fn streaming_in_slices_gives_the_same_samples() {
    // The live view advances the run in small slices; the samples must not depend on that.
    let opts = RunOptions { sample_dt: Some(0.05), ..Default::default() };
    let (_, whole) =
        simulate(paper::ring_model(paper::C_RING), &paper::initial(), opts.clone()).expect("runs");
    let mut sim =
        Simulation::new(paper::ring_model(paper::C_RING), &paper::initial(), opts).expect("starts");
    let mut sliced = Vec::new();
    let mut t = 0.0;
    while sim.advance(t, &mut |s| sliced.push(*s)).is_none() {
        t += 0.37;
    }
    assert_eq!(whole.len(), sliced.len());
    for (a, b) in whole.iter().zip(&sliced) {
        assert_eq!(a.t, b.t);
        assert_eq!(a.theta(), b.theta());
    }
}
