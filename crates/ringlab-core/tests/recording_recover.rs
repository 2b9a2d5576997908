//! Motion recovery against the sample's truth, regenerated with the physics core: point A,
//! the angles, `v_p` and the turning points agree with the truth within their stated
//! uncertainties.

mod common;
mod truth;

use ringlab_core::physics::TurnKind;
use ringlab_core::recording::marks::MarkOrder;
use ringlab_core::recording::{read_recording, recover};
use std::f64::consts::PI;

fn wrap(x: f64) -> f64 {
    (x + PI).rem_euclid(2.0 * PI) - PI
}

/// RMS of z-scores and the fraction beyond 4 sigma.
fn z_stats(z: &[f64]) -> (f64, f64) {
    let rms = (z.iter().map(|x| x * x).sum::<f64>() / z.len() as f64).sqrt();
    (rms, z.iter().filter(|x| x.abs() > 4.0).count() as f64 / z.len() as f64)
}

#[test]
fn recovers_the_sample_motion_within_its_uncertainties() {
    let t = truth::load();
    let rec = read_recording(&common::test_data("sample-ring.csv")).unwrap();
    let m = recover(&rec).unwrap();
    let mm = t.units.length_mm;
    let (l, ts) = (mm, t.units.time_s);

    // The noise, the numbering, the spin, the start and the still end.
    let noise = m.noise_px.unwrap();
    assert!((noise - 0.5).abs() < 0.05, "noise {noise} px (truth 0.5)");
    assert_eq!(m.mark_order, MarkOrder::Forward);
    assert_eq!(m.spin_sign, 1.0);
    assert_eq!(m.first_inner_turn.unwrap().at, 0.0, "the sample starts at an inner turning point");
    let rest = m.rest_from.unwrap();
    assert!((1822..=1825).contains(&rest), "rest from frame {rest} (truth: 1824)");

    let moving = (t.t_end / (1.0 / 300.0 / ts)).floor() as usize;
    let (mut za, mut ztheta, mut zphi, mut zpsi, mut zv) = (vec![], vec![], vec![], vec![], vec![]);
    let mut checked = 0;
    for (i, f) in m.frames.iter().enumerate().take(moving) {
        let s = &t.frames[i];
        let a = f.a_mm.unwrap();
        za.push((a[0] - s.x_a * l) / f.a_sigma_mm);
        za.push((a[1] - s.y_a * l) / f.a_sigma_mm);
        let v_true = s.v_p * l / ts;
        zv.push((f.v_p_mm_s.unwrap() - v_true) / f.v_p_sigma_mm_s);
        let ang = f.angles.unwrap();
        // theta where the marks still see it well (the ellipse is not yet a circle).
        if s.theta() < 1.3 {
            ztheta.push((ang.theta - s.theta()) / f.angles_sigma[1]);
        }
        if f.branch_checked {
            checked += 1;
            // The branch is the truth's: phi and psi agree modulo 2 pi, not pi.
            zphi.push(wrap(ang.phi - s.phi()) / f.angles_sigma[0]);
            zpsi.push(wrap(ang.psi - s.psi()) / f.angles_sigma[2]);
        }
    }
    for (name, z, lo, hi) in [
        ("A", &za, 0.85, 1.2),
        ("theta", &ztheta, 0.8, 1.3),
        ("phi", &zphi, 0.8, 1.4),
        ("psi", &zpsi, 0.8, 1.4),
        ("v_p", &zv, 0.85, 1.2),
    ] {
        let (rms, beyond) = z_stats(z);
        assert!(rms > lo && rms < hi, "{name}: z rms {rms:.3} over {} frames", z.len());
        assert!(beyond < 0.01, "{name}: {:.2}% beyond 4 sigma", beyond * 100.0);
    }
    assert!(checked > 400, "the branch was settled in {checked} frames only");

    // The turning points: the first twenty agree with the truth run's in time and theta.
    let dt = 1.0 / 300.0 / ts;
    let truth_points: Vec<(TurnKind, f64, f64)> = {
        let opts = ringlab_core::physics::RunOptions { sample_dt: None, ..Default::default() };
        let (summary, _) =
            ringlab_core::physics::simulate(t.model.clone(), &t.initial, opts).unwrap();
        summary
            .turning_points
            .iter()
            .skip(1)
            .map(|p| (p.kind, p.sample.t / dt, p.sample.theta()))
            .collect()
    };
    for (k, p) in m.turning_points.iter().take(20).enumerate() {
        let (kind, at, theta) = truth_points[k];
        assert_eq!(p.kind, kind, "turning point {k}");
        assert!(
            (p.at - at).abs() < 4.0 * p.at_sigma + 0.3,
            "turning point {k} at frame {:.2} +- {:.2}, truth {at:.2}",
            p.at,
            p.at_sigma
        );
        assert!(
            (p.theta - theta).abs() < 4.0 * p.theta_sigma + 0.01,
            "turning point {k}: theta {} +- {}, truth {theta}",
            p.theta,
            p.theta_sigma
        );
    }

    // The start state reconstructed from the data alone is close to the truth's.
    let y = m.state(0, 4, false).unwrap();
    let y_true = t.initial.to_state();
    assert!((y[1] - y_true[1]).abs() < 0.02, "theta0 {} vs {}", y[1], y_true[1]);
    assert!((y[5] - y_true[5]).abs() / y_true[5] < 0.05, "w3 {} vs {}", y[5], y_true[5]);
}

/// Stillness is judged by a still mark's jitter, not by the camera: through a near, tilted or
/// distorting camera the marks scatter about their flat poses several times the noise, and
/// judged by all of that scatter a ring still walking slowly was called still up to 15 frames
/// early (now the scatter counts up to twice the tracks' noise).
#[test]
fn the_still_end_through_a_camera_that_is_not_flat_is_where_the_ring_stops() {
    let truth: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(common::test_data("independent/truth.json")).unwrap(),
    )
    .unwrap();
    for name in ["perspective", "tilted-camera", "lens-off-centre"] {
        let rec = read_recording(&common::test_data(&format!("independent/{name}.csv"))).unwrap();
        let m = recover(&rec).unwrap();
        let t_end = truth[name]["t_end"].as_f64().unwrap();
        let stops = (t_end * m.units.time_s * rec.header.fps).floor() as i64;
        let rest = m.rest_from.expect("the ring stops") as i64;
        assert!((rest - stops).abs() <= 3, "{name}: still from frame {rest}, stops at {stops}");
        let (noise, scatter) = (m.noise_px.unwrap(), m.pose_scatter_px.unwrap());
        assert!(noise < 0.55 && scatter > 1.5, "{name}: noise {noise} px, scatter {scatter} px");
        assert!(m.pose_scatter_note().is_some(), "{name}: the scatter is pointed out");
    }
}

/// Through a tripod's camera (600 mm, tilted 25 degrees, in the header) each mark is mapped
/// onto the table's plan at its own height: the poses then fit the marks to a tenth of a pixel,
/// where the flat view leaves pixels.
#[test]
fn a_tilted_pinholes_marks_are_placed_at_their_heights() {
    use ringlab_core::config::load_preset;
    use ringlab_core::recording::synth::{SynthOptions, synthesize};
    let case = load_preset("paper-ring").expect("preset").build().expect("case");
    let opts = SynthOptions {
        noise_px: 0.0,
        camera_distance_mm: Some(600.0),
        camera_tilt_deg: 25.0,
        camera_in_header: true,
        ..SynthOptions::default()
    };
    let s = synthesize(&case, &opts).expect("synthesized");
    let m = recover(&s.recording).expect("recovered");
    let scatter = m.pose_scatter_px.expect("a scatter");
    let mut flat = s.recording.clone();
    (flat.header.camera_distance_mm, flat.header.camera_tilt_deg) = (None, None);
    let flat = recover(&flat).expect("recovered").pose_scatter_px.expect("a scatter");
    // A tenth of a pixel is left (not yet understood: docs/film.md); onto the table, pixels.
    assert!(scatter < 0.15 && scatter < flat / 10.0, "{scatter} px against {flat} px");
}
