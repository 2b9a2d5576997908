//! Cases saved as TOML (File > Save case) read back to the same case, run as the presets do,
//! and open the window (`ringlab --config`); bad files are named.

mod common;

use common::{assert_fails_with, ringlab};
use ringlab::config::{CaseFile, load_case_file, load_preset, preset_names, save_case_file};
use std::path::PathBuf;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ringlab-cases-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn every_preset_round_trips_through_a_saved_file() {
    let d = dir("presets");
    for name in preset_names() {
        let f = load_preset(name).unwrap();
        let path = d.join(format!("{name}.toml"));
        save_case_file(&path, &f).unwrap();
        let back = load_case_file(&path).unwrap();
        assert_eq!(back, f, "{name}");
        assert_eq!(back.build().unwrap(), f.build().unwrap(), "{name}: the same case to run");
    }
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn a_changed_case_with_effects_round_trips_number_for_number() {
    let d = dir("changed");
    let mut f = load_preset("paper-ring").unwrap();
    f.drag.c = [0.1 / 3.0, 0.063_000_000_000_1, 1e-7];
    f.initial.theta = std::f64::consts::PI / 7.0;
    f.effects.reynolds_drag = Some([868.0, 0.5, 10.0]);
    f.effects.pivot_friction = 0.003;
    f.effects.slip_mu = Some(0.4);
    let path = d.join("changed.toml");
    save_case_file(&path, &f).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.starts_with("# A ringlab case"), "a header says what it is");
    for section in ["[units]", "[body]", "[drag]", "[initial]", "[run]", "[effects]"] {
        assert!(text.contains(section), "{section} in\n{text}");
    }
    assert_eq!(load_case_file(&path).unwrap(), f);
    // The paper's model has no [effects] section.
    let plain = d.join("plain.toml");
    save_case_file(&plain, &load_preset("coin").unwrap()).unwrap();
    assert!(!std::fs::read_to_string(&plain).unwrap().contains("[effects]"));
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn a_saved_case_runs_as_its_preset_does() {
    let d = dir("runs");
    let path = d.join("coin.toml");
    save_case_file(&path, &load_preset("coin").unwrap()).unwrap();
    let (a, b) = (d.join("a.csv"), d.join("b.csv"));
    let out = ringlab(&["simulate", "--preset", "coin", "--out", a.to_str().unwrap()]);
    assert!(out.status.success());
    let out =
        ringlab(&["simulate", "--config", path.to_str().unwrap(), "--out", b.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn a_case_that_does_not_build_is_not_saved_and_a_bad_folder_is_named() {
    let d = dir("bad");
    let mut f: CaseFile = load_preset("paper-ring").unwrap();
    f.body.thickness = Some(5.0);
    let path = d.join("bad.toml");
    let e = save_case_file(&path, &f).unwrap_err().to_string();
    assert!(e.contains("bad.toml") && e.contains("not saved"), "{e}");
    assert!(!path.exists());
    let e = save_case_file(&d.join("no/such/folder.toml"), &load_preset("coin").unwrap())
        .unwrap_err()
        .to_string();
    assert!(e.contains("folder.toml"), "{e}");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn the_window_with_a_bad_case_file_stops_before_opening_with_the_files_error() {
    let d = dir("window");
    let bad = d.join("typo.toml");
    std::fs::write(&bad, "name = 1\n").unwrap();
    assert_fails_with(&["--config", bad.to_str().unwrap()], &["typo.toml"]);
    assert_fails_with(
        &["--config", d.join("missing.toml").to_str().unwrap()],
        &["missing.toml", "cannot read"],
    );
    // The window's flag is not a subcommand's.
    assert_fails_with(&["--config", bad.to_str().unwrap(), "presets"], &["cannot be used"]);
    std::fs::remove_dir_all(&d).ok();
}
