//! `ringlab bench --track`: how fast a film is decoded and tracked, per 2,000 frames (the
//! goal: 20 s on 2 cores for 1280x1024), and whether the memory held stays flat as the frames
//! pass (the peak resident size after each pass).

use anyhow::{Context, Result};
use ringlab::film::{TrackOptions, track};
use ringlab::recording::import::BodyMm;
use serde::Serialize;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

#[derive(Serialize)]
struct TrackBench {
    film: String,
    width_px: usize,
    height_px: usize,
    frames_per_pass: usize,
    passes: usize,
    seconds_per_2000_frames: f64,
    frames_per_second: f64,
    /// Peak resident memory (MiB) after each pass: flat when nothing grows with the frames.
    peak_rss_mib: Vec<f64>,
}

/// The process's peak resident size (Linux: VmHWM), MiB.
fn peak_rss_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1).and_then(|v| v.parse::<f64>().ok()))
        })
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

pub fn run(film: &Path, json: bool) -> Result<()> {
    let body = BodyMm::of_case(&ringlab::config::load_preset("steel-ring")?)
        .map_err(anyhow::Error::msg)?;
    let opts = TrackOptions::for_body(body);
    let cancel = AtomicBool::new(false);
    let (mut frames, mut seconds, mut passes) = (0usize, 0.0, 0usize);
    let mut peaks = Vec::new();
    let mut size = (0, 0, 0);
    while frames < 2000 {
        let clock = Instant::now();
        let t = track(film, &opts, &mut |_, _| {}, &cancel)
            .with_context(|| format!("the benchmark's film {}", film.display()))?;
        seconds += clock.elapsed().as_secs_f64();
        frames += t.report.frames;
        passes += 1;
        size = (t.report.width_px, t.report.height_px, t.report.frames);
        peaks.push(peak_rss_mib());
    }
    let report = TrackBench {
        film: film.display().to_string(),
        width_px: size.0,
        height_px: size.1,
        frames_per_pass: size.2,
        passes,
        seconds_per_2000_frames: seconds / frames as f64 * 2000.0,
        frames_per_second: frames as f64 / seconds,
        peak_rss_mib: peaks,
    };
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!(
            "tracking {} ({}x{}, {} frames a pass, {} passes): {:.1} s per 2,000 frames ({:.0} frames/s), decoding included",
            report.film,
            report.width_px,
            report.height_px,
            report.frames_per_pass,
            report.passes,
            report.seconds_per_2000_frames,
            report.frames_per_second
        );
        let peaks: Vec<String> = report.peak_rss_mib.iter().map(|m| format!("{m:.0}")).collect();
        println!("peak memory after each pass (MiB): {}", peaks.join(", "));
    }
    Ok(())
}
