//! `ringlab track`: a film's marks found frame by frame and written as a recording; and the
//! film read the same way wherever a command takes a recording (`import_args::load_one`).

use super::import_args::ImportArgs;
use super::progress::{COUNT_TEMPLATE, LateBar};
use anyhow::{Context, Result, bail};
use clap::Args;
use ringlab::film::{MarkStyle, Roi, TrackOptions, TrackedFilm};
use std::io::Write;
use std::path::{Path, PathBuf};
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
}

#[derive(Args, Debug)]
pub struct TrackArgs {
    /// The film: a video file (MP4, MOV, AVI, MKV: what ffmpeg decodes) or a folder of
    /// numbered PNG, JPEG or TIFF frames (then --fps)
    #[arg(value_name = "VIDEO")]
    pub film: PathBuf,
    /// The recording to write (format v1)
    #[arg(long, value_name = "REC.csv")]
    pub out: PathBuf,
    /// Also write each centre's standard error (px) per frame and mark as CSV
    #[arg(long, value_name = "ERRORS.csv")]
    pub errors: Option<PathBuf>,
    /// Also write the film with the tracked marks and the path of A drawn over it (MP4)
    #[arg(long, value_name = "OUT.mp4")]
    pub overlay: Option<PathBuf>,
    /// With --overlay: fit the model first and draw its marks and path of A too
    #[arg(long, requires = "overlay")]
    pub fit: bool,
    /// Print the report as JSON
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub import: ImportArgs,
}

/// The tracking options from the shared flags. `--marks` names the marks' style for a film.
pub fn options(import: &ImportArgs, film: &FilmArgs) -> Result<TrackOptions> {
    let style = match import.marks.as_deref() {
        None => MarkStyle::Auto,
        Some(s) => MarkStyle::parse(s)
            .with_context(|| format!("--marks '{s}': for a film, one of {}", MarkStyle::NAMES))?,
    };
    let roi = film
        .roi
        .as_deref()
        .map(|r| {
            Roi::parse(r)
                .with_context(|| format!("--roi '{r}': not X,Y,W,H (pixels, W and H positive)"))
        })
        .transpose()?;
    let o = import.options()?;
    let body = o.body.context(
        "a film does not say the body: give --preset NAME (see `ringlab presets`) or --shape, --outer-radius-mm, --width-mm, --thickness-mm",
    )?;
    if let Some(to) = film.to_frame
        && to < film.from_frame
    {
        bail!("--to-frame {to} comes before --from-frame {}", film.from_frame);
    }
    Ok(TrackOptions {
        style,
        roi,
        from_frame: film.from_frame,
        to_frame: film.to_frame,
        fps: o.fps,
        px_per_mm: o.px_per_mm,
        body,
    })
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
    out.push(format!("scale written: {:.5} px/mm", r.px_per_mm));
    out.extend(r.notes.iter().map(|n| format!("note: {n}")));
    out
}

/// Writes `bytes` to `path` through a temporary file beside it, renamed when whole.
pub fn write_whole(path: &Path, bytes: &[u8]) -> Result<()> {
    let name = path.file_name().with_context(|| format!("{}: not a file name", path.display()))?;
    let tmp = path.with_file_name(format!(".{}.part", name.to_string_lossy()));
    let write = || -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    };
    write().map_err(|e| {
        std::fs::remove_file(&tmp).ok();
        anyhow::anyhow!("cannot write {}: {e}", path.display())
    })
}

pub fn run(args: &TrackArgs) -> Result<()> {
    if !ringlab::film::is_film(&args.film) && args.film.exists() {
        bail!(
            "{}: not a film (a video file: {}; or a folder of frames)",
            args.film.display(),
            ringlab::film::VIDEO_EXTENSIONS.join(", ")
        );
    }
    let opts = options(&args.import, &args.import.film)?;
    let tracked = track_film(&args.film, &opts)?;
    let mut bytes = Vec::new();
    ringlab::recording::write_recording(&mut bytes, &tracked.recording)?;
    ringlab::recording::parse_recording(&bytes, &args.out)
        .context("the written recording does not read back")?;
    if let Some(path) = &args.errors {
        let mut e = String::from("frame,s1,s2,s3,s4\n");
        for (i, s) in tracked.sigma.iter().enumerate() {
            let cells: Vec<String> =
                s.iter().map(|v| v.map_or(String::new(), |v| format!("{v:.3}"))).collect();
            e.push_str(&format!("{},{}\n", tracked.recording.frame_number(i), cells.join(",")));
        }
        write_whole(path, e.as_bytes())?;
    }
    write_whole(&args.out, &bytes)?;
    if let Some(path) = &args.overlay {
        let model = if args.fit { Some(fitted_marks(&tracked.recording)?) } else { None };
        write_overlay_film(&args.film, &opts, &tracked.recording, model.as_deref(), path)?;
        println!("overlay written: {}", path.display());
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&tracked.report)?);
    } else {
        for line in describe(&tracked) {
            println!("{line}");
        }
        println!("written: {}", args.out.display());
    }
    Ok(())
}

/// The model fitted to a recording, as its marks at every frame.
fn fitted_marks(rec: &ringlab::recording::Recording) -> Result<Vec<Option<[[f64; 2]; 4]>>> {
    let cancel = interrupt_flag();
    let fit = ringlab::analysis::fit::fit(
        rec,
        &ringlab::analysis::fit::FitOptions::default(),
        &|_| {},
        &cancel,
    )
    .map_err(|e| anyhow::anyhow!("the fit for the overlay failed: {e}"))?;
    Ok(fit.predicted_marks(&rec.frames))
}

/// The film with the overlay drawn, as MP4, with a progress bar.
pub fn write_overlay_film(
    film: &Path,
    opts: &TrackOptions,
    rec: &ringlab::recording::Recording,
    model: Option<&[Option<[[f64; 2]; 4]>]>,
    out: &Path,
) -> Result<()> {
    let cancel = interrupt_flag();
    let bar = LateBar::new(COUNT_TEMPLATE);
    let overlay = ringlab::session::overlay::Overlay { tracked: rec, model };
    let r = ringlab::export::overlay::write_overlay(film, opts, &overlay, out, &mut |i, n| {
        if i.is_multiple_of(16) {
            bar.update(i as u64, n as u64, "overlay".into());
        }
        !cancel.load(std::sync::atomic::Ordering::Relaxed)
    });
    bar.finish();
    Ok(r?)
}
