//! A camera held in the hand: its own motion measured from the table (`film::camera_motion`),
//! on a cut of the shared hand-held film (frames 990-1039 of `dark-handheld.mp4`, whose true
//! camera path relative to the cut's first frame moves up to 10.18 px and turns up to 0.912
//! degrees), on a colours cut shaken as a hand shakes a camera (`make-shaken.sh`: up to about
//! 20 px and 2 degrees, slow and smooth), and a film from a still camera reported as still.

mod common;

use common::test_data;
use ringlab_core::film::{TrackOptions, track};
use ringlab_core::physics::Shape;
use ringlab_core::recording::import::BodyMm;
use ringlab_core::recording::read_recording;
use std::sync::atomic::AtomicBool;

fn steel_ring() -> TrackOptions {
    TrackOptions::for_body(BodyMm {
        shape: Shape::Ring,
        outer_radius_mm: 20.66,
        width_mm: 18.0,
        thickness_mm: Some(1.0),
    })
}

fn motion(name: &str) -> ringlab_core::film::CameraMotionReport {
    let path = test_data(&format!("video/{name}.mp4"));
    let cancel = AtomicBool::new(false);
    track(&path, &steel_ring(), &mut |_, _| {}, &cancel).expect("tracks").report.camera_motion
}

#[test]
fn a_hand_held_camera_is_found_moving_as_it_did() {
    let m = motion("dark-handheld-cut");
    assert!(m.hand_held, "{m:?}");
    // Within a tenth of the motion: the largest shift found is not yet as close to the truth
    // as the registration's own error says (docs/film.md).
    assert!((m.largest_shift_px - 10.18).abs() < 1.0, "{m:?}");
    assert!((m.largest_turn_deg - 0.912).abs() < 0.05, "{m:?}");
    assert!(m.registration_sigma_px < 0.2, "{m:?}");
}

#[test]
fn a_still_camera_is_reported_still() {
    let m = motion("colours-none-mid");
    assert!(!m.hand_held, "{m:?}");
    assert!(m.largest_shift_px < 0.2 && m.largest_turn_deg < 0.02, "{m:?}");
}

#[test]
fn a_shaken_films_marks_are_written_in_the_first_frames_camera() {
    let cancel = AtomicBool::new(false);
    let path = test_data("video/colours-none-mid-shaken.mp4");
    let t = track(&path, &steel_ring(), &mut |_, _| {}, &cancel).expect("tracks");
    assert!(t.report.camera_motion.hand_held, "{:?}", t.report.camera_motion);
    let truth = read_recording(&test_data("video/colours-none-mid-shaken.truth.csv"))
        .expect("truth in the first frame's camera");
    // Colours are numbered by their hue: mark k is the truth's mark k.
    let (mut sum, mut found, mut visible, mut far) = (0.0, 0, 0, 0);
    for (tracked, true_marks) in t.recording.frames.iter().zip(&truth.frames) {
        for (m, p) in tracked.iter().zip(true_marks) {
            let Some(p) = p else { continue };
            visible += 1;
            if let Some(m) = m {
                let e = (m[0] - p[0]).hypot(m[1] - p[1]);
                sum += e * e;
                found += 1;
                far += usize::from(e > 3.0);
            }
        }
    }
    let rms = (sum / found.max(1) as f64).sqrt();
    // The still film tracks at 0.36 px; the registration's bias leaves the shaken one looser
    // (docs/film.md), and without the camera's motion taken out it is 20 px off.
    assert!(rms < 1.2, "rms {rms:.3} px");
    assert!(found as f64 >= 0.98 * visible as f64, "found {found} of {visible}");
    assert_eq!(far, 0, "marks more than 3 px off");
}
