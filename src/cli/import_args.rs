//! Flags shared by every command that reads a recording: what a lab tracker's file does not
//! say (frame rate, scale, the body, which points are the marks).

use anyhow::{Context, Result, bail};
use clap::Args;
use ringlab::config::load_preset;
use ringlab::film::{CameraGiven, MarkStyle, Roi, TrackOptions};
use ringlab::physics::Shape;
use ringlab::recording::import::{BodyMm, Format, ImportOptions, Imported, LengthUnit, import};
use std::path::PathBuf;

#[derive(Args, Debug, Clone, Default)]
#[command(next_help_heading = "Reading a tracker's file (see `ringlab import --help`)")]
pub struct ImportArgs {
    /// The file's format: dlc, tracker (data tables or .trk), trackmate, csv (default: told
    /// from the file; ringlab v1 recordings are always recognised)
    #[arg(long, value_name = "FORMAT")]
    pub from: Option<String>,
    /// Frames per second (where the file does not say)
    #[arg(long)]
    pub fps: Option<f64>,
    /// Pixels per mm at the table (where the file does not say)
    #[arg(long)]
    pub px_per_mm: Option<f64>,
    /// The four marks' names (bodyparts, track ids, point masses) in cyclic order round the rim
    /// (default: the first four in the file); for a film, what they look like: colours, dark,
    /// bright or auto (default)
    #[arg(long, value_name = "A,B,C,D")]
    pub marks: Option<String>,
    /// DeepLabCut: points below this likelihood are missing marks
    #[arg(long, default_value_t = ringlab::recording::import::DEFAULT_MIN_LIKELIHOOD)]
    pub min_likelihood: f64,
    /// The body from a preset (see `ringlab presets`)
    #[arg(long, value_name = "NAME", conflicts_with_all = ["shape", "outer_radius_mm", "width_mm", "thickness_mm"])]
    pub preset: Option<String>,
    /// The body's shape: ring or disk
    #[arg(long)]
    pub shape: Option<String>,
    /// The body's outer radius (mm)
    #[arg(long)]
    pub outer_radius_mm: Option<f64>,
    /// The body's width along its axis (mm)
    #[arg(long)]
    pub width_mm: Option<f64>,
    /// A ring's wall thickness (mm)
    #[arg(long)]
    pub thickness_mm: Option<f64>,
    /// Plain CSV: the frame column (or time:NAME, in s) and x1,y1,..,x4,y4, by name or number
    #[arg(long, value_name = "F,X1,Y1,..")]
    pub columns: Option<String>,
    /// The positions' unit where the file does not say it: px, um, mm, cm, m (Tracker tables
    /// need it; plain CSV default px)
    #[arg(long)]
    pub unit: Option<String>,
    /// Plain CSV: y grows upward
    #[arg(long)]
    pub y_up: bool,
    #[command(flatten)]
    pub film: super::film_args::FilmArgs,
}

fn list(s: &str) -> Vec<String> {
    s.split(',').map(|p| p.trim().to_string()).collect()
}

impl ImportArgs {
    /// The tracking options from the shared flags. `--marks` names the marks' style for a film.
    pub fn track_options(&self) -> Result<TrackOptions> {
        let (import, film) = (self, &self.film);
        let style = match import.marks.as_deref() {
            None => MarkStyle::Auto,
            Some(s) => MarkStyle::parse(s).with_context(|| {
                format!("--marks '{s}': for a film, one of {}", MarkStyle::NAMES)
            })?,
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
            camera: CameraGiven {
                distance_mm: film.camera_distance_mm,
                tilt_deg: film.camera_tilt_deg,
            },
            body,
        })
    }

    /// The format named by `--from`.
    pub fn format(&self) -> Result<Option<Format>> {
        self.from
            .as_deref()
            .map(|f| {
                Format::parse(f)
                    .with_context(|| format!("--from '{f}': not one of {}", Format::NAMES))
            })
            .transpose()
    }

    /// The body from `--preset` or the body flags (none when neither is given).
    pub fn body(&self) -> Result<Option<BodyMm>> {
        if let Some(name) = &self.preset {
            return Ok(Some(BodyMm::of_case(&load_preset(name)?).map_err(anyhow::Error::msg)?));
        }
        let any = self.shape.is_some()
            || self.outer_radius_mm.is_some()
            || self.width_mm.is_some()
            || self.thickness_mm.is_some();
        if !any {
            return Ok(None);
        }
        let shape = self.shape.as_deref().context("the body needs --shape ring|disk")?;
        let shape =
            Shape::parse(shape).with_context(|| format!("--shape '{shape}': not ring or disk"))?;
        let r = self.outer_radius_mm.context("the body needs --outer-radius-mm")?;
        let h = self.width_mm.context("the body needs --width-mm")?;
        if shape == Shape::Ring && self.thickness_mm.is_none() {
            bail!("a ring needs --thickness-mm (its wall)");
        }
        Ok(Some(BodyMm { shape, outer_radius_mm: r, width_mm: h, thickness_mm: self.thickness_mm }))
    }

    pub fn options(&self) -> Result<ImportOptions> {
        let positive = |v: Option<f64>, flag: &str| -> Result<Option<f64>> {
            match v {
                Some(x) if !(x.is_finite() && x > 0.0) => {
                    bail!("{flag} = {x}: must be a positive number")
                }
                v => Ok(v),
            }
        };
        Ok(ImportOptions {
            fps: positive(self.fps, "--fps")?,
            px_per_mm: positive(self.px_per_mm, "--px-per-mm")?,
            marks: self.marks.as_deref().map(list),
            min_likelihood: self.min_likelihood,
            body: self.body()?,
            columns: self.columns.as_deref().map(list),
            unit: self
                .unit
                .as_deref()
                .map(|u| {
                    LengthUnit::parse(u)
                        .with_context(|| format!("--unit '{u}': not one of {}", LengthUnit::NAMES))
                })
                .transpose()?,
            y_up: self.y_up,
        })
    }

    /// Reads the files as one recording (format v1 or a tracker's).
    pub fn load(&self, files: &[PathBuf]) -> Result<Imported> {
        Ok(import(files, self.format()?, &self.options()?)?)
    }
}

/// What an import did, in lines for the terminal (nothing for a plain v1 file).
pub fn describe(imported: &Imported) -> Vec<String> {
    let r = &imported.report;
    if r.source == ringlab::recording::import::Source::Ringlab {
        return r.notes.iter().map(|n| format!("note: {n}")).collect();
    }
    let rec = &imported.recording;
    let usable = rec.frames.iter().filter(|f| ringlab::recording::is_usable(f)).count();
    let mut out = vec![format!(
        "read as {}: marks 1-4 = {}; {} frames ({usable} usable), {} marks found, {} blank, {} below likelihood",
        r.source.name(),
        r.marks.join(", "),
        rec.frames.len(),
        rec.mark_count(),
        r.blank,
        r.low_likelihood
    )];
    out.extend(r.notes.iter().map(|n| format!("note: {n}")));
    out
}

/// One recording from one file, what the import did said on stderr (stdout may be JSON).
pub fn load_one(
    args: &ImportArgs,
    file: &std::path::Path,
) -> Result<ringlab::recording::Recording> {
    if ringlab::film::is_film(file) {
        return load_film(args, file);
    }
    let imported = args.load(&[file.to_path_buf()])?;
    for line in describe(&imported) {
        eprintln!("{line}");
    }
    Ok(imported.recording)
}

/// A film tracked first (`ringlab track`'s flags), what the tracking found said on stderr.
pub fn load_film(
    args: &ImportArgs,
    file: &std::path::Path,
) -> Result<ringlab::recording::Recording> {
    let opts = args.track_options()?;
    let tracked = super::film_args::track_film(file, &opts)?;
    for line in super::film_args::describe(&tracked) {
        eprintln!("{line}");
    }
    Ok(tracked.recording)
}
