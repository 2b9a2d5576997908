//! Films of a spinning ring: the four marks found in each frame and written as a recording.
//!
//! Stages of [`track`]: open the film ([`source`]: ffmpeg for video files, the `image` crate
//! for a folder of frames), find the four marks in the first frames ([`find`]; dots confirmed
//! by the next frame, [`acquire`]), follow them frame by frame ([`follow`], sub-pixel centres
//! by [`centre`]), measure the scale from the ring where none is given ([`scale`]), and
//! assemble the recording with a report of what was found, left out, and the centres' error.

pub mod acquire;
pub mod assemble;
pub mod camera_fit;
pub mod camera_motion;
pub mod centre;
pub mod choice;
pub mod error;
pub mod find;
pub mod follow;
pub mod frame;
pub mod lost;
pub mod pass;
pub mod phase;
pub mod pose_error;
pub mod register;
pub mod rim;
pub mod scale;
pub mod source;
pub mod stages;
pub mod style;
pub mod timestamps;
pub mod tuning;

pub use camera_fit::{CameraGiven, RingCamera};
pub use camera_motion::CameraMotionReport;
pub use frame::Frame;
pub use scale::RingScale;
pub use source::{FilmInfo, FilmSource, VIDEO_EXTENSIONS, is_film};
pub use stages::StageReport;
pub use tuning::TrackTuning;

use crate::recording::import::BodyMm;
use crate::recording::marks::{MarkGeometry, MarkOrder, mark_radius};
use crate::recording::{FrameMarks, Recording};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// What the marks look like.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum MarkStyle {
    /// Four distinct colours: each named by its hue.
    Colours,
    /// Four identical dots darker than the rim.
    Dark,
    /// Four identical dots brighter than the rim.
    Bright,
    /// Told from the first frames.
    Auto,
}

impl MarkStyle {
    pub const NAMES: &'static str = "colours, dark, bright, auto";
    pub fn parse(s: &str) -> Option<MarkStyle> {
        match s.trim().to_ascii_lowercase().as_str() {
            "colours" | "colors" => Some(MarkStyle::Colours),
            "dark" => Some(MarkStyle::Dark),
            "bright" => Some(MarkStyle::Bright),
            "auto" => Some(MarkStyle::Auto),
            _ => None,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            MarkStyle::Colours => "colours",
            MarkStyle::Dark => "dark",
            MarkStyle::Bright => "bright",
            MarkStyle::Auto => "auto",
        }
    }
}

/// A region of interest in pixels: the marks are looked for inside it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Roi {
    pub x: f64,
    pub y: f64,
    pub width: f64,
    pub height: f64,
}

impl Roi {
    pub fn whole(info: &FilmInfo) -> Roi {
        Roi { x: 0.0, y: 0.0, width: info.width as f64, height: info.height as f64 }
    }
    pub fn contains(&self, x: f64, y: f64) -> bool {
        x >= self.x && y >= self.y && x < self.x + self.width && y < self.y + self.height
    }
    /// The rectangle in a plane `scale` times coarser than the luma, clipped to it:
    /// `(x0, y0, w, h)` in that plane's samples, with `margin` samples more on each side.
    pub fn bounds(
        &self,
        scale: f64,
        w: usize,
        h: usize,
        margin: usize,
    ) -> (usize, usize, usize, usize) {
        let x0 = ((self.x / scale).floor() as usize).saturating_sub(margin).min(w);
        let y0 = ((self.y / scale).floor() as usize).saturating_sub(margin).min(h);
        let x1 = (((self.x + self.width) / scale).ceil() as usize + margin).min(w);
        let y1 = (((self.y + self.height) / scale).ceil() as usize + margin).min(h);
        (x0, y0, x1.saturating_sub(x0), y1.saturating_sub(y0))
    }

    /// `X,Y,W,H` in pixels.
    pub fn parse(s: &str) -> Option<Roi> {
        let v: Vec<f64> =
            s.split(',').map(|p| p.trim().parse::<f64>().ok()).collect::<Option<_>>()?;
        let [x, y, width, height] = v[..] else { return None };
        (v.iter().all(|v| v.is_finite()) && x >= 0.0 && y >= 0.0 && width > 0.0 && height > 0.0)
            .then_some(Roi { x, y, width, height })
    }
}

/// What the film does not say.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackOptions {
    pub style: MarkStyle,
    pub roi: Option<Roi>,
    /// First frame tracked (frames before it are passed over).
    pub from_frame: u64,
    /// Last frame tracked (inclusive); `None`: to the end.
    pub to_frame: Option<u64>,
    /// Frames per second where the film does not say (a folder of frames never does).
    pub fps: Option<f64>,
    /// The scale; `None`: measured from the ring.
    pub px_per_mm: Option<f64>,
    /// The camera's distance and tilt where known; what is not given is measured from the
    /// ring ([`camera_fit`]).
    pub camera: camera_fit::CameraGiven,
    pub body: BodyMm,
}

/// The header key of the tracker's own estimate of a centre's error (px per coordinate),
/// defined where the tracks' noise estimate reads it.
pub use crate::recording::tracks::TRACKER_SIGMA_KEY;

/// The start of the header's `px_per_mm_from` where the scale was fitted from the ring
/// through a near camera, defined where the camera reads it.
pub use crate::recording::camera::NEAR_RING_SCALE;

impl TrackOptions {
    /// The whole film of `body`, the marks' style told from it, the frame rate from the
    /// container, the scale from the ring.
    pub fn for_body(body: BodyMm) -> TrackOptions {
        TrackOptions {
            style: MarkStyle::Auto,
            roi: None,
            from_frame: 0,
            to_frame: None,
            fps: None,
            px_per_mm: None,
            camera: camera_fit::CameraGiven::default(),
            body,
        }
    }
}

/// Frames looked through for the four marks before giving up.
pub const ACQUIRE_FRAMES: u64 = 60;

#[derive(Debug, thiserror::Error)]
#[error("{}: {kind}", path.display())]
pub struct FilmError {
    pub path: PathBuf,
    pub kind: FilmErrorKind,
}

impl FilmError {
    pub fn new(path: &Path, kind: FilmErrorKind) -> FilmError {
        FilmError { path: path.to_path_buf(), kind }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum FilmErrorKind {
    #[error(
        "ffmpeg and ffprobe are needed to read a video and were not found on PATH (Debian: apt-get install ffmpeg)"
    )]
    NoFfmpeg,
    #[error("not a video ffmpeg can read: {0}")]
    NotAVideo(String),
    #[error("{0}")]
    Io(String),
    #[error("a folder without frames: no PNG, JPEG or TIFF files in it")]
    NoFrames,
    #[error("cannot read this frame: {0}")]
    BadFrame(String),
    #[error("the film is cut off: {decoded} frames decoded{}{}", expected.map(|n| format!(" of the {n} its header announces")).unwrap_or_default(), if said.is_empty() { String::new() } else { format!(" (ffmpeg: {said})") })]
    CutOff { decoded: u64, expected: Option<u64>, said: String },
    #[error("the frame rate is not known (a folder of frames does not say it): give --fps")]
    NeedsFps,
    #[error(
        "no four marks found in frames {first}..{last} (looked for {style} marks): check --marks, --roi and the body's size, or that the marks are in view"
    )]
    NoMarks { first: u64, last: u64, style: &'static str },
    #[error("fewer than two usable frames (both marks of an opposite pair found): {usable}")]
    TooFewUsable { usable: usize },
    #[error("--from-frame {from} is beyond the film's {frames} frames")]
    StartBeyondEnd { from: u64, frames: u64 },
    #[error(
        "the scale cannot be measured from the ring (fewer than 3 frames with all four marks): give --px-per-mm"
    )]
    NoScale,
    #[error("{0}")]
    Options(String),
    #[error(
        "the table's scale cannot be measured through the camera given (fewer than 20 frames with all four marks): give --px-per-mm too"
    )]
    NoCameraScale,
    #[error("cancelled")]
    Cancelled,
}

/// What the tracking did, for the terminal and the JSON.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TrackReport {
    pub style: MarkStyle,
    pub frames: usize,
    pub width_px: usize,
    pub height_px: usize,
    pub fps: f64,
    /// The first frame where the four marks were found.
    pub acquired_at: u64,
    pub marks_found: usize,
    /// Marks left out because their identity was ambiguous.
    pub left_out_ambiguous: usize,
    /// Times the ring was lost and found again.
    pub reacquired: usize,
    /// What each stage after the follower did, by name, in the order they ran
    /// ([`stages::STAGES`]): the marks it left out and, `join`, the stretches it numbered
    /// again across a loss.
    pub stages: Vec<StageReport>,
    /// Median standard error of the centres from the pixels' noise, per mark (px, per
    /// coordinate); `None` for a mark never found.
    pub centre_sigma_px: [Option<f64>; 4],
    /// The error of one centre per coordinate from the marks' parallelogram (`error`), noise
    /// and the error that turns with the ring together; `None` where a near camera breaks it.
    pub tracker_sigma_px: Option<f64>,
    /// The scale from the ring (also where `--px-per-mm` was given, as a check).
    pub ring_scale: Option<RingScale>,
    /// The camera fitted from the ring (distance, tilt, the table's scale), where it was
    /// fitted; written in the header where given or a tripod's ([`RingCamera::is_tripod`]).
    pub camera: Option<RingCamera>,
    /// The scale written: given, or from the ring.
    pub px_per_mm: f64,
    /// The camera's own motion measured from the table (always), and whether the marks were
    /// written in the first frame's camera for it (`camera_motion`).
    pub camera_motion: CameraMotionReport,
    pub notes: Vec<String>,
}

impl TrackReport {
    /// What the stage named `name` did; `None` where no stage has that name.
    pub fn stage(&self, name: &str) -> Option<&StageReport> {
        self.stages.iter().find(|s| s.name == name)
    }

    /// Marks the stage named `name` left out (0 where none has that name).
    pub fn left_out_by(&self, name: &str) -> usize {
        self.stage(name).map_or(0, |s| s.left_out)
    }
}

/// A film tracked: the recording, the centres' errors per frame and mark, the report.
#[derive(Clone, Debug)]
pub struct TrackedFilm {
    pub recording: Recording,
    pub sigma: Vec<[Option<f64>; 4]>,
    pub report: TrackReport,
    /// The marks where they were seen in each frame's image (the recording's, moved back by
    /// the camera's motion where the film was hand-held): what an overlay draws on the film.
    pub seen: Vec<FrameMarks>,
}

impl TrackedFilm {
    /// The recording with the marks where they were seen in the film as taken.
    pub fn as_seen(&self) -> Recording {
        Recording { frames: self.seen.clone(), ..self.recording.clone() }
    }
}

fn mark_radius_mm(body: &BodyMm) -> f64 {
    let w = body.thickness_mm.unwrap_or(body.outer_radius_mm);
    match crate::physics::Body::new(body.shape, body.outer_radius_mm, body.width_mm, w) {
        Ok(b) => mark_radius(&b),
        Err(_) => body.outer_radius_mm,
    }
}

/// The camera fitted from the ring with what the options give held (`camera_fit`); an error
/// where a camera given is impossible, or where it was given but neither it nor the scale can
/// be had from the ring.
fn ring_camera(
    opts: &TrackOptions,
    info: &FilmInfo,
    frames: &[FrameMarks],
    ring_scale: Option<&RingScale>,
) -> Result<Option<RingCamera>, FilmErrorKind> {
    let body = &opts.body;
    let geometry = MarkGeometry {
        radius: mark_radius_mm(body),
        r_outer: body.outer_radius_mm,
        h: body.width_mm,
        order: MarkOrder::Forward,
    };
    let start = ring_scale.map(|rs| rs.table.map_or(rs.px_per_mm, |t| t.px_per_mm));
    let Some(start) = opts.px_per_mm.or(start) else { return Ok(None) };
    let size = [info.width as f64, info.height as f64];
    let fitted = camera_fit::fit_camera(frames, geometry, size, start, opts.camera, opts.px_per_mm);
    if fitted.is_none() && opts.camera.any() && opts.px_per_mm.is_none() {
        return Err(FilmErrorKind::NoCameraScale);
    }
    Ok(fitted)
}

/// The note of a tripod's camera.
fn camera_note(c: &RingCamera) -> String {
    let distance = c.distance_mm.map_or("far".to_string(), |d| {
        format!("{d:.0} +- {:.0} mm from the table", c.distance_sigma_mm)
    });
    let how = if c.given.any() {
        "the camera given, what was not given fitted from the ring"
    } else {
        "a camera on a tripod, fitted from the ring over many frames"
    };
    format!(
        "{how}: {distance}, tilted {:.2} +- {:.2} degrees from the vertical; the table's scale under the image centre {:.4} +- {:.4} px/mm; the marks' figure through it {:.3} px (through a far camera looking straight down {:.3} px); written in the header",
        c.tilt_deg, c.tilt_sigma_deg, c.px_per_mm, c.px_per_mm_sigma, c.figure_px, c.far_figure_px
    )
}

/// Tracks a film (a video file or a folder of frames) with the tracker's own numbers
/// ([`TrackTuning::default`]): see [`track_tuned`].
pub fn track(
    path: &Path,
    opts: &TrackOptions,
    progress: &mut dyn FnMut(u64, Option<u64>),
    cancel: &AtomicBool,
) -> Result<TrackedFilm, FilmError> {
    track_tuned(path, opts, &TrackTuning::default(), progress, cancel)
}

/// Tracks a film (a video file or a folder of frames): see the module's stages.
/// `progress(done, total)` after each frame; `cancel` is looked at between frames.
pub fn track_tuned(
    path: &Path,
    opts: &TrackOptions,
    tuning: &TrackTuning,
    progress: &mut dyn FnMut(u64, Option<u64>),
    cancel: &AtomicBool,
) -> Result<TrackedFilm, FilmError> {
    let job = pass::Job { path, opts, tuning, cancel };
    let tallest = 2.0 * opts.body.outer_radius_mm + opts.body.width_mm;
    camera_fit::check_given(&opts.camera, tallest)
        .map_err(|m| job.err(FilmErrorKind::Options(m)))?;
    let mut film = pass::open(&job)?;
    let mut search = pass::search_for(&job, &film.info);
    if search.style == MarkStyle::Auto
        && let Some(told) = style::tell_style(path, opts, &search.roi, search.range, cancel)?
    {
        search.style = told;
    }
    let tracked = pass::pass(&job, &mut film, search, progress)?;
    let facts = assemble::FilmFacts { info: &film.info, fps: film.fps };
    assemble::assemble(&job, facts, tracked)
}
