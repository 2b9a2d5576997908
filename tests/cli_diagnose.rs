//! `ringlab diagnose` from the command line: the sample recording (made by the paper's model
//! with nothing hidden) must come out as `none`; the JSON, the report's figures and text; clear
//! errors for bad files and flags.

mod common;

use common::{assert_fails_with, ringlab};

use std::path::PathBuf;

#[test]
fn the_sample_is_none_with_json_and_a_report() {
    let sample = common::test_data("sample-ring.csv");
    let dir: PathBuf =
        std::env::temp_dir().join(format!("ringlab-diagnose-{}", std::process::id()));
    let out = ringlab(&[
        "diagnose",
        sample.to_str().unwrap(),
        "--json",
        "--report",
        dir.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    assert_eq!(v["left_out"], "none", "{}", v["explanation"]);
    assert!(v["mismatch"].is_null(), "{}", v["mismatch"]);
    let (before, after) =
        (v["before"]["rms_px"].as_f64().unwrap(), v["after"]["rms_px"].as_f64().unwrap());
    assert_eq!(before, after);
    // The sample's noise is 0.5 px; its header's width (18 mm) is the 17.74 mm ring's rounded up.
    assert!(before < 0.52, "misfit {before}");
    let h = v["after"]["params"]["h_mm"].as_f64().unwrap();
    assert!((h - 17.7408).abs() < 0.02, "fitted width {h} mm");
    for (i, c) in [0.031, 0.066, 0.083].iter().enumerate() {
        let got = v["after"]["params"][format!("C{}", i + 1)].as_f64().unwrap();
        assert!((got / c - 1.0).abs() < 0.02, "C{} = {got}", i + 1);
    }
    let candidates = v["candidates"].as_array().unwrap();
    // A row for every effect of the list, the plain model ("none") among them.
    assert_eq!(candidates.len(), ringlab::physics::EffectKind::ALL.len());
    // The open world's fields: nothing named, no glitch, no excess left; the noise from the tracks.
    assert_eq!(v["left_out_all"].as_array().map(|a| a.len()), Some(0));
    assert_eq!(v["glitches"], 0);
    assert!((v["noise_px"].as_f64().unwrap() - 0.5).abs() < 0.03, "noise {}", v["noise_px"]);
    assert!(v["before"]["excess_px"].as_f64().unwrap() < 0.75 * v["noise_px"].as_f64().unwrap());
    for c in candidates {
        assert!(c["name"].is_string() && c["rms_px"].is_number() && c["score"].is_number(), "{c}");
    }
    assert!(v["explanation"].as_str().unwrap().starts_with("Nothing was left out"));
    assert!(v["compute_seconds"].as_f64().unwrap() > 0.0);
    for png in ["trace.png", "residual.png", "candidates.png"] {
        let bytes = std::fs::read(dir.join(png)).unwrap_or_else(|e| panic!("{png}: {e}"));
        assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n") && bytes.len() > 2000, "{png}");
    }
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(
        md.contains("**Left out: none**")
            && md.contains("(residual.png)")
            && md.contains("| rank | candidate")
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The independent simulator's recording with a tracker's faults: every position left out is
/// listed by its frame number in the file and its mark, and the swapped labels (1 and 3 in
/// that recording) are most of those found swapped.
#[test]
fn the_glitches_left_out_are_listed_by_frame_and_mark() {
    let rec = common::test_data("independent/glitches.csv");
    let out = ringlab(&["diagnose", rec.to_str().unwrap(), "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    let marks = v["glitch_marks"].as_array().expect("glitch_marks");
    assert_eq!(Some(marks.len() as u64), v["glitches"].as_u64());
    assert!(marks.len() >= 40, "{} glitches", marks.len());
    let frames = v["frames"].as_u64().unwrap();
    for g in marks {
        assert!(g["frame"].as_u64().is_some_and(|f| f < frames), "{g}");
        assert!(g["mark"].as_u64().is_some_and(|m| (1..=4).contains(&m)), "{g}");
        assert!(g["kind"] == "outlier" || g["kind"] == "swapped", "{g}");
    }
    let swapped: Vec<u64> = marks
        .iter()
        .filter(|g| g["kind"] == "swapped")
        .map(|g| g["mark"].as_u64().unwrap())
        .collect();
    // A frame may hold an outlier beside the swap, and its mark is counted as swapped too.
    let one_or_three = swapped.iter().filter(|m| **m == 1 || **m == 3).count();
    assert!(swapped.contains(&1) && swapped.contains(&3), "{swapped:?}");
    assert!(one_or_three * 10 >= swapped.len() * 8, "{swapped:?}");
}

#[test]
fn bad_files_and_flags_are_clear_errors() {
    assert_fails_with(&["diagnose", "no-such-file.csv"], &["no-such-file.csv"]);
    let sample = common::test_data("sample-ring.csv");
    let s = sample.to_str().unwrap();
    assert_fails_with(&["diagnose", s, "--candidates", "slip,wind"], &["'wind'", "reynolds_drag"]);
    assert_fails_with(&["diagnose", s, "--evidence", "-1"], &["--evidence"]);
    assert_fails_with(&["diagnose-bench", "--seeds", "0"], &["--seeds"]);
}

/// The bench's table (`docs/diagnosis.md`) made again from rows saved by `--out` (nothing
/// diagnosed): rates, false alarms, the excess beyond the noise, the goals' checks, the text
/// between the markers replaced (a marker quoted in a sentence is not one); bad rows named by
/// file and line.
#[test]
fn the_bench_table_is_made_from_saved_rows() {
    let dir = std::env::temp_dir().join(format!("ringlab-bench-rows-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let header =
        "family,seed,expected,said,before_rms_px,after_rms_px,noise_px,glitches,seconds,frames\n";
    let slip = dir.join("slip.csv");
    std::fs::write(
        &slip,
        format!(
            "{header}single:slip,1,slip,slip,10,0.5,0.5,0,12,1500\nsingle:slip,2,slip,unexplained,8,8,0.5,0,20,1600\nsingle:slip,3,slip,slip,12,0.5,0.5,0,30,1700\n"
        ),
    )
    .unwrap();
    let none = dir.join("none.csv");
    std::fs::write(
        &none,
        format!("{header}camera-known:tilted,1,none,none,0.5,0.5,0.5,0,10,1400\nwithheld:slip,1,unexplained,none,1.2,1.2,0.5,0,9,1400\npair:reynolds_drag+pivot_friction,1,reynolds_drag+pivot_friction,pivot_friction+reynolds_drag,15,0.5,0.5,3,14,1000\nglitches:none,1,none,failed,0,0,0,0,3,1400\nglitches:none,2,none,none,0.5,0.5,0.5,4,8,1400\n"),
    )
    .unwrap();
    let readme = dir.join("diagnosis.md");
    let intro = "intro: the table lies between `<!-- diagnose-bench begin -->` and `<!-- diagnose-bench end -->`\n";
    std::fs::write(
        &readme,
        format!(
            "{intro}<!-- diagnose-bench begin -->\nold table\n<!-- diagnose-bench end -->\nafter\n"
        ),
    )
    .unwrap();
    let args = |files: &str| {
        vec![
            "diagnose-bench".to_string(),
            "--from-csv".into(),
            files.into(),
            "--readme".into(),
            readme.to_str().unwrap().into(),
        ]
    };
    let out = ringlab(
        &args(&format!("{},{}", slip.display(), none.display()))
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&readme).unwrap();
    assert!(
        !text.contains("old table") && text.starts_with(intro) && text.ends_with("after\n"),
        "{text}"
    );
    assert!(text.contains("| camera-known:tilted | none | 1 | 1/1 (false alarms 0%) |"), "{text}");
    assert!(text.contains("| single:slip | slip | 3 | 2/3 (67%) | unexplained | 10.99 -> 0.000 px | >999x | 20.0 / 30.0 s | 25.0 / 35.3 s |"), "{text}");
    // Pairs are right in either order; a `none` where the baseline misses by twice the noise is counted.
    assert!(
        text.contains(
            "| pair:reynolds_drag+pivot_friction | reynolds_drag+pivot_friction | 1 | 1/1 (100%) |"
        ),
        "{text}"
    );
    assert!(text.contains("twice the noise or more: 1."), "{text}");
    // The speed goal, per 2,000 frames: single:slip seed 3 (30 s, 1,700 frames) misses it.
    assert!(text.contains("within 30 s per 2,000 frames: 7 of 8."), "{text}");
    // A diagnosis that failed is a wrong answer in its family, not a false alarm.
    assert!(
        text.contains("| glitches:none | none | 2 | 1/2 (false alarms 0%) | failed |"),
        "{text}"
    );

    // The same recording twice, a row that is not one, a file that is not a table.
    let s = slip.to_str().unwrap();
    assert_fails_with(
        &["diagnose-bench", "--from-csv", &format!("{s},{s}")],
        &["single:slip seed 1", "twice"],
    );
    let bad = dir.join("bad.csv");
    std::fs::write(&bad, format!("{header}single:slip,1,slip,slap,10,0.5,0.5,0,12,1500\n"))
        .unwrap();
    assert_fails_with(
        &["diagnose-bench", "--from-csv", bad.to_str().unwrap()],
        &["bad.csv:2", "'slap'"],
    );
    std::fs::write(&bad, format!("{header}single:slip,1,slip,slip,ten,0.5,0.5,0,12,1500\n"))
        .unwrap();
    assert_fails_with(
        &["diagnose-bench", "--from-csv", bad.to_str().unwrap()],
        &["bad.csv:2", "before_rms_px", "'ten'"],
    );
    std::fs::write(&bad, format!("{header}twin:slip,1,slip,slip,10,0.5,0.5,0,12,1500\n")).unwrap();
    assert_fails_with(
        &["diagnose-bench", "--from-csv", bad.to_str().unwrap()],
        &["bad.csv:2", "'twin:slip' is not a family"],
    );
    std::fs::write(&bad, "frame,x1,y1\n").unwrap();
    assert_fails_with(
        &["diagnose-bench", "--from-csv", bad.to_str().unwrap()],
        &["bad.csv:1", "not a diagnose-bench table"],
    );
    assert_fails_with(
        &["diagnose-bench", "--families", "pair:slip+slip"],
        &["--families", "'pair:slip+slip'"],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A recording the bench keeps is the one it diagnosed, bit for bit: diagnosing the kept file
/// gives the row's answer, misfits, noise and glitches exactly (a file rounded to 0.01 px can
/// end in another valley of the least squares).
#[test]
fn a_kept_bench_recording_gives_its_row_again() {
    let dir = std::env::temp_dir().join(format!("ringlab-bench-keep-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let rows = dir.join("rows.csv");
    let kept = dir.join("kept");
    let out = ringlab(&[
        "diagnose-bench",
        "--families",
        "glitches:slip",
        "--first-seed",
        "7",
        "--seeds",
        "1",
        "--keep",
        kept.to_str().unwrap(),
        "--out",
        rows.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&rows).unwrap();
    let row: Vec<&str> = text.lines().nth(1).expect("one row").split(',').collect();
    let file = kept.join("glitches-slip-seed7.csv");
    let out = ringlab(&["diagnose", file.to_str().unwrap(), "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    let names: Vec<&str> =
        v["left_out_all"].as_array().unwrap().iter().map(|n| n.as_str().unwrap()).collect();
    let said = if names.is_empty() {
        v["left_out"].as_str().unwrap().to_string()
    } else {
        names.join("+")
    };
    assert_eq!(said, row[3], "the kept file's answer against the row's");
    let number = |i: usize| row[i].parse::<f64>().unwrap();
    assert_eq!(v["before"]["rms_px"].as_f64().unwrap(), number(4));
    assert_eq!(v["after"]["rms_px"].as_f64().unwrap(), number(5));
    assert_eq!(v["noise_px"].as_f64().unwrap(), number(6));
    assert_eq!(v["glitches"].as_u64().unwrap(), row[7].parse::<u64>().unwrap());
    assert!(number(7) > 0.0, "this recording has glitches to find: {text}");
    let _ = std::fs::remove_dir_all(&dir);
}
