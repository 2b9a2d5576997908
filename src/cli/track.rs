//! `ringlab track`: a film's marks found frame by frame and written as a recording (the
//! film's flags and its tracking for every command are in `film_args` and `import_args`.

use super::film_args::{describe, interrupt_flag, track_film};
use super::import_args::ImportArgs;
use super::progress::{COUNT_TEMPLATE, LateBar};
use anyhow::{Context, Result, bail};
use clap::Args;
use ringlab::film::TrackOptions;
use std::io::Write;
use std::path::{Path, PathBuf};

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
    let opts = args.import.track_options()?;
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
        // The overlay draws the film as taken: the marks where they were seen in it (the
        // model's, fitted in the table's frame, drawn there too).
        write_overlay_film(&args.film, &opts, &tracked.as_seen(), model.as_deref(), path)?;
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
