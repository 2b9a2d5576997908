//! A film wherever a command reads a recording: the flags it adds (`FilmArgs`, in
//! `ImportArgs`), the tracking with a progress bar and Ctrl-C, and the report's lines. A leaf:
//! `import_args` and `track` both use it.

use super::progress::{COUNT_TEMPLATE, LateBar};
use anyhow::Result;
use clap::Args;
use ringlab::film::{TrackOptions, TrackedFilm};
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

/// Flags for a film, shared by every command that reads a recording.
#[derive(Args, Debug, Clone, Default)]
#[command(next_help_heading = "Reading a film (a video file or a folder of frames)")]
pub struct FilmArgs {
    /// Look for the marks inside this rectangle only: X,Y,W,H in pixels
    #[arg(long, value_name = "X,Y,W,H")]
    pub roi: Option<String>,
    /// First frame to track (counted from 0)
    #[arg(long, default_value_t = 0)]
    pub from_frame: u64,
    /// Last frame to track (inclusive; default: the film's last)
    #[arg(long)]
    pub to_frame: Option<u64>,
    /// The camera's distance (mm) from the table along its axis, where known (default: measured
    /// from the ring; the table's scale is then measured through that camera)
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    pub camera_distance_mm: Option<f64>,
    /// The camera's tilt (degrees) from the vertical about the image's horizontal, positive
    /// with the camera towards the image's bottom edge, where known (default: measured from
    /// the ring)
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    pub camera_tilt_deg: Option<f64>,
}

/// Ctrl-C sets this flag (once per process) instead of ending at once, so that nothing is left
/// half-written.
pub fn interrupt_flag() -> Arc<AtomicBool> {
    static FLAG: std::sync::OnceLock<Arc<AtomicBool>> = std::sync::OnceLock::new();
    FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        let f = flag.clone();
        // Where no handler can be set, Ctrl-C ends the process as before.
        ctrlc::set_handler(move || f.store(true, std::sync::atomic::Ordering::Relaxed)).ok();
        flag
    })
    .clone()
}

/// Tracks a film with a progress bar.
pub fn track_film(path: &Path, opts: &TrackOptions) -> Result<TrackedFilm> {
    let cancel = interrupt_flag();
    let bar = LateBar::new(COUNT_TEMPLATE);
    let mut progress = |done: u64, total: Option<u64>| {
        if done.is_multiple_of(16) {
            bar.update(done, total.unwrap_or(done).max(done), "tracking".into());
        }
    };
    let tracked = ringlab::film::track(path, opts, &mut progress, &cancel);
    bar.finish();
    Ok(tracked?)
}

/// What the tracking found, in lines for the terminal.
pub fn describe(t: &TrackedFilm) -> Vec<String> {
    let r = &t.report;
    let visible_guess = r.frames * 4;
    let sig = r
        .centre_sigma_px
        .iter()
        .map(|s| s.map_or("-".to_string(), |v| format!("{v:.2}")))
        .collect::<Vec<_>>()
        .join(", ");
    let mut out = vec![
        format!(
            "tracked {} frames of {}x{} at {} fps ({} marks), found from frame {}: {} marks ({:.1}% of 4 a frame), {} left out as ambiguous, lost and found again {} times",
            r.frames,
            r.width_px,
            r.height_px,
            r.fps,
            r.style.name(),
            r.acquired_at,
            r.marks_found,
            100.0 * r.marks_found as f64 / visible_guess.max(1) as f64,
            r.left_out_ambiguous,
            r.reacquired
        ),
        format!(
            "centre's error from the pixels' noise (median, px per coordinate), marks 1-4: {sig}"
        ),
    ];
    let m = &r.camera_motion;
    out.push(format!(
        "camera's motion from the table: up to {:.2} px and {:.3} degrees from the first frame (registration error {:.3} px){}",
        m.largest_shift_px,
        m.largest_turn_deg,
        m.registration_sigma_px,
        if m.hand_held { ": held in the hand, marks written in the first frame's camera" } else { ": still, marks written as seen" }
    ));
    let renumbered = r.stage("join").map_or(0, |s| s.renumbered);
    if renumbered > 0 {
        out.push(format!(
            "dots found again after {renumbered} losses numbered as before from the ring's turning across each"
        ));
    }
    let stages: Vec<String> =
        r.stages.iter().map(|s| format!("{} {}", s.name, s.left_out)).collect();
    out.push(format!("marks left out by the stages after the follower: {}", stages.join(", ")));
    if let Some(s) = &r.ring_scale {
        out.push(format!(
            "scale from the ring: {:.4} +- {:.4} px/mm over {} frames, holding {:.1} mm above the table{}",
            s.px_per_mm,
            s.sigma,
            s.frames,
            s.height_mm,
            if s.camera_is_near() { " (a near camera: see the note)" } else { " (a far camera: the same at the table)" }
        ));
    }
    if let Some(c) = &r.camera {
        let distance = c
            .distance_mm
            .map_or("far".to_string(), |d| format!("{d:.0} +- {:.0} mm away", c.distance_sigma_mm));
        let taken = if c.is_tripod() {
            "written in the header"
        } else if c.is_believed() {
            "looking nearly straight down: left to the ring's scale and the diagnosis"
        } else {
            "not clearly other than far and straight down: not written"
        };
        out.push(format!(
            "camera from the ring over {} frames: {distance}, tilted {:.2} +- {:.2} degrees, table scale {:.4} +- {:.4} px/mm; marks' figure {:.3} px through it, {:.3} px far and straight down ({taken})",
            c.frames, c.tilt_deg, c.tilt_sigma_deg, c.px_per_mm, c.px_per_mm_sigma, c.figure_px, c.far_figure_px
        ));
    }
    out.push(format!("scale written: {:.5} px/mm", r.px_per_mm));
    out.extend(r.notes.iter().map(|n| format!("note: {n}")));
    out
}
