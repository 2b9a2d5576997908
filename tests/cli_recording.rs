//! `ringlab synth`, `recover` and `fit` from the command line: outputs, and clear errors
//! (never a panic) for bad files and flags.

mod common;

use common::{assert_fails_with, ringlab};

use std::path::PathBuf;

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ringlab-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn synth_then_fit_recovers_the_parameters() {
    let dir = temp_dir("synth-fit");
    let path = dir.join("disk-drag.csv");
    let p = path.to_str().unwrap();
    let out = ringlab(&[
        "synth",
        "--preset",
        "paper-disk-drag",
        "--c2",
        "0.05",
        "--seed",
        "9",
        "--drop-marks",
        "0.02",
        "--out",
        p,
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("at rest"));
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.starts_with(
        "# ringlab-recording v1\n# fps = 300.0\n# px_per_mm = 3.364764\n# shape = ring\n"
    ));

    let out = ringlab(&["fit", p, "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    for key in
        ["c", "c_sigma", "theta0", "phidot0", "psidot0", "rms_px", "frames", "compute_seconds"]
    {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    let c: Vec<f64> = v["c"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    for (got, want) in c.iter().zip([0.2, 0.05, 0.2]) {
        assert!((got / want - 1.0).abs() < 0.1, "C {c:?}");
    }
    assert!((v["theta0"].as_f64().unwrap() / 0.55 - 1.0).abs() < 0.02);
    assert!((v["phidot0"].as_f64().unwrap() / 4.5 - 1.0).abs() < 0.02);
    assert_eq!(v["frames"].as_u64().unwrap() as usize, text.lines().count() - 13);

    let motion = dir.join("motion.csv");
    let out = ringlab(&["recover", p, "--out", motion.to_str().unwrap(), "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    assert_eq!(v["first_inner_turn"]["frame"].as_f64().unwrap(), 0.0);
    let table = std::fs::read_to_string(&motion).unwrap();
    assert!(table.starts_with("frame,t_s,t_model,marks,ax_mm,ay_mm"));
    assert_eq!(table.lines().count(), text.lines().count() - 13 + 1);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_human_fit_report_names_the_start_and_misfit() {
    let sample = common::test_data("sample-ring.csv");
    let out = ringlab(&["fit", sample.to_str().unwrap(), "--threads", "2"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in ["drag  C1 = ", "theta0 = ", "phidot0 = ", "misfit ", "px rms"] {
        assert!(text.contains(needle), "missing '{needle}' in:\n{text}");
    }
}

#[test]
fn bad_recordings_give_their_file_and_line() {
    let dir = temp_dir("bad-rec");
    let good = std::fs::read_to_string(common::test_data("sample-ring.csv")).unwrap();
    let head: String = good.lines().take(30).map(|l| format!("{l}\n")).collect();
    let cases = [
        ("no-fps.csv", head.replace("# fps = 300.0\n", ""), "missing required header key 'fps'"),
        ("text.csv", head.replace("\n5,605.20,", "\n5,abc,"), ":16: x1 = 'abc' is not a number"),
        ("order.csv", head.replace("\n7,", "\n9,"), ":18: frames out of order"),
        (
            "scale.csv",
            head.replace("px_per_mm = 3.364764", "px_per_mm = 0"),
            ":3: px_per_mm = 0 must be greater",
        ),
        (
            "one.csv",
            good.lines().take(11).map(|l| format!("{l}\n")).collect(),
            "fewer than two usable frames",
        ),
    ];
    for (name, text, needle) in &cases {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        for cmd in ["fit", "recover"] {
            assert_fails_with(&[cmd, path.to_str().unwrap()], &[name, needle]);
        }
    }
    assert_fails_with(&["fit", "/nonexistent/x.csv"], &["/nonexistent/x.csv", "cannot read"]);
    // Too short to fit, though readable.
    let short = dir.join("short.csv");
    std::fs::write(&short, &head).unwrap();
    assert_fails_with(&["fit", short.to_str().unwrap()], &["short.csv", "too few frames"]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_flags_are_named() {
    let out = "/tmp/ringlab-never-written.csv";
    assert_fails_with(&["synth", "--noise-px", "-1", "--out", out], &["noise_px"]);
    assert_fails_with(&["synth", "--fps", "0", "--out", out], &["fps"]);
    assert_fails_with(&["synth", "--px-per-mm", "nan", "--out", out], &["px_per_mm"]);
    assert_fails_with(&["synth", "--lens-k1", "3", "--out", out], &["k1"]);
    assert_fails_with(
        &["synth", "--effect", "wind", "--effect-strength", "1", "--out", out],
        &["--effect 'wind'"],
    );
    assert_fails_with(
        &["synth", "--effect", "rolling_friction", "--out", out],
        &["--effect-strength"],
    );
    assert_fails_with(
        &["synth", "--effect", "pivot_friction", "--effect-strength", "-1", "--out", out],
        &["must not be negative"],
    );
    assert_fails_with(&["synth", "--image", "1280", "--out", out], &["--image"]);
    assert_fails_with(&["synth", "--drop-marks", "1.5", "--out", out], &["missing fraction"]);
    assert_fails_with(&["synth", "--c1", "-1", "--out", out], &["C1"]);
    assert_fails_with(&["synth"], &["--out"]);
    assert_fails_with(&["synth", "--out", "/nonexistent/dir/x.csv"], &["cannot create"]);
    let sample = common::test_data("sample-ring.csv");
    let s = sample.to_str().unwrap();
    assert_fails_with(&["fit", s, "--c-start", "0.1,0.2"], &["--c-start"]);
    assert_fails_with(&["fit", s, "--c-start", "0.1,-0.2,0.3"], &["positive"]);
    assert_fails_with(&["fit", s, "--effect", "wind"], &["--effect 'wind'"]);
    assert_fails_with(&["fit", s, "--segment-frames", "4"], &["too short"]);
    assert_fails_with(&["fit"], &["<FILE>"]);
    // The sliding contact: synth passes the run's refusal on, or makes the recording.
    let slip = ringlab(&[
        "synth",
        "--effect",
        "slip",
        "--effect-strength",
        "0.3",
        "--t-end",
        "5",
        "--out",
        out,
    ]);
    let err = String::from_utf8_lossy(&slip.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert!(slip.status.success() || err.contains("slip"), "{err}");
    std::fs::remove_file(out).ok();
}

#[test]
fn camera_flags_film_through_a_pinhole_and_say_so_only_when_asked() {
    let dir = temp_dir("synth-camera");
    let (quiet, told) = (dir.join("quiet.csv"), dir.join("told.csv"));
    let base = ["synth", "--t-end", "3", "--camera-distance-mm", "450", "--camera-tilt-deg", "-10"];
    let run = |extra: &[&str], out: &PathBuf| {
        let args: Vec<&str> = base
            .iter()
            .copied()
            .chain(extra.iter().copied())
            .chain(["--out", out.to_str().unwrap()])
            .collect();
        let o = ringlab(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stderr).to_string()
    };
    let note = run(&[], &quiet);
    assert!(note.contains("camera pinhole at 450 mm, tilt -10 deg (not in the header)"), "{note}");
    run(&["--camera-in-header"], &told);
    let (quiet, told) =
        (std::fs::read_to_string(&quiet).unwrap(), std::fs::read_to_string(&told).unwrap());
    assert!(!quiet.contains("camera_"), "{quiet}");
    assert!(told.contains("# camera_distance_mm = 450.0\n# camera_tilt_deg = -10.0\n"));
    // Same marks either way: only the header differs.
    let frames =
        |t: &str| t.lines().skip_while(|l| l.starts_with('#')).collect::<Vec<_>>().join("\n");
    assert_eq!(frames(&quiet), frames(&told));
    std::fs::remove_dir_all(&dir).ok();
    let out = "/tmp/ringlab-never-written-camera.csv";
    assert_fails_with(&["synth", "--camera-distance-mm", "-5", "--out", out], &["camera distance"]);
    assert_fails_with(
        &["synth", "--camera-distance-mm", "nan", "--out", out],
        &["camera distance"],
    );
    assert_fails_with(
        &["synth", "--camera-distance-mm", "60", "--out", out],
        &["camera distance", "outer radius"],
    );
    assert_fails_with(&["synth", "--camera-tilt-deg", "85", "--out", out], &["camera tilt"]);
    assert!(!std::path::Path::new(out).exists());
}
