//! The command line: outputs, and a clear error (never a panic) for every bad flag or value.

use std::process::{Command, Output};

fn ringlab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ringlab")).args(args).output().expect("runs the binary")
}

fn assert_fails_with(args: &[&str], needle: &str) {
    let out = ringlab(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} succeeded");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    assert!(err.contains(needle), "{args:?}: error does not mention '{needle}':\n{err}");
}

#[test]
fn simulate_json_reports_the_paper_case() {
    let out = ringlab(&["simulate", "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    for key in [
        "t_end",
        "end_reason",
        "retrograde_turn",
        "inflection_time",
        "prograde_cycles",
        "lift_off",
        "slip",
        "friction_ratio_at_theta_max",
        "rhs_evaluations",
        "steps",
        "compute_seconds",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert_eq!(v["end_reason"], "flat");
    assert_eq!(v["retrograde_turn"], true);
    assert!((v["t_end"].as_f64().unwrap() - 126.1021).abs() < 0.01);
    assert!(!v["lift_off"].as_array().unwrap().is_empty());
}

#[test]
fn simulate_writes_csv_with_the_documented_columns() {
    let dir = std::env::temp_dir().join(format!("ringlab-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("disk.csv");
    let out = ringlab(&[
        "simulate",
        "--preset",
        "paper-disk-drag",
        "--dt",
        "0.5",
        "--out",
        path.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&path).unwrap();
    let header = text.lines().next().unwrap();
    assert!(header.starts_with(
        "t,phi,theta,psi,w1,w2,w3,x_c,y_c,z_c,x_a,y_a,x_p,y_p,v_p,f_1,f_f,f_n,energy"
    ));
    let rows: Vec<&str> = text.lines().skip(1).collect();
    // 0, 0.5, ..., 40.5 and the end point at about 40.95.
    assert!(rows.len() >= 80 && rows.len() <= 84, "{} rows", rows.len());
    assert!(rows.iter().all(|r| r.split(',').count() == header.split(',').count()));
    let human = String::from_utf8_lossy(&out.stdout);
    assert!(human.contains("retrograde turn: no"), "{human}");
    assert!(human.contains("MODEL INVALID: F_N <= 0"), "lift-off not reported:\n{human}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn overrides_change_the_run() {
    let out = ringlab(&["simulate", "--json", "--c1", "0.2", "--c3", "0.2"]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(v["retrograde_turn"], false);
    let out = ringlab(&["simulate", "--json", "--t-end", "10"]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(v["end_reason"], "t_end");
    assert_eq!(v["t_end"].as_f64().unwrap(), 10.0);
}

#[test]
fn every_preset_runs() {
    let out = ringlab(&["presets"]);
    let list = String::from_utf8_lossy(&out.stdout);
    for name in
        ["paper-ring", "paper-disk-drag", "aluminium-disk", "steel-ring", "coin", "wedding-ring"]
    {
        assert!(list.contains(name), "preset {name} missing");
        let out = ringlab(&["simulate", "--preset", name, "--json"]);
        assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
    }
}

#[test]
fn bad_values_are_named() {
    assert_fails_with(&["simulate", "--c1", "-1"], "C1");
    assert_fails_with(&["simulate", "--c2", "abc"], "--c2");
    assert_fails_with(&["simulate", "--c3", "nan"], "--c3");
    assert_fails_with(&["simulate", "--theta0", "2"], "theta0");
    assert_fails_with(&["simulate", "--theta0", "-0.1"], "theta0");
    assert_fails_with(&["simulate", "--phidot0", "inf"], "--phidot0");
    assert_fails_with(&["simulate", "--rtol", "0"], "rtol");
    assert_fails_with(&["simulate", "--rtol", "2"], "rtol");
    assert_fails_with(&["simulate", "--atol", "-1"], "atol");
    assert_fails_with(&["simulate", "--dt", "-0.1"], "dt");
    assert_fails_with(&["simulate", "--t-end", "0"], "t_end");
    assert_fails_with(&["simulate", "--mu", "-0.4"], "mu");
    assert_fails_with(&["simulate", "--preset", "nonesuch"], "unknown preset 'nonesuch'");
    assert_fails_with(
        &["simulate", "--preset", "coin", "--config", "x.toml"],
        "cannot be used with",
    );
    assert_fails_with(&["simulate", "--bogus"], "--bogus");
    assert_fails_with(&["sweep", "--out", "/tmp/x.csv", "--c1-range", "0.1"], "--c1-range");
    assert_fails_with(&["sweep", "--out", "/tmp/x.csv", "--c2-range", "0,1"], "logarithmic");
    assert_fails_with(&["sweep", "--out", "/tmp/x.csv", "--c3-range", "0.5,0.1"], "--c3-range");
}

#[test]
fn effects_from_flags_and_from_a_case_file_agree_and_show_in_the_json() {
    let out = ringlab(&["simulate", "--json", "--effect", "slip", "--effect-strength", "0.4"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(v["slip_mu"], 0.4);
    assert_eq!(v["effects"][0]["name"], "slip");
    let sliding = v["sliding"].as_array().expect("sliding intervals");
    assert!(sliding.len() >= 2 && sliding[0][0] == 0.0, "{sliding:?}");
    assert!(v["slip"].as_array().unwrap().is_empty(), "would-slip is for pure rolling");

    // The same through a case file's [effects].
    let dir = std::env::temp_dir().join(format!("ringlab-fx-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let good = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/crates/ringlab-core/assets/presets/paper-ring.toml"
    ))
    .unwrap();
    let path = dir.join("slip.toml");
    std::fs::write(&path, format!("{good}\n[effects]\nslip_mu = 0.4\n")).unwrap();
    let out = ringlab(&["simulate", "--json", "--config", path.to_str().unwrap()]);
    let w: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(w["sliding"], v["sliding"]);
    assert_eq!(w["t_end"], v["t_end"]);

    // Several effects at once, and the samples say when the contact slides.
    let csv = dir.join("effects.csv");
    let out = ringlab(&[
        "simulate",
        "--effect",
        "slip",
        "--effect-strength",
        "0.4",
        "--effect",
        "reynolds_drag",
        "--effect-strength",
        "0.5",
        "--dt",
        "0.5",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let human = String::from_utf8_lossy(&out.stdout);
    assert!(
        human.contains("effect reynolds_drag = 0.5")
            && human.contains("sliding contact (mu = 0.4)"),
        "{human}"
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.lines().next().unwrap().ends_with(",sliding,slip_speed"));
    assert!(text.lines().nth(1).unwrap().contains(",1,"), "the start slides");
    // A start held rolling: the flag and the case file's key agree; the held stretch is
    // reported as would-slip, and the first slide comes after it.
    let held = ringlab(&[
        "simulate",
        "--json",
        "--effect",
        "slip",
        "--effect-strength",
        "0.4",
        "--slip-start",
        "held",
    ]);
    assert!(held.status.success(), "{}", String::from_utf8_lossy(&held.stderr));
    let h: serde_json::Value = serde_json::from_slice(&held.stdout).expect("json");
    let held_until = h["slip"][0][1].as_f64().expect("the held stretch");
    assert_eq!(h["slip"][0][0], 0.0);
    let first_slide = h["sliding"][0][0].as_f64().expect("a slide");
    assert!(first_slide >= held_until && held_until > 0.0, "{h}");
    std::fs::write(&path, format!("{good}\n[effects]\nslip_mu = 0.4\nslip_start_held = true\n"))
        .unwrap();
    let out = ringlab(&["simulate", "--json", "--config", path.to_str().unwrap()]);
    let w: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!((&w["sliding"], &w["slip"]), (&h["sliding"], &h["slip"]));

    std::fs::write(&path, format!("{good}\n[effects]\nslip_mu = -0.4\n")).unwrap();
    let out = ringlab(&["simulate", "--config", path.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("slip.toml") && err.contains("slip mu"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_effects_are_named() {
    assert_fails_with(
        &["simulate", "--effect", "wind", "--effect-strength", "1"],
        "reynolds_drag, rolling_friction",
    );
    assert_fails_with(&["simulate", "--effect", "slip"], "--effect-strength");
    assert_fails_with(
        &["simulate", "--effect", "slip", "--effect-strength", "-1"],
        "--effect-strength -1 for slip",
    );
    assert_fails_with(&["simulate", "--effect", "slip", "--effect-strength", "3"], "Painleve");
    assert_fails_with(
        &["simulate", "--effect", "pivot_friction", "--effect-strength", "abc"],
        "--effect-strength",
    );
    assert_fails_with(
        &["simulate", "--effect", "rolling_friction", "--effect-strength", "inf"],
        "finite",
    );
    assert_fails_with(
        &["simulate", "--effect", "camera_distortion", "--effect-strength", "-0.05"],
        "synth",
    );
    assert_fails_with(
        &[
            "simulate",
            "--effect",
            "slip",
            "--effect-strength",
            "0.3",
            "--effect",
            "slip",
            "--effect-strength",
            "0.4",
        ],
        "twice",
    );
    assert_fails_with(&["simulate", "--effect-strength", "0.3"], "--effect");
    assert_fails_with(&["simulate", "--slip-start", "held"], "--slip-start needs --effect slip");
    assert_fails_with(
        &["simulate", "--effect", "slip", "--effect-strength", "0.4", "--slip-start", "late"],
        "--slip-start",
    );
    assert_fails_with(&["synth", "--slip-start", "held", "--out", "-"], "--effect slip");
}

#[test]
fn bad_case_files_are_named_with_the_file() {
    let dir = std::env::temp_dir().join(format!("ringlab-cfg-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let good = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/crates/ringlab-core/assets/presets/paper-ring.toml"
    ))
    .unwrap();
    let cases: &[(&str, String, &str)] = &[
        ("missing.toml", String::new(), "cannot read"),
        ("syntax.toml", "name = ".to_string(), "syntax.toml"),
        ("unknown-key.toml", good.replace("[drag]", "[drag]\ncolour = 1"), "colour"),
        ("no-thickness.toml", good.replace("thickness = 0.05", ""), "thickness"),
        (
            "thick-wall.toml",
            good.replace("thickness = 0.05", "thickness = 2.0"),
            "wall thickness w",
        ),
        ("bad-shape.toml", good.replace("shape = \"ring\"", "shape = \"torus\""), "torus"),
        ("bad-units.toml", good.replace("system = \"model\"", "system = \"furlong\""), "furlong"),
        ("zero-width.toml", good.replace("width = 0.88", "width = 0.0"), "width h"),
        (
            "negative-drag.toml",
            good.replace("c = [0.03, 0.063, 0.085]", "c = [0.03, -0.063, 0.085]"),
            "C2",
        ),
        (
            "short-drag.toml",
            good.replace("c = [0.03, 0.063, 0.085]", "c = [0.03, 0.063]"),
            "short-drag.toml",
        ),
    ];
    for (name, text, needle) in cases {
        let path = dir.join(name);
        if !text.is_empty() {
            std::fs::write(&path, text).unwrap();
        }
        let out = ringlab(&["simulate", "--config", path.to_str().unwrap()]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{name} accepted");
        assert!(!err.contains("panicked"), "{name}: {err}");
        assert!(err.contains(needle), "{name}: error does not mention '{needle}':\n{err}");
        assert!(err.contains(name), "{name}: error does not name the file:\n{err}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn sweep_shards_merge_into_the_whole_grid() {
    let d = std::env::temp_dir().join(format!("ringlab-sweep-shards-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let p = |name: &str| d.join(name).display().to_string();
    let whole = ringlab(&["sweep", "--n", "3", "--threads", "1", "--out", &p("whole.csv")]);
    assert!(whole.status.success(), "{}", String::from_utf8_lossy(&whole.stderr));
    for i in 0..3 {
        let out = ringlab(&[
            "sweep",
            "--n",
            "3",
            "--threads",
            "1",
            "--shard",
            &format!("{i}/3"),
            "--out",
            &p(&format!("s{i}.csv")),
        ]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let rows = std::fs::read_to_string(p(&format!("s{i}.csv"))).unwrap().lines().count() - 1;
        assert_eq!(rows, 9, "shard {i} takes every third of 27 points");
    }
    // Merged in any order, the shards give the whole sweep's table line for line.
    let merged = ringlab(&[
        "sweep",
        "--merge",
        &p("s2.csv"),
        &p("s0.csv"),
        &p("s1.csv"),
        "--out",
        &p("merged.csv"),
    ]);
    assert!(merged.status.success(), "{}", String::from_utf8_lossy(&merged.stderr));
    assert_eq!(
        std::fs::read_to_string(p("merged.csv")).unwrap(),
        std::fs::read_to_string(p("whole.csv")).unwrap()
    );
    assert_fails_with(
        &["sweep", "--merge", &p("s0.csv"), &p("s2.csv"), "--out", &p("m.csv")],
        "18 of the 27 points of their grid (point 1 is missing)",
    );
    assert_fails_with(
        &["sweep", "--merge", &p("s0.csv"), &p("whole.csv"), "--out", &p("m.csv")],
        "grid point 0 is in two tables",
    );
    assert_fails_with(&["sweep", "--shard", "3/3", "--out", &p("m.csv")], "0 <= I < N");
}
