//! `ringlab bench --recording`: the speed of the recording side (reader, recovery, fit).

use anyhow::{Context, Result};
use ringlab::analysis::fit::{FitOptions, fit};
use ringlab::recording::{Recording, parse_recording, read_recording, recover, write_recording};
use serde::Serialize;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// Frames of the reader benchmark (the figure: 100,000 frames in 1 s or less).
pub const READ_FRAMES: usize = 100_000;

#[derive(Serialize, Debug)]
struct RecordingBench {
    read_frames: usize,
    read_bytes: usize,
    read_ms: f64,
    read_file_ms: f64,
    recover_ms: f64,
    fit_sample_seconds: Option<f64>,
    fit_threads: usize,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// The sample's frames repeated and renumbered to `n` frames.
fn long_recording(sample: &Recording, n: usize) -> Recording {
    let frames = (0..n).map(|i| sample.frames[i % sample.frames.len()]).collect();
    Recording { frames, first_frame: 0, header: sample.header.clone() }
}

pub fn run(sample_path: &Path, repeats: usize, skip_fit: bool, json: bool) -> Result<()> {
    let sample = read_recording(sample_path)?;
    let long = long_recording(&sample, READ_FRAMES);
    let mut bytes = Vec::new();
    write_recording(&mut bytes, &long)?;
    let mut times = Vec::new();
    for _ in 0..repeats.max(1) {
        let clock = Instant::now();
        let rec = parse_recording(&bytes, Path::new("bench.csv"))?;
        times.push(clock.elapsed().as_secs_f64() * 1e3);
        std::hint::black_box(rec);
    }
    let read_ms = median(times);
    let file = std::env::temp_dir().join(format!("ringlab-bench-{}.csv", std::process::id()));
    std::fs::write(&file, &bytes).with_context(|| format!("writing {}", file.display()))?;
    let mut times = Vec::new();
    for _ in 0..repeats.max(1) {
        let clock = Instant::now();
        let rec = read_recording(&file)?;
        times.push(clock.elapsed().as_secs_f64() * 1e3);
        std::hint::black_box(rec);
    }
    std::fs::remove_file(&file).ok();
    let read_file_ms = median(times);
    let clock = Instant::now();
    std::hint::black_box(recover(&long)?);
    let recover_ms = clock.elapsed().as_secs_f64() * 1e3;
    let fit_sample_seconds = if skip_fit {
        None
    } else {
        let mut times = Vec::new();
        for _ in 0..repeats.clamp(1, 3) {
            let r = fit(&sample, &FitOptions::default(), &|_| {}, &AtomicBool::new(false))?;
            times.push(r.compute_seconds);
        }
        Some(median(times))
    };
    let report = RecordingBench {
        read_frames: READ_FRAMES,
        read_bytes: bytes.len(),
        read_ms,
        read_file_ms,
        recover_ms,
        fit_sample_seconds,
        fit_threads: rayon::current_num_threads(),
    };
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    println!(
        "read {} frames ({:.1} MB) from memory: {:.1} ms, from a file: {:.1} ms (median of {})",
        report.read_frames,
        report.read_bytes as f64 / 1e6,
        report.read_ms,
        report.read_file_ms,
        repeats.max(1)
    );
    println!("recover the motion of {} frames: {:.0} ms", report.read_frames, report.recover_ms);
    if let Some(s) = report.fit_sample_seconds {
        println!(
            "fit {} ({} frames): {:.2} s on {} threads",
            sample_path.display(),
            sample.frames.len(),
            s,
            report.fit_threads
        );
    }
    Ok(())
}
