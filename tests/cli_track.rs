//! `ringlab track` and films wherever a recording is read, on the command line: the recording
//! written whole, the centres' errors, the overlay film, a fit from a film, and the errors of
//! bad films and flags (ffmpeg missing too), Ctrl-C leaving nothing behind.

mod common;

use common::test_data;
use ringlab::recording::read_recording;
use std::path::{Path, PathBuf};
use std::process::Command;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ringlab-cli-track-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

#[test]
fn track_writes_a_recording_the_errors_and_a_report() {
    let d = dir("write");
    let (out, errors) = (d.join("rec.csv"), d.join("errors.csv"));
    let film = s(&test_data("video/colours-none-mid.mp4"));
    let r = common::ringlab(&[
        "track",
        &film,
        "--preset",
        "steel-ring",
        "--out",
        &s(&out),
        "--errors",
        &s(&errors),
    ]);
    let said = String::from_utf8_lossy(&r.stdout);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(said.contains("tracked 240 frames of 1280x1024 at 300 fps (colours marks)"), "{said}");
    assert!(said.contains("scale from the ring: 3.3"), "{said}");
    let rec = read_recording(&out).expect("reads back");
    assert_eq!(rec.frames.len(), 240);
    assert!((rec.header.px_per_mm / 3.364764 - 1.0).abs() < 0.01, "{}", rec.header.px_per_mm);
    let text = std::fs::read_to_string(&errors).expect("errors written");
    assert_eq!(text.lines().count(), 241, "a header and a row a frame");
    assert!(
        text.starts_with("frame,s1,s2,s3,s4\n249,") || text.starts_with("frame,s1,s2,s3,s4\n0,")
    );
    // Nothing half-written beside them.
    let left: Vec<_> = std::fs::read_dir(&d).expect("dir").filter_map(|e| e.ok()).collect();
    assert_eq!(left.len(), 2, "{left:?}");
    // JSON: the same report.
    let r =
        common::ringlab(&["track", &film, "--preset", "steel-ring", "--out", &s(&out), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&r.stdout).expect("JSON");
    assert_eq!(v["style"], "colours");
    assert_eq!(v["frames"], 240);
    assert!(v["tracker_sigma_px"].as_f64().is_some_and(|x| x > 0.0 && x < 0.6), "{v}");
}

#[test]
fn the_overlay_is_the_film_with_the_marks_drawn_over_it() {
    let d = dir("overlay");
    let (out, overlay) = (d.join("rec.csv"), d.join("overlay.mp4"));
    let film = s(&test_data("video/dark-perspective-mid.mp4"));
    let r = common::ringlab(&[
        "track",
        &film,
        "--preset",
        "steel-ring",
        "--to-frame",
        "29",
        "--out",
        &s(&out),
        "--overlay",
        &s(&overlay),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let probe = Command::new("ffprobe")
        .args([
            "-v",
            "error",
            "-count_frames",
            "-show_entries",
            "stream=nb_read_frames,width,height",
        ])
        .args(["-of", "csv=p=0"])
        .arg(&overlay)
        .output()
        .expect("ffprobe runs");
    assert_eq!(String::from_utf8_lossy(&probe.stdout).trim(), "1280,1024,30");
    // The marks are drawn: the overlay's frame differs from the film's where a mark is.
    let frame = |path: &Path| -> Vec<u8> {
        let o = Command::new("ffmpeg")
            .args(["-v", "error", "-i"])
            .arg(path)
            .args(["-frames:v", "1", "-f", "rawvideo", "-pix_fmt", "rgb24", "-"])
            .output()
            .expect("ffmpeg runs");
        o.stdout
    };
    let (a, b) = (frame(&test_data("video/dark-perspective-mid.mp4")), frame(&overlay));
    let rec = read_recording(&out).expect("reads");
    let m = rec.frames[0].iter().flatten().next().expect("a mark in frame 0");
    // Five pixels right of the mark's centre: its circle.
    let i = 3 * (m[1].round() as usize * 1280 + m[0].round() as usize + 5);
    let diff: i32 = (0..3).map(|c| (a[i + c] as i32 - b[i + c] as i32).abs()).sum();
    assert!(diff > 60, "no circle drawn round the mark ({diff})");
}

#[test]
fn fit_and_recover_take_a_film_and_track_it_first() {
    let film = s(&test_data("video/colours-none-mid.mp4"));
    let r = common::ringlab(&["fit", &film, "--preset", "steel-ring", "--json"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let v: serde_json::Value = serde_json::from_slice(&r.stdout).expect("JSON");
    let rms = v["rms_px"].as_f64().expect("rms");
    assert!(rms < 1.0, "{v}");
    assert!(String::from_utf8_lossy(&r.stderr).contains("tracked 240 frames"));
    let r = common::ringlab(&["recover", &film, "--preset", "steel-ring", "--json"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
}

#[test]
fn bad_films_and_flags_are_clear_errors() {
    let d = dir("bad");
    let film = s(&test_data("video/colours-none-mid.mp4"));
    let out = s(&d.join("rec.csv"));
    common::assert_fails_with(
        &["track", &film, "--out", &out],
        &["does not say the body", "--preset"],
    );
    common::assert_fails_with(
        &["track", &film, "--preset", "steel-ring", "--marks", "purple", "--out", &out],
        &["--marks 'purple'", "colours, dark, bright, auto"],
    );
    common::assert_fails_with(
        &["track", &film, "--preset", "steel-ring", "--roi", "1,2,3", "--out", &out],
        &["--roi '1,2,3'"],
    );
    common::assert_fails_with(
        &[
            "track",
            &film,
            "--preset",
            "steel-ring",
            "--from-frame",
            "9",
            "--to-frame",
            "3",
            "--out",
            &out,
        ],
        &["--to-frame 3 comes before --from-frame 9"],
    );
    for (flag, value, said) in [
        ("--camera-distance-mm", "-50", "--camera-distance-mm -50: must be a distance"),
        ("--camera-distance-mm", "30", "more than the ring's 59 mm"),
        ("--camera-tilt-deg", "95", "--camera-tilt-deg 95: must be the camera's angle"),
        ("--camera-tilt-deg", "NaN", "within (-80, 80)"),
    ] {
        common::assert_fails_with(
            &["track", &film, "--preset", "steel-ring", flag, value, "--out", &out],
            &[said],
        );
    }
    common::assert_fails_with(
        &["fit", &film, "--preset", "steel-ring", "--camera-tilt-deg", "steep"],
        &["--camera-tilt-deg", "steep"],
    );
    let text = d.join("notes.txt");
    std::fs::write(&text, "not a film").expect("writes");
    common::assert_fails_with(
        &["track", &s(&text), "--preset", "steel-ring", "--out", &out],
        &["notes.txt", "not a film"],
    );
    let fake = d.join("fake.mp4");
    std::fs::write(&fake, "not a film either").expect("writes");
    common::assert_fails_with(
        &["diagnose", &s(&fake), "--preset", "steel-ring"],
        &["fake.mp4", "not a video ffmpeg can read"],
    );
    common::assert_fails_with(
        &["track", &s(&d), "--preset", "steel-ring", "--fps", "300", "--out", &out],
        &["no PNG, JPEG or TIFF"],
    );
    assert!(!d.join("rec.csv").exists(), "nothing written on an error");
}

#[test]
fn without_ffmpeg_a_film_is_an_error_that_says_how_to_get_it() {
    let d = dir("noffmpeg");
    let out = Command::new(env!("CARGO_BIN_EXE_ringlab"))
        .args(["track", &s(&test_data("video/colours-none-mid.mp4")), "--preset", "steel-ring"])
        .args(["--out", &s(&d.join("rec.csv"))])
        .env("PATH", &d)
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && !err.contains("panicked"), "{err}");
    assert!(
        err.contains("ffmpeg and ffprobe are needed") && err.contains("apt-get install ffmpeg"),
        "{err}"
    );
}

#[test]
fn ctrl_c_leaves_nothing_half_written() {
    let d = dir("ctrlc");
    let (out, overlay) = (d.join("rec.csv"), d.join("overlay.mp4"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_ringlab"))
        .args([
            "track",
            &s(&test_data("video/colours-reynolds-flicker-mid.mp4")),
            "--preset",
            "steel-ring",
        ])
        .args(["--out", &s(&out), "--overlay", &s(&overlay), "--fit"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("starts");
    // Tracking, then a fit of several seconds, then the overlay: the signal lands in one.
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let killed =
        Command::new("kill").args(["-INT", &child.id().to_string()]).status().expect("kill");
    assert!(killed.success());
    let status = child.wait().expect("ends");
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().expect("piped"), &mut err).ok();
    assert!(!status.success(), "it ended as if not interrupted: {err}");
    assert!(err.contains("cancelled"), "{err}");
    let left: Vec<_> =
        std::fs::read_dir(&d).expect("dir").filter_map(|e| e.ok()).map(|e| e.path()).collect();
    // The recording is written whole before the overlay starts; nothing else may be there.
    assert!(left.iter().all(|p| p == &out), "{left:?}");
    if out.exists() {
        read_recording(&out).expect("whole");
    }
}

#[test]
fn diagnose_takes_films_one_by_one_and_as_a_table() {
    let d = dir("table");
    let table = d.join("table.csv");
    let films = [
        s(&test_data("video/colours-none-mid.mp4")),
        s(&test_data("video/dark-perspective-mid.mp4")),
    ];
    let r = common::ringlab(&[
        "diagnose",
        &films[0],
        &films[1],
        "--preset",
        "steel-ring",
        "--table",
        &s(&table),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let text = std::fs::read_to_string(&table).expect("table written");
    let rows: Vec<&str> = text.lines().skip(1).collect();
    assert_eq!(rows.len(), 2, "{text}");
    assert!(rows[0].starts_with(&films[0]) && rows[1].starts_with(&films[1]), "{text}");
    // The colour film's model left nothing out; its misfit is at the tracker's noise.
    let r = common::ringlab(&["diagnose", &films[0], "--preset", "steel-ring", "--json"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let v: serde_json::Value = serde_json::from_slice(&r.stdout).expect("JSON");
    assert_eq!(v["left_out"], "none", "{v}");
    assert!(
        v["after"]["rms_px"].as_f64().expect("rms") < 1.3 * v["noise_px"].as_f64().expect("noise")
    );
}

/// A near camera's film (the shared `dark-perspective`'s first 600 frames: a pinhole 400 mm
/// above the table, tilted 5 degrees): the tracker's table scale, fitted with the camera's
/// distance, is off by about a percent; the diagnosis fits it with the pinhole, names the
/// camera, and the fit reaches the centres' error the tracker says.
#[test]
fn diagnose_names_a_near_camera_from_its_film_and_corrects_the_scale() {
    let film = s(&test_data("video/dark-perspective-start.mp4"));
    let r = common::ringlab(&["diagnose", &film, "--preset", "steel-ring", "--json"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let v: serde_json::Value = serde_json::from_slice(&r.stdout).expect("JSON");
    assert_eq!(v["left_out"], "camera_perspective", "{v}");
    let after = &v["after"];
    let (rms, noise) = (after["rms_px"].as_f64(), v["noise_px"].as_f64());
    assert!(rms.zip(noise).is_some_and(|(r, n)| r < 1.1 * n), "{rms:?} px against {noise:?}");
    let distance = 1000.0 / after["params"]["camera_perspective"].as_f64().expect("strength");
    assert!((distance / 400.0 - 1.0).abs() < 0.03, "{distance} mm");
    let tilt = after["params"]["camera_tilt_deg"].as_f64().expect("tilt");
    assert!((tilt - 5.0).abs() < 0.3, "{tilt} deg");
    // The scale written (the tracker's) corrected by the fit, against the film's truth.
    let out = s(&dir("near").join("near.csv"));
    let written =
        common::ringlab(&["track", &film, "--preset", "steel-ring", "--json", "--out", &out]);
    assert!(written.status.success(), "{}", String::from_utf8_lossy(&written.stderr));
    let report: serde_json::Value = serde_json::from_slice(&written.stdout).expect("JSON");
    let tracked = report["px_per_mm"].as_f64().expect("scale");
    let correction = after["params"]["table_scale_correction_pct"].as_f64().expect("fitted");
    let table = tracked * (1.0 + correction / 100.0);
    assert!((table / 3.364764 - 1.0).abs() < 0.003, "{tracked} corrected to {table} px/mm");
}

/// A tripod's film (`colours-tripod-30-mid`: 550 mm, tilted 30 degrees, nothing left out of
/// the physics): the tracker writes the camera it fits from the ring, and the diagnosis names
/// nothing but that camera, placed from the motion; with the camera given, nothing at all.
#[test]
fn diagnose_names_at_most_a_tripods_camera() {
    let film = s(&test_data("video/colours-tripod-30-mid.mp4"));
    let out = s(&dir("tripod").join("tripod.csv"));
    let r = common::ringlab(&["track", &film, "--preset", "steel-ring", "--out", &out]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let said = String::from_utf8_lossy(&r.stdout);
    assert!(said.contains("camera from the ring over 400 frames"), "{said}");
    let rec = read_recording(Path::new(&out)).expect("reads back");
    assert!(rec.header.camera_distance_mm.is_some() && rec.header.camera_tilt_deg.is_some());
    let r = common::ringlab(&["diagnose", &film, "--preset", "steel-ring", "--json"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let v: serde_json::Value = serde_json::from_slice(&r.stdout).expect("JSON");
    assert_eq!(v["left_out"], "camera_perspective", "{v}");
    let after = &v["after"];
    let distance = 1000.0 / after["params"]["camera_perspective"].as_f64().expect("strength");
    assert!((distance / 550.0 - 1.0).abs() < 0.03, "{distance} mm");
    let tilt = after["params"]["camera_tilt_deg"].as_f64().expect("tilt");
    assert!((tilt - 30.0).abs() < 0.5, "{tilt} deg");
    let given = [
        "diagnose",
        &film,
        "--preset",
        "steel-ring",
        "--camera-distance-mm",
        "550",
        "--camera-tilt-deg",
        "30",
        "--json",
    ];
    let r = common::ringlab(&given);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let v: serde_json::Value = serde_json::from_slice(&r.stdout).expect("JSON");
    assert_eq!(v["left_out"], "none", "{v}");
}
