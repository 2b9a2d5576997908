//! Films of a spinning ring: the four marks found in each frame and written as a recording.
//!
//! Stages of [`track`]: open the film ([`source`]: ffmpeg for video files, the `image` crate
//! for a folder of frames), find the four marks in the first frames ([`find`]; dots confirmed
//! by the next frame, [`acquire`]), follow them frame by frame ([`follow`], sub-pixel centres
//! by [`centre`]), measure the scale from the ring where none is given ([`scale`]), and
//! assemble the recording with a report of what was found, left out, and the centres' error.

pub mod acquire;
pub mod brief;
pub mod camera_fit;
pub mod camera_motion;
pub mod centre;
pub mod choice;
pub mod error;
pub mod few;
pub mod find;
pub mod follow;
pub mod frame;
pub mod join;
pub mod lost;
pub mod phase;
pub mod pose_error;
pub mod register;
pub mod rim;
pub mod scale;
pub mod source;
pub mod spread;
pub mod stray_hue;
pub mod style;
pub mod timestamps;

pub use camera_fit::{CameraGiven, RingCamera};
pub use camera_motion::CameraMotionReport;
pub use frame::Frame;
pub use scale::RingScale;
pub use source::{FilmInfo, FilmSource, VIDEO_EXTENSIONS, is_film};

use crate::physics::Shape;
use crate::recording::import::BodyMm;
use crate::recording::marks::{MarkGeometry, MarkOrder, mark_radius};
use crate::recording::{Camera, FrameMarks, Header, Recording, is_usable};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

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
    /// Dots found anew after a loss and numbered again from the ring's turning (`join`).
    pub renumbered_after_loss: usize,
    /// Marks left out because their numbering could not be carried across a loss.
    pub left_out_unnumbered: usize,
    /// Marks left out with a frame whose marks do not have the ring's size (`spread`).
    pub left_out_off_size: usize,
    /// Coloured marks left out for a hue astray from the mark's over the film (`stray_hue`).
    pub left_out_stray_hue: usize,
    /// Marks left out, seen in fewer than 3 frames in a row between frames without (`brief`).
    pub left_out_glimpses: usize,
    /// Marks left out with a frame of one or two where the ring is mostly lost (`few`).
    pub left_out_unchecked: usize,
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

fn semi_major_range(opts: &TrackOptions, info: &FilmInfo) -> (f64, f64) {
    let r = mark_radius_mm(&opts.body);
    match opts.px_per_mm {
        Some(s) => (0.6 * r * s, 1.6 * r * s),
        None => (3.0, info.width.min(info.height) as f64 / 2.0),
    }
}

/// The table scale's largest relative uncertainty at which a near camera's fitted pinhole
/// checks the centres' error (`pose_error`).
const MAX_POSE_SCALE_SIGMA: f64 = 0.02;

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

/// Tracks a film (a video file or a folder of frames): see the module's stages.
/// `progress(done, total)` after each frame; `cancel` is looked at between frames.
pub fn track(
    path: &Path,
    opts: &TrackOptions,
    progress: &mut dyn FnMut(u64, Option<u64>),
    cancel: &AtomicBool,
) -> Result<TrackedFilm, FilmError> {
    let err = |kind| FilmError::new(path, kind);
    let tallest = 2.0 * opts.body.outer_radius_mm + opts.body.width_mm;
    camera_fit::check_given(&opts.camera, tallest).map_err(|m| err(FilmErrorKind::Options(m)))?;
    let mut source = FilmSource::open(path)?;
    let info = source.info().clone();
    let fps = opts.fps.or(info.fps).ok_or(err(FilmErrorKind::NeedsFps))?;
    if let (Some(to), from) = (opts.to_frame, opts.from_frame)
        && to < from
    {
        return Err(err(FilmErrorKind::Options(format!(
            "--to-frame {to} comes before --from-frame {from}"
        ))));
    }
    let skipped = source.skip(opts.from_frame)?;
    if skipped < opts.from_frame {
        return Err(err(FilmErrorKind::StartBeyondEnd { from: opts.from_frame, frames: skipped }));
    }
    let total = match (info.frames, opts.to_frame) {
        (_, Some(to)) => Some(to + 1 - opts.from_frame),
        (Some(n), None) => Some(n.saturating_sub(opts.from_frame)),
        _ => None,
    };
    let roi = opts.roi.unwrap_or(Roi::whole(&info));
    let range = semi_major_range(opts, &info);
    let mut style = opts.style;
    if style == MarkStyle::Auto
        && let Some(told) = style::tell_style(path, opts, &roi, range, cancel)?
    {
        style = told;
    }

    let mut tracks = Tracks::default();
    let mut frame = Frame::default();
    let mut follower: Option<follow::Follower> = None;
    let mut acquirer = acquire::Acquirer::default();
    let mut acquired_at = None;
    let mut ambiguous = 0usize;
    // Slots where dots were found anew after a loss, numbered by a guess.
    let mut new_numbering = Vec::new();
    let mut camera = camera_motion::CameraMotion::default();
    // The last marks found: where the ring is near the next frame, for its registration.
    let mut ring_seen: FrameMarks = [None; 4];
    let mut index = opts.from_frame;
    loop {
        if opts.to_frame.is_some_and(|to| index > to) {
            break;
        }
        if cancel.load(Ordering::Relaxed) {
            return Err(err(FilmErrorKind::Cancelled));
        }
        if !source.next_frame(&mut frame)? {
            break;
        }
        let slot = (index - opts.from_frame) as usize;
        if slot == 0 {
            camera.first_frame(&frame);
        }
        let result = match follower.as_mut() {
            None => {
                if index - opts.from_frame >= ACQUIRE_FRAMES {
                    return Err(err(FilmErrorKind::NoMarks {
                        first: opts.from_frame,
                        last: index - 1,
                        style: opts.style.name(),
                    }));
                }
                let found = find::find_marks(&frame, &roi, style, range);
                if let Some((s, _)) = &found {
                    style = *s;
                }
                match acquirer.offer(index, &frame, found) {
                    Some(run) => {
                        acquired_at = Some(run.first.0);
                        let at = opts.from_frame;
                        let mut run_tracks =
                            RunTracks { first: at, tracks: &mut tracks, camera: &mut camera };
                        let (f, last) = follow_run(run, style, roi, range, &mut run_tracks);
                        follower = Some(f);
                        last
                    }
                    None => follow::FrameResult::default(),
                }
            }
            Some(f) => {
                camera.register(slot, &frame, &ring_seen, false, Some(&mut *f));
                f.step(&frame, index)
            }
        };
        if result.marks.iter().any(Option::is_some) {
            ring_seen = result.marks;
        }
        ambiguous += result.ambiguous;
        if result.new_numbering {
            new_numbering.push(tracks.frames.len());
        }
        tracks.push(&result);
        index += 1;
        progress(index - opts.from_frame, total);
    }
    let reacquired = follower.as_ref().map_or(0, |f| f.refound);
    let Tracks { mut frames, mut sigma, hues } = tracks;
    let camera = camera.finish(frames.len());
    let mut motion = camera.report(&frames);
    if motion.hand_held {
        camera.to_table(&mut frames, &mut sigma, &mut motion);
    }
    let joined = join::number_across_losses(&mut frames, &mut sigma, &new_numbering);
    let off_size = spread::leave_out_off_size(&mut frames, &mut sigma);
    let stray_hue = stray_hue::leave_out_stray_hues(&mut frames, &mut sigma, &hues);
    let unchecked = few::leave_out_unchecked(&mut frames, &mut sigma);
    let glimpses = brief::leave_out_glimpses(&mut frames, &mut sigma);
    let counts = Counts {
        ambiguous,
        reacquired,
        joined,
        off_size,
        stray_hue,
        unchecked,
        glimpses,
        camera: motion,
    };
    let seen = if counts.camera.hand_held { camera.to_image(&frames) } else { frames.clone() };
    let mut tracked = assemble(path, opts, &info, fps, style, acquired_at, frames, sigma, counts)?;
    tracked.seen = seen;
    Ok(tracked)
}

/// Where an acquisition's run is followed: the film's first frame tracked, the tracks so
/// far, the camera's registration.
struct RunTracks<'a> {
    first: u64,
    tracks: &'a mut Tracks,
    camera: &'a mut camera_motion::CameraMotion,
}

/// Follows the ring from the first frame of the run that acquired it (`acquire`) through the
/// others, whose results replace those already pushed (`first`: the film's first frame
/// tracked); the last of the run is the frame in hand, whose result is returned with the
/// ambiguous marks of the whole run.
fn follow_run(
    run: acquire::Run,
    style: MarkStyle,
    roi: Roi,
    range: (f64, f64),
    to: &mut RunTracks,
) -> (follow::Follower, follow::FrameResult) {
    let (index, frame, found) = run.first;
    let mut f = follow::Follower::new(style, &found, &frame, index, roi, range);
    let mut result = f.acquired();
    to.camera.register((index - to.first) as usize, &frame, &result.marks, true, None);
    let mut ambiguous = 0;
    let mut at = index;
    for (index, frame) in run.rest {
        to.tracks.set((at - to.first) as usize, &result);
        let slot = (index - to.first) as usize;
        to.camera.register(slot, &frame, &result.marks, false, Some(&mut f));
        result = f.step(&frame, index);
        ambiguous += result.ambiguous;
        at = index;
    }
    result.ambiguous = ambiguous;
    (f, result)
}

/// What each frame gave, by frame: the marks, their centres' errors and, for colours, hues.
#[derive(Default)]
struct Tracks {
    frames: Vec<FrameMarks>,
    sigma: Vec<[Option<f64>; 4]>,
    hues: Vec<[Option<f64>; 4]>,
}

impl Tracks {
    fn push(&mut self, r: &follow::FrameResult) {
        self.frames.push(r.marks);
        self.sigma.push(r.sigma);
        self.hues.push(r.hues);
    }

    /// A frame already pushed given again (an acquisition's run followed).
    fn set(&mut self, slot: usize, r: &follow::FrameResult) {
        if slot < self.frames.len() {
            (self.frames[slot], self.sigma[slot], self.hues[slot]) = (r.marks, r.sigma, r.hues);
        }
    }
}

/// What the tracking counted on the way.
struct Counts {
    ambiguous: usize,
    reacquired: usize,
    joined: join::Joined,
    /// Marks left out with a frame not of the ring's size (`spread`).
    off_size: usize,
    /// Marks left out for a hue astray from the mark's (`stray_hue`).
    stray_hue: usize,
    /// Marks left out with a frame of one or two (`few`).
    unchecked: usize,
    /// Marks left out, seen in too few frames in a row (`brief`).
    glimpses: usize,
    /// The camera's own motion (`camera_motion`).
    camera: CameraMotionReport,
}

#[allow(clippy::too_many_arguments)]
fn assemble(
    path: &Path,
    opts: &TrackOptions,
    info: &FilmInfo,
    fps: f64,
    style: MarkStyle,
    acquired_at: Option<u64>,
    frames: Vec<FrameMarks>,
    sigma: Vec<[Option<f64>; 4]>,
    counts: Counts,
) -> Result<TrackedFilm, FilmError> {
    let Counts {
        ambiguous,
        reacquired,
        joined,
        off_size,
        stray_hue,
        unchecked,
        glimpses,
        camera: motion,
    } = counts;
    let err = |kind| FilmError::new(path, kind);
    let Some(acquired_at) = acquired_at else {
        return Err(err(FilmErrorKind::NoMarks {
            first: opts.from_frame,
            last: opts.from_frame + frames.len().saturating_sub(1) as u64,
            style: opts.style.name(),
        }));
    };
    let usable = frames.iter().filter(|f| is_usable(f)).count();
    if usable < 2 {
        return Err(err(FilmErrorKind::TooFewUsable { usable }));
    }
    let body = &opts.body;
    let centre = [info.width as f64 / 2.0, info.height as f64 / 2.0];
    let ring_scale = scale::ring_scale(
        &frames,
        mark_radius_mm(body),
        body.outer_radius_mm,
        body.width_mm,
        centre,
    );
    let mut notes = Vec::new();
    let mut ring_scale = ring_scale;
    if let Some(rs) = ring_scale.as_mut() {
        let size = [info.width as f64, info.height as f64];
        notes.extend(pose_error::check_near_camera(rs, &frames, size, mark_radius_mm(body)));
    }
    let camera = ring_camera(opts, info, &frames, ring_scale.as_ref()).map_err(err)?;
    let tripod = camera.filter(RingCamera::is_tripod);
    if let Some(c) = &tripod {
        // The tripod's camera answers what the straight-down view's scale could not.
        notes.clear();
        notes.push(camera_note(c));
    }
    let from_tripod = tripod.filter(|_| opts.px_per_mm.is_none()).map(|c| c.px_per_mm);
    let px_per_mm = match (opts.px_per_mm.or(from_tripod), &ring_scale) {
        (Some(s), Some(rs)) => {
            let off = rs.px_per_mm / s - 1.0;
            if off.abs() > 0.03 && tripod.is_none() {
                notes.push(format!(
                    "the ring measures {:.4} px/mm, {:+.1}% from the --px-per-mm given: check the body's size",
                    rs.px_per_mm,
                    100.0 * off
                ));
            }
            s
        }
        (Some(s), None) => s,
        (None, Some(rs)) => rs.table.map_or(rs.px_per_mm, |t| t.px_per_mm),
        (None, None) => return Err(err(FilmErrorKind::NoScale)),
    };
    if let Some(rs) = &ring_scale
        && rs.camera_is_near()
        && tripod.is_none()
    {
        notes.push(match rs.table {
            Some(t) => format!(
                "a near camera (the marks' scale grows with their height): about {:.0} mm away; the table's scale under the image centre, {:.4} +- {:.4} px/mm, fitted with it (the marks' own, {:.4} px/mm, holds {:.1} mm above the table)",
                t.camera_distance_mm, t.px_per_mm, t.sigma, rs.px_per_mm, rs.height_mm
            ),
            None => format!(
                "a near camera (the scale grows {:.2}% per mm of the marks' height) whose distance could not be fitted: {:.4} px/mm holds {:.1} mm above the table, not at it (give --px-per-mm for the table's)",
                100.0 * rs.growth_per_mm,
                rs.px_per_mm,
                rs.height_mm
            ),
        });
    }
    let mut per_mark: [Vec<f64>; 4] = Default::default();
    for s in &sigma {
        for k in 0..4 {
            if let Some(v) = s[k] {
                per_mark[k].push(v);
            }
        }
    }
    let centre_sigma_px = per_mark.map(|mut v| {
        (!v.is_empty()).then(|| {
            v.sort_by(|a, b| a.total_cmp(b));
            v[v.len() / 2]
        })
    });
    let near = tripod.is_none() && ring_scale.as_ref().is_some_and(RingScale::camera_is_near);
    // Through a near camera, the marks' circle posed in each frame through the pinhole fitted
    // with the scale checks the centres instead of the parallelogram, where that pinhole is
    // known well enough: a wrong distance leaves a residual of its own in every pose.
    let near_camera = ring_scale
        .as_ref()
        .and_then(|rs| rs.table)
        .filter(|t| t.sigma < MAX_POSE_SCALE_SIGMA * t.px_per_mm)
        .map(|t| Camera {
            distance_mm: Some(t.camera_distance_mm),
            ..Camera::centred(px_per_mm, info.width as f64, info.height as f64)
        });
    let tracker_sigma_px = match (near, near_camera) {
        _ if tripod.is_some() => tripod.map(|c| c.figure_px),
        (false, _) => error::closure_sigma(&frames),
        (true, Some(cam)) => pose_error::pinhole_closure_sigma(&frames, &cam, mark_radius_mm(body)),
        (true, None) => None,
    };
    // The scale's own spread over the frames misses a bias the four centres share (each
    // pulled out or in from A by its neighbourhood alike): one centre's error over the
    // marks' radius bounds it.
    if let (Some(rs), Some(e)) = (ring_scale.as_mut(), tracker_sigma_px) {
        rs.sigma = rs.sigma.hypot(e / mark_radius_mm(body));
    }
    // Each centre's error: its own noise and the share of the closure beyond the noise.
    let mut sigma = sigma;
    if let Some(total) = tracker_sigma_px {
        let noise: Vec<f64> = sigma.iter().flatten().flatten().copied().collect();
        let mean_var = noise.iter().map(|s| s * s).sum::<f64>() / noise.len().max(1) as f64;
        let beyond = (total * total - mean_var).max(0.0);
        for s in sigma.iter_mut().flatten().flatten() {
            *s = (*s * *s + beyond).sqrt();
        }
    } else if near {
        notes.push(
            "a near camera whose distance is not known well enough (the table's scale within 2%) for the marks' figure to check the centres' error: the error said is the pixels' noise alone".into(),
        );
    }
    if info.missing > 0 {
        notes.push(format!(
            "the film's frame rate varies: its timestamps leave {} of its frames at {} frames/s untaken; they are empty rows at their times",
            info.missing, fps
        ));
    }
    notes.extend(lost::lost_note(&frames, opts.from_frame));
    notes.extend(camera_motion::camera_note(&motion));
    if joined.unsettled > 0 {
        notes.push(format!(
            "{} marks left out in {} stretches after a loss: dots found anew there that the ring's turning across the loss could not number as the rest",
            joined.marks_left_out, joined.unsettled
        ));
    }
    if off_size > 0 {
        notes.push(format!(
            "{off_size} marks left out in frames whose marks spread wider or narrower than the ring (a look-alike among them)"
        ));
    }
    if unchecked > 0 {
        notes.push(format!(
            "{unchecked} marks left out in frames of fewer than {} marks where the ring was mostly lost: nothing checks them against the ring's figure",
            few::LEAST_MARKS
        ));
    }
    if glimpses > 0 {
        notes.push(format!(
            "{glimpses} marks left out, seen in fewer than {} frames in a row between frames where the ring was lost: nothing confirms them",
            brief::LEAST_RUN
        ));
    }
    if stray_hue > 0 {
        notes.push(format!(
            "{stray_hue} marks left out whose hue strayed more than {} rad from the mark's over the frames near (a look-alike, or the blur of a ring on edge)",
            stray_hue::STRAY
        ));
    }
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let mut extra = vec![
        ("tracked_from".to_string(), name),
        ("tracked_marks".to_string(), style.name().to_string()),
    ];
    if let Some(s) = tracker_sigma_px {
        extra.push((TRACKER_SIGMA_KEY.to_string(), format!("{s:.3}")));
    }
    if opts.px_per_mm.is_none()
        && let Some(c) = &tripod
    {
        extra.push(("px_per_mm_from".to_string(), camera_fit::scale_from(c)));
    } else if opts.px_per_mm.is_none()
        && let Some(rs) = &ring_scale
    {
        let from = match rs.table {
            Some(t) => format!(
                "{NEAR_RING_SCALE}, +-{:.4}, about {:.0} mm away",
                t.sigma, t.camera_distance_mm
            ),
            None => format!("ring, +-{:.4}, at {:.1} mm", rs.sigma, rs.height_mm),
        };
        extra.push(("px_per_mm_from".to_string(), from));
    }
    let header = Header {
        fps,
        px_per_mm,
        shape: body.shape,
        outer_radius_mm: body.outer_radius_mm,
        width_mm: body.width_mm,
        thickness_mm: if body.shape == Shape::Ring {
            body.thickness_mm
        } else {
            body.thickness_mm.or(Some(body.outer_radius_mm))
        },
        image_width_px: Some(info.width as f64),
        image_height_px: Some(info.height as f64),
        camera_distance_mm: tripod.and_then(|c| c.distance_mm).or(opts.camera.distance_mm),
        camera_tilt_deg: tripod.map(|c| c.tilt_deg).or(opts.camera.tilt_deg),
        extra,
    };
    let marks_found = frames.iter().map(|f| f.iter().flatten().count()).sum();
    let report = TrackReport {
        style,
        frames: frames.len(),
        width_px: info.width,
        height_px: info.height,
        fps,
        acquired_at,
        marks_found,
        left_out_ambiguous: ambiguous,
        reacquired,
        renumbered_after_loss: joined.settled,
        left_out_unnumbered: joined.marks_left_out,
        left_out_off_size: off_size,
        left_out_stray_hue: stray_hue,
        left_out_glimpses: glimpses,
        left_out_unchecked: unchecked,
        centre_sigma_px,
        tracker_sigma_px,
        ring_scale,
        camera,
        px_per_mm,
        camera_motion: motion,
        notes,
    };
    let recording = Recording { header, first_frame: opts.from_frame, frames };
    Ok(TrackedFilm { recording, sigma, report, seen: Vec::new() })
}
