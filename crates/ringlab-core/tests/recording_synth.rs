//! Synthesized recordings: they read back as written, look like the sample when made from
//! its truth, and carry their options (noise, lens, effects, missing marks, mark order, spin).

mod common;
mod truth;

use ringlab_core::config::load_preset;
use ringlab_core::physics::EffectKind;
use ringlab_core::physics::run::RunError;
use ringlab_core::recording::marks::MarkGeometry;
use ringlab_core::recording::marks::MarkOrder;
use ringlab_core::recording::synth::{SynthError, SynthOptions, Synthesized, synthesize};
use ringlab_core::recording::{Camera, parse_recording, read_recording, recover, write_recording};
use std::path::Path;

/// The paper-ring preset with the sample's truth parameters.
fn truth_case() -> ringlab_core::config::Case {
    let mut f = load_preset("paper-ring").unwrap();
    f.drag.c = [0.031, 0.066, 0.083];
    f.initial.theta = 0.56;
    f.initial.phi_dot = 4.4;
    f.initial.psi_dot = 0.03;
    f.initial.phi = 0.7;
    f.build().unwrap()
}

fn written(s: &Synthesized) -> Vec<u8> {
    let mut out = Vec::new();
    write_recording(&mut out, &s.recording).unwrap();
    out
}

#[test]
fn a_synthesized_recording_reads_back_as_written() {
    let s = synthesize(
        &truth_case(),
        &SynthOptions { missing_fraction: 0.05, ..SynthOptions::default() },
    )
    .unwrap();
    let back = parse_recording(&written(&s), Path::new("synth.csv")).unwrap();
    assert_eq!(back.header, s.recording.header);
    assert_eq!(back.frames.len(), s.recording.frames.len());
    for (a, b) in back.frames.iter().zip(&s.recording.frames) {
        for (p, q) in a.iter().zip(b) {
            match (p, q) {
                (Some(p), Some(q)) => {
                    assert!((p[0] - q[0]).abs() <= 0.005 && (p[1] - q[1]).abs() <= 0.005)
                }
                (None, None) => {}
                _ => panic!("a mark changed its presence"),
            }
        }
    }
    let missing = back.frames.iter().flatten().filter(|m| m.is_none()).count() as f64
        / (4 * back.frames.len()) as f64;
    assert!((missing - 0.05).abs() < 0.01, "missing fraction {missing}");
}

#[test]
fn made_from_the_truth_it_looks_like_the_sample() {
    let sample = read_recording(&common::test_data("sample-ring.csv")).unwrap();
    let s = synthesize(&truth_case(), &SynthOptions::default()).unwrap();
    let synth = parse_recording(&written(&s), Path::new("synth.csv")).unwrap();
    let (hs, hy) = (&sample.header, &synth.header);
    assert_eq!(synth.frames.len(), sample.frames.len(), "frames (1824 moving + 60 still)");
    assert_eq!((hy.fps, hy.px_per_mm, hy.shape), (hs.fps, hs.px_per_mm, hs.shape));
    assert_eq!((hy.image_width_px, hy.image_height_px), (hs.image_width_px, hs.image_height_px));
    // The marks agree up to two draws of the noise: sqrt(2) * 0.5 px per coordinate.
    let (mut ss, mut n) = (0.0, 0);
    for (a, b) in sample.frames.iter().zip(&synth.frames) {
        for (p, q) in a.iter().zip(b) {
            let (p, q) = (p.unwrap(), q.unwrap());
            ss += (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
            n += 2;
        }
    }
    let rms = (ss / n as f64).sqrt();
    assert!((rms - 0.5 * 2f64.sqrt()).abs() < 0.03, "rms difference {rms} px");
    let (ms, my) = (recover(&sample).unwrap(), recover(&synth).unwrap());
    assert_eq!(ms.rest_from, my.rest_from);
    assert!((my.noise_px.unwrap() - ms.noise_px.unwrap()).abs() < 0.03);
    assert_eq!((ms.mark_order, ms.spin_sign), (my.mark_order, my.spin_sign));
    // And the truth run is what the synth ran.
    let t = truth::load();
    assert_eq!(s.samples.len(), t.frames.len());
    assert!((s.summary.t_end - t.t_end).abs() < 1e-9);
}

#[test]
fn options_reach_the_recording() {
    let case = truth_case();
    let base =
        synthesize(&case, &SynthOptions { noise_px: 0.0, ..SynthOptions::default() }).unwrap();
    // Noise-free marks sit on the projected geometry: no noise in the pose fits.
    let m = recover(&base.recording).unwrap();
    assert!(m.noise_px.unwrap() < 0.01, "noise-free recording shows {} px", m.noise_px.unwrap());

    // Lens distortion moves points away from the centre (k1 > 0) in proportion to rho^2.
    let lens = synthesize(
        &case,
        &SynthOptions { noise_px: 0.0, lens_k1: 0.05, ..SynthOptions::default() },
    )
    .unwrap();
    let c = [640.0, 512.0];
    let d = |p: [f64; 2]| (p[0] - c[0]).hypot(p[1] - c[1]);
    let (p, q) = (base.recording.frames[500][0].unwrap(), lens.recording.frames[500][0].unwrap());
    let rho2 = (d(p) / (0.5 * 1280f64.hypot(1024.0))).powi(2);
    assert!((d(q) / d(p) - (1.0 + 0.05 * rho2)).abs() < 1e-9);
    let as_effect = SynthOptions {
        noise_px: 0.0,
        effect: Some((EffectKind::CameraDistortion, 0.05)),
        ..SynthOptions::default()
    };
    assert_eq!(synthesize(&case, &as_effect).unwrap().recording.frames, lens.recording.frames);

    // A physical effect changes the motion; the same seed gives the same file.
    let friction = SynthOptions {
        effect: Some((EffectKind::RollingFriction, 0.002)),
        ..SynthOptions::default()
    };
    let f = synthesize(&case, &friction).unwrap();
    assert!(f.summary.t_end < base.summary.t_end, "rolling friction should end the motion sooner");
    assert_eq!(synthesize(&case, &friction).unwrap().recording.frames, f.recording.frames);

    // Mark order and spin direction are read back from the data.
    let rev = synthesize(
        &case,
        &SynthOptions { mark_order: MarkOrder::Reverse, ..SynthOptions::default() },
    )
    .unwrap();
    assert_eq!(recover(&rev.recording).unwrap().mark_order, MarkOrder::Reverse);
    let mut mirrored = load_preset("paper-ring").unwrap();
    mirrored.initial.phi_dot = -4.5;
    let neg = synthesize(&mirrored.build().unwrap(), &SynthOptions::default()).unwrap();
    assert_eq!(recover(&neg.recording).unwrap().spin_sign, -1.0);
    assert_eq!(recover(&base.recording).unwrap().spin_sign, 1.0);
}

#[test]
fn bad_options_and_unavailable_effects_are_errors() {
    let case = truth_case();
    for bad in [
        SynthOptions { fps: 0.0, ..SynthOptions::default() },
        SynthOptions { px_per_mm: f64::NAN, ..SynthOptions::default() },
        SynthOptions { noise_px: -1.0, ..SynthOptions::default() },
        SynthOptions { missing_fraction: 1.0, ..SynthOptions::default() },
        SynthOptions {
            lens_k1: 0.1,
            effect: Some((EffectKind::CameraDistortion, 0.1)),
            ..SynthOptions::default()
        },
    ] {
        assert!(matches!(synthesize(&case, &bad), Err(SynthError::Option(_))), "{bad:?} accepted");
    }
    let negative =
        SynthOptions { effect: Some((EffectKind::PivotFriction, -0.1)), ..SynthOptions::default() };
    assert!(matches!(synthesize(&case, &negative), Err(SynthError::Effect(_))));
    // The sliding contact: either it runs, or the run says clearly that it cannot.
    let slip = SynthOptions { effect: Some((EffectKind::Slip, 0.3)), ..SynthOptions::default() };
    match synthesize(&case, &slip) {
        Ok(s) => assert!(!s.recording.frames.is_empty()),
        Err(e) => {
            assert!(matches!(e, SynthError::Run(RunError::Unsupported(_))), "{e:?}");
            assert!(e.to_string().contains("slip"), "{e}");
        }
    }
}

#[test]
fn a_pinhole_camera_magnifies_the_marks_and_its_header_keys_reproduce_them() {
    let case = truth_case();
    let plain = SynthOptions { noise_px: 0.0, ..SynthOptions::default() };
    let ortho = synthesize(&case, &plain).unwrap();
    let pin_opts = SynthOptions { camera_distance_mm: Some(450.0), ..plain.clone() };
    let pin = synthesize(&case, &pin_opts).unwrap();
    // By default the header does not say.
    assert_eq!(pin.recording.header, ortho.recording.header);
    assert_eq!(
        (pin.recording.header.camera_distance_mm, pin.recording.header.camera_tilt_deg),
        (None, None)
    );
    // Every mark is above the table, so it is seen farther from the image centre; off the
    // centre by several pixels (about 6% of the distance: 450 / (450 - 27 mm)).
    let centre = [640.0, 512.0];
    let r = |p: [f64; 2]| (p[0] - centre[0]).hypot(p[1] - centre[1]);
    let (mut far, mut shift) = (0, 0.0f64);
    for (i, (a, b)) in ortho.recording.frames.iter().zip(&pin.recording.frames).enumerate() {
        for (p, q) in a.iter().zip(b) {
            let (p, q) = (p.unwrap(), q.unwrap());
            assert!(r(q) > r(p), "frame {i}: {q:?} not farther out than {p:?}");
            if r(p) > 150.0 {
                far += 1;
                shift = shift.max((q[0] - p[0]).hypot(q[1] - p[1]));
                assert!((q[0] - p[0]).hypot(q[1] - p[1]) > 5.0, "frame {i}: {p:?} -> {q:?}");
            }
        }
    }
    assert!(far > 100 && shift > 8.0, "{far} marks off the centre, largest shift {shift} px");
    // With the keys in the header (the same marks), the camera read back reproduces them.
    for (distance, tilt) in [(450.0, 0.0), (450.0, 20.0), (700.0, -35.0)] {
        let opts = SynthOptions {
            camera_distance_mm: Some(distance),
            camera_tilt_deg: tilt,
            camera_in_header: true,
            ..plain.clone()
        };
        let s = synthesize(&case, &opts).unwrap();
        if tilt == 0.0 {
            assert_eq!(s.recording.frames, pin.recording.frames);
        }
        let back = parse_recording(&written(&s), Path::new("pinhole.csv")).unwrap();
        assert_eq!(
            (back.header.camera_distance_mm, back.header.camera_tilt_deg),
            (Some(distance), Some(tilt))
        );
        let camera = Camera::for_recording(&back.header, &back.frames);
        assert_eq!(camera, s.camera);
        let geometry = MarkGeometry::of_body(&back.header.body_mm().unwrap(), MarkOrder::Forward);
        let mut worst = 0.0f64;
        for (sample, frame) in s.samples.iter().zip(&back.frames) {
            let l = s.length_mm;
            let marks = geometry.marks3(
                [sample.x_a * l, sample.y_a * l],
                sample.phi(),
                sample.theta(),
                sample.psi(),
            );
            for (m, seen) in marks.iter().zip(frame) {
                let p = camera.to_px3(m[0], m[1], m[2]);
                let seen = seen.unwrap();
                worst = worst.max((p[0] - seen[0]).abs()).max((p[1] - seen[1]).abs());
            }
        }
        // Written to a hundredth of a pixel; the header's body to the nanometre.
        assert!(worst < 0.0051, "{distance} mm, {tilt} deg: {worst} px");
        // Read as orthographic (keys dropped), the same marks miss by pixels.
        let flat = Camera { distance_mm: None, tilt_rad: 0.0, ..camera };
        let s0 = &s.samples[0];
        let m = geometry.marks3(
            [s0.x_a * s.length_mm, s0.y_a * s.length_mm],
            s0.phi(),
            s0.theta(),
            s0.psi(),
        )[0];
        let seen = back.frames[0][0].unwrap();
        let p = flat.to_px(m[0], m[1]);
        assert!((p[0] - seen[0]).hypot(p[1] - seen[1]) > 2.0, "{distance} mm, {tilt} deg");
    }
}

#[test]
fn camera_options_are_checked() {
    let case = truth_case();
    for bad in [
        SynthOptions { camera_distance_mm: Some(0.0), ..SynthOptions::default() },
        SynthOptions { camera_distance_mm: Some(f64::INFINITY), ..SynthOptions::default() },
        SynthOptions { camera_distance_mm: Some(100.0), ..SynthOptions::default() },
        SynthOptions { camera_tilt_deg: 80.0, ..SynthOptions::default() },
        SynthOptions { camera_tilt_deg: f64::NAN, ..SynthOptions::default() },
    ] {
        assert!(matches!(synthesize(&case, &bad), Err(SynthError::Option(_))), "{bad:?} accepted");
    }
    // Just beyond five outer radii (103.3 mm) is allowed.
    let near = SynthOptions { camera_distance_mm: Some(110.0), ..SynthOptions::default() };
    assert_eq!(synthesize(&case, &near).unwrap().camera.distance_mm, Some(110.0));
    // A ring that rolls behind a tilted camera cannot be filmed: an error, not NaN pixels.
    let mut away = case.clone();
    away.initial.y_c = 10.0;
    let tilted = SynthOptions { camera_tilt_deg: -60.0, ..near }; // towards +Y, where the ring is
    assert!(matches!(synthesize(&away, &tilted), Err(SynthError::Camera(_))));
}
