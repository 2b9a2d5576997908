//! `ringlab render --view film`: a film of the ring as a lab's camera takes it (straight down,
//! orthographic, a known scale, the marks as discs) and its truth, the marks' true centres as a
//! recording (format v1). The flags of its own ([`FilmFlags`]) and the run.

use super::case_args::CaseArgs;
use super::film_args::interrupt_flag;
use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use ringlab::export::mp4::find_ffmpeg;
use ringlab::export::{ExportError, FilmMarks, FilmSpec, plan_film, write_film};
use ringlab::recording::write_recording;
use ringlab::render::Gpu;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Marks {
    /// Red, green, blue, yellow: marks 1 to 4
    Colours,
    /// Four identical dark dots
    Dark,
    /// Four identical bright dots
    Bright,
}

/// The flags of `--view film` alone.
#[derive(Args, Debug, Clone, Default)]
#[command(next_help_heading = "A film (--view film)")]
pub struct FilmFlags {
    /// Write the marks' true centres in the film as a recording (format v1)
    #[arg(long, value_name = "TRUTH.csv")]
    pub truth: Option<PathBuf>,
    /// The camera's scale at the table [default: the largest, to 3 digits, that keeps the ring
    /// in the picture from --from to --to]
    #[arg(long, value_name = "K")]
    pub px_per_mm: Option<f64>,
    /// What the marks look like [default: colours]
    #[arg(long, value_enum)]
    pub marks: Option<Marks>,
    /// The marks' diameter (mm) [default: 2]
    #[arg(long, value_name = "MM")]
    pub mark_mm: Option<f64>,
    /// Draw at N times the size and average down (anti-aliasing) [default: 3]
    #[arg(long, value_name = "N")]
    pub supersample: Option<u32>,
}

impl FilmFlags {
    /// The first flag given, for a view that is not a film.
    pub fn first_given(&self) -> Option<&'static str> {
        [
            (self.truth.is_some(), "--truth"),
            (self.px_per_mm.is_some(), "--px-per-mm"),
            (self.marks.is_some(), "--marks"),
            (self.mark_mm.is_some(), "--mark-mm"),
            (self.supersample.is_some(), "--supersample"),
        ]
        .into_iter()
        .find_map(|(given, flag)| given.then_some(flag))
    }
}

/// What the film needs of `render`'s flags.
pub struct FilmRequest<'a> {
    pub case: &'a CaseArgs,
    pub video: &'a Path,
    pub from: f64,
    pub to: f64,
    pub fps: Option<f64>,
    pub size: [u32; 2],
    pub flags: &'a FilmFlags,
}

/// Default picture size of a film.
pub const FILM_SIZE: [u32; 2] = [640, 512];
/// Default frame rate: a high-speed camera's, as in the paper.
pub const FILM_FPS: f64 = 300.0;

pub fn run(req: &FilmRequest) -> Result<()> {
    let flags = req.flags;
    let spec = FilmSpec {
        from: req.from,
        to: req.to,
        fps: req.fps.unwrap_or(FILM_FPS),
        size: req.size,
        px_per_mm: flags.px_per_mm,
        marks: match flags.marks.unwrap_or(Marks::Colours) {
            Marks::Colours => FilmMarks::Colours,
            Marks::Dark => FilmMarks::Dark,
            Marks::Bright => FilmMarks::Bright,
        },
        mark_diameter_mm: flags.mark_mm.unwrap_or(2.0),
        supersample: flags.supersample.unwrap_or(3),
    };
    let is_mp4 =
        req.video.extension().and_then(|e| e.to_str()).map(|e| e.eq_ignore_ascii_case("mp4"));
    match is_mp4 {
        Some(true) if find_ffmpeg().is_none() => {
            bail!("--video {}: {}", req.video.display(), ExportError::NoFfmpeg)
        }
        Some(false) => bail!(
            "--video {}: a film is an .mp4 file or a folder (a name without an extension) of PNG frames",
            req.video.display()
        ),
        _ => {}
    }
    check_folder("--video", req.video)?;
    if let Some(t) = &flags.truth {
        check_folder("--truth", t)?;
    }
    let case = req.case.case()?;
    let plan = plan_film(&case, &spec)?;
    let gpu = Gpu::new()?;
    let interrupted = interrupt_flag();
    let bar = super::progress::LateBar::new(super::progress::COUNT_TEMPLATE);
    let report = write_film(&gpu, &plan, req.video, &mut |done, total| {
        bar.update(done as u64, total as u64, "frames".into());
        !interrupted.load(Ordering::Relaxed)
    })
    .with_context(|| format!("--video {}", req.video.display()))?;
    bar.finish();
    if let Some(path) = &flags.truth {
        write_truth(path, &plan.truth)?;
    }
    let visible = plan.truth.mark_count();
    let [w, h] = spec.size;
    println!(
        "wrote {} ({} frames of {w}x{h} at {} frames/s, frames {} to {} of the run; {:.1} kB; {:.1} s, {:.0} ms a frame, {})",
        req.video.display(),
        report.frames,
        spec.fps,
        plan.truth.first_frame,
        plan.truth.first_frame + report.frames as u64 - 1,
        report.bytes as f64 / 1000.0,
        report.seconds,
        1000.0 * report.seconds / report.frames.max(1) as f64,
        gpu.adapter.name
    );
    println!(
        "camera: straight down, orthographic, {} px/mm, the table's ({:.3}, {:.3}) mm at the picture's centre; marks: {}, {} mm",
        plan.camera.px_per_mm,
        plan.centre_mm[0],
        plan.centre_mm[1],
        spec.marks.name(),
        spec.mark_diameter_mm
    );
    if let Some(path) = &flags.truth {
        println!(
            "wrote {} (the marks' true centres: {visible} of {} in the picture)",
            path.display(),
            4 * report.frames
        );
    }
    Ok(())
}

/// Writes the truth whole or not at all (a temporary file renamed when complete).
fn write_truth(path: &Path, truth: &ringlab::recording::Recording) -> Result<()> {
    let tmp = path.with_extension("csv.part");
    let written = std::fs::File::create(&tmp).and_then(|f| {
        let mut out = std::io::BufWriter::new(f);
        write_recording(&mut out, truth)?;
        std::io::Write::flush(&mut out)
    });
    if let Err(e) = written.and_then(|_| std::fs::rename(&tmp, path)) {
        std::fs::remove_file(&tmp).ok();
        bail!("--truth {}: {e}", path.display());
    }
    Ok(())
}

/// The folder `path` goes into must exist.
pub fn check_folder(flag: &str, path: &Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty())
        && !dir.is_dir()
    {
        bail!("{flag} {}: the folder {} does not exist", path.display(), dir.display());
    }
    Ok(())
}
