//! `ringlab import` and trackers' files on the command line: the import written and read back,
//! `fit` on the tracker's file directly, a folder diagnosed in shards and merged.

mod common;

use ringlab::recording::{Recording, read_recording};
use std::path::{Path, PathBuf};

fn sample() -> Recording {
    read_recording(&common::test_data("sample-ring.csv")).expect("the sample reads")
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ringlab-cli-import-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn write(path: &Path, text: &str) -> PathBuf {
    std::fs::write(path, text).expect("writes");
    path.to_path_buf()
}

#[test]
fn import_command_writes_a_recording_that_fit_and_diagnose_read_alike() {
    let rec = sample();
    let d = dir("cli");
    let text = common::deeplabcut_text(&rec);
    let dlc = write(&d.join("ring.csv"), &text);
    let out = d.join("ring.rec.csv");
    let s = |p: &Path| p.display().to_string();
    let body = [
        "--shape",
        "ring",
        "--outer-radius-mm",
        "20.66",
        "--width-mm",
        "18",
        "--thickness-mm",
        "1",
    ];
    let dlc_name = s(&dlc);
    let mut args = vec![
        "import",
        "--from",
        "dlc",
        &dlc_name,
        "--fps",
        "300",
        "--px-per-mm",
        "3.364764",
        "--marks",
        "m1,m2,m3,m4",
    ];
    args.extend(body);
    let o = s(&out);
    args.extend(["--out", &o]);
    let r = common::ringlab(&args);
    let stdout = String::from_utf8_lossy(&r.stdout);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(stdout.contains("read as DeepLabCut CSV: marks 1-4 = m1, m2, m3, m4"), "{stdout}");
    let written = read_recording(&out).expect("the import reads as format v1");
    assert_eq!(written.frames.len(), rec.frames.len());

    // `fit` reads the tracker's file directly, with the same flags, to the same numbers.
    let fit_json = |extra: &[&str]| -> serde_json::Value {
        let r = common::ringlab(&[&["fit", "--json"], extra].concat());
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        serde_json::from_slice(&r.stdout).expect("json")
    };
    let direct = fit_json(
        &[
            &[
                s(&dlc).as_str(),
                "--fps",
                "300",
                "--px-per-mm",
                "3.364764",
                "--marks",
                "m1,m2,m3,m4",
            ][..],
            &body,
        ]
        .concat(),
    );
    let via_file = fit_json(&[o.as_str()]);
    // (The recording holds hundredths of a pixel, the DeepLabCut file thousandths.)
    for i in 0..3 {
        let (a, b) = (direct["c"][i].as_f64().unwrap(), via_file["c"][i].as_f64().unwrap());
        assert!((a - b).abs() < 1e-3 * b, "C{}: {a} read directly, {b} through the import", i + 1);
    }

    // What the file lacks is asked for by name; a v1 file is read by its own header, and
    // flags meant for trackers' files (a folder may hold both) are said not to apply.
    common::assert_fails_with(&["fit", &s(&dlc), "--px-per-mm", "3.3"], &["ring.csv", "--fps"]);
    let r = common::ringlab(&["fit", &o, "--fps", "250", "--json"]);
    assert!(r.status.success());
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(
        err.contains("a ringlab v1 recording, read by its own header (the given fps not applied)"),
        "{err}"
    );
    let r = common::ringlab(&["fit", &o, "--from", "trackmate", "--json"]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(err.contains("read by its own header (the given format not applied)"), "{err}");
    common::assert_fails_with(
        &["import", &s(&dlc), "--out", &o, "--from", "excel"],
        &["--from 'excel'", "dlc, tracker, trackmate, csv"],
    );
}

/// Reads a `--table` CSV: (file, left_out, error) per row.
fn table_rows(path: &Path) -> Vec<(String, String, String)> {
    let text = std::fs::read_to_string(path).expect("the table is written");
    let mut r = csv_rows(&text);
    let header = r.remove(0);
    assert_eq!(header[0], "file");
    let col = |name: &str| header.iter().position(|h| h == name).expect(name);
    r.iter().map(|c| (c[0].clone(), c[col("left_out")].clone(), c[col("error")].clone())).collect()
}

/// Enough CSV for the tables: quoted cells may hold commas.
fn csv_rows(text: &str) -> Vec<Vec<String>> {
    text.lines()
        .map(|l| {
            let (mut cells, mut cell, mut quoted) = (Vec::new(), String::new(), false);
            for ch in l.chars() {
                match ch {
                    '"' => quoted = !quoted,
                    ',' if !quoted => cells.push(std::mem::take(&mut cell)),
                    c => cell.push(c),
                }
            }
            cells.push(cell);
            cells
        })
        .collect()
}

#[test]
fn diagnose_shards_cover_a_folder_exactly_once_and_merge() {
    let rec = sample();
    let d = dir("shards");
    let folder = d.join("recordings");
    std::fs::create_dir_all(&folder).unwrap();
    let short = |n: usize| Recording { frames: rec.frames[..n].to_vec(), ..rec.clone() };
    for (name, r) in [("a.csv", short(400)), ("e.csv", short(450))] {
        let mut bytes = Vec::new();
        ringlab::recording::write_recording(&mut bytes, &r).unwrap();
        std::fs::write(folder.join(name), bytes).unwrap();
    }
    let dlc = common::deeplabcut_text(&short(400));
    write(&folder.join("c-dlc.csv"), &dlc);
    write(&folder.join("b.csv"), "not a recording\n");
    write(
        &folder.join("d.csv"),
        "# ringlab-recording v1\n# fps = -3\n# px_per_mm = 3\n# shape = disk\n# outer_radius_mm = 10\n# width_mm = 2\nframe,x1,y1,x2,y2,x3,y3,x4,y4\n",
    );
    let mut files: Vec<String> = std::fs::read_dir(&folder)
        .unwrap()
        .map(|e| e.unwrap().path().display().to_string())
        .collect();
    files.reverse();
    let flags = [
        "--fps",
        "300",
        "--px-per-mm",
        "3.364764",
        "--marks",
        "m1,m2,m3,m4",
        "--preset",
        "paper-ring",
        "--threads",
        "1",
    ];
    let mut tables = Vec::new();
    let mut seen: Vec<String> = Vec::new();
    for i in 0..3 {
        let table = d.join(format!("shard{i}.csv")).display().to_string();
        let shard = format!("{i}/3");
        let args: Vec<&str> = [
            &["diagnose"][..],
            &files.iter().map(String::as_str).collect::<Vec<_>>(),
            &flags,
            &["--table", &table, "--shard", &shard],
        ]
        .concat();
        let out = common::ringlab(&args);
        let rows = table_rows(Path::new(&table));
        let errors = rows.iter().filter(|r| r.1 == "error").count();
        assert_eq!(
            out.status.success(),
            errors == 0,
            "shard {i}: exit status against {errors} error rows"
        );
        for (file, left_out, error) in rows {
            match Path::new(&file).file_name().unwrap().to_str().unwrap() {
                "b.csv" => assert!(error.contains("b.csv") && error.contains("--from"), "{error}"),
                "d.csv" => assert!(
                    error.contains("d.csv:2: fps = -3 must be greater than zero"),
                    "{error}"
                ),
                _ => assert!(left_out != "error" && error.is_empty(), "{file}: {left_out} {error}"),
            }
            seen.push(file);
        }
        tables.push(table);
    }
    // Sorted order, every third file to each shard: each file exactly once.
    let mut sorted = files.clone();
    sorted.sort();
    let mut got = seen.clone();
    got.sort();
    assert_eq!(got, sorted, "the shards cover the folder exactly once");
    assert_eq!(seen.len(), 5);

    let all = d.join("all.csv").display().to_string();
    let merge: Vec<&str> = [
        &["diagnose", "--merge"][..],
        &tables.iter().map(String::as_str).collect::<Vec<_>>(),
        &["--table", &all],
    ]
    .concat();
    let out = common::ringlab(&merge);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let merged: Vec<String> = table_rows(Path::new(&all)).into_iter().map(|r| r.0).collect();
    assert_eq!(merged, sorted, "merged in file order");
    common::assert_fails_with(
        &["diagnose", "--merge", &tables[0], &tables[0], "--table", &all],
        &["in two shards", "shard0.csv:2"],
    );
}
