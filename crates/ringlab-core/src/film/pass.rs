//! The pass through a film's frames: opened at the first frame tracked, the ring looked for
//! until four marks are acquired (`acquire`), then followed frame by frame (`follow`) with the
//! camera's motion registered (`camera_motion`); after the last frame the marks are moved into
//! the first frame's camera where it was held in the hand, and the stages run (`stages`).

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use super::camera_motion::{CameraMotion, CameraMotionReport};
use super::follow::{Follower, FrameResult, Search};
use super::stages::{StageContext, StageReport, Track};
use super::tuning::TrackTuning;
use super::{
    FilmError, FilmErrorKind, FilmInfo, FilmSource, Frame, MarkStyle, Roi, TrackOptions, acquire,
    find, stages,
};
use crate::recording::FrameMarks;

/// What was asked: the film, what it does not say, the tracker's numbers, and the flag that
/// cancels the tracking between frames.
pub struct Job<'a> {
    pub path: &'a Path,
    pub opts: &'a TrackOptions,
    pub tuning: &'a TrackTuning,
    pub cancel: &'a AtomicBool,
}

impl Job<'_> {
    pub fn err(&self, kind: FilmErrorKind) -> FilmError {
        FilmError::new(self.path, kind)
    }

    fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
}

/// A film opened at its first frame tracked: what it is, its frame rate, and how many frames
/// are to be tracked where that is known.
pub struct OpenedFilm {
    pub source: FilmSource,
    pub info: FilmInfo,
    pub fps: f64,
    pub total: Option<u64>,
}

/// Opens the film and passes over the frames before the first tracked; an error where the
/// options contradict each other or the film.
pub fn open(job: &Job) -> Result<OpenedFilm, FilmError> {
    let opts = job.opts;
    let mut source = FilmSource::open(job.path)?;
    let info = source.info().clone();
    let fps = opts.fps.or(info.fps).ok_or(job.err(FilmErrorKind::NeedsFps))?;
    if let (Some(to), from) = (opts.to_frame, opts.from_frame)
        && to < from
    {
        return Err(job.err(FilmErrorKind::Options(format!(
            "--to-frame {to} comes before --from-frame {from}"
        ))));
    }
    let skipped = source.skip(opts.from_frame)?;
    if skipped < opts.from_frame {
        return Err(
            job.err(FilmErrorKind::StartBeyondEnd { from: opts.from_frame, frames: skipped })
        );
    }
    let total = match (info.frames, opts.to_frame) {
        (_, Some(to)) => Some(to + 1 - opts.from_frame),
        (Some(n), None) => Some(n.saturating_sub(opts.from_frame)),
        _ => None,
    };
    Ok(OpenedFilm { source, info, fps, total })
}

/// What the pass made of the film, before its recording is assembled.
pub struct Tracked {
    /// The style the marks were found in.
    pub style: MarkStyle,
    /// The first frame where the four marks were found; `None`: never.
    pub acquired_at: Option<u64>,
    /// The marks in the table's frame, after the stages.
    pub track: Track,
    /// The marks where they were seen in each frame's image.
    pub seen: Vec<FrameMarks>,
    /// Marks the follower left out as ambiguous.
    pub ambiguous: usize,
    /// Times the ring was lost and found again.
    pub reacquired: usize,
    /// The camera's own motion.
    pub motion: CameraMotionReport,
    /// What each stage did, in the order they ran.
    pub stages: Vec<StageReport>,
}

/// Tracks every frame of `film` for `search` (its style told where it was auto), then moves
/// the marks into the table's frame and runs the stages.
pub fn pass(
    job: &Job,
    film: &mut OpenedFilm,
    search: Search,
    progress: &mut dyn FnMut(u64, Option<u64>),
) -> Result<Tracked, FilmError> {
    let opts = job.opts;
    let mut frames = Frames::new(search);
    let mut frame = Frame::default();
    let mut index = opts.from_frame;
    loop {
        if opts.to_frame.is_some_and(|to| index > to) {
            break;
        }
        if job.cancelled() {
            return Err(job.err(FilmErrorKind::Cancelled));
        }
        if !film.source.next_frame(&mut frame)? {
            break;
        }
        frames.take(job, &frame, index).map_err(|k| job.err(k))?;
        index += 1;
        progress(index - opts.from_frame, film.total);
    }
    Ok(frames.finish(job))
}

/// The frames so far: what each gave, the follower once the ring was acquired, the camera's
/// registration.
struct Frames {
    search: Search,
    tracks: Tracks,
    follower: Option<Follower>,
    acquirer: acquire::Acquirer,
    acquired_at: Option<u64>,
    ambiguous: usize,
    /// Slots where dots were found anew after a loss, numbered by a guess.
    new_numbering: Vec<usize>,
    camera: CameraMotion,
    /// The last marks found: where the ring is near the next frame, for its registration.
    ring_seen: FrameMarks,
}

impl Frames {
    fn new(search: Search) -> Frames {
        Frames {
            search,
            tracks: Tracks::default(),
            follower: None,
            acquirer: acquire::Acquirer::default(),
            acquired_at: None,
            ambiguous: 0,
            new_numbering: Vec::new(),
            camera: CameraMotion::default(),
            ring_seen: [None; 4],
        }
    }

    /// Frame `index`: the ring looked for or followed in it, its result pushed.
    fn take(&mut self, job: &Job, frame: &Frame, index: u64) -> Result<(), FilmErrorKind> {
        let slot = (index - job.opts.from_frame) as usize;
        if slot == 0 {
            self.camera.first_frame(frame);
        }
        let result = match self.follower.as_mut() {
            None => self.acquire(job, frame, index)?,
            Some(f) => {
                self.camera.register(slot, frame, &self.ring_seen, false, Some(&mut *f));
                f.step(frame, index)
            }
        };
        if result.marks.iter().any(Option::is_some) {
            self.ring_seen = result.marks;
        }
        self.ambiguous += result.ambiguous;
        if result.new_numbering {
            self.new_numbering.push(self.tracks.frames.len());
        }
        self.tracks.push(&result);
        Ok(())
    }

    /// The ring looked for in frame `index` before it was acquired; once a run of frames
    /// agrees, followed through them from the run's first. An error where none was acquired
    /// in the first frames.
    fn acquire(
        &mut self,
        job: &Job,
        frame: &Frame,
        index: u64,
    ) -> Result<FrameResult, FilmErrorKind> {
        let from = job.opts.from_frame;
        if index - from >= job.tuning.acquire_frames {
            return Err(FilmErrorKind::NoMarks {
                first: from,
                last: index - 1,
                style: job.opts.style.name(),
            });
        }
        let found = find::find_marks(frame, &self.search.roi, self.search.style, self.search.range);
        if let Some((s, _)) = &found {
            self.search.style = *s;
        }
        let Some(run) = self.acquirer.offer(index, frame, found) else {
            return Ok(FrameResult::default());
        };
        self.acquired_at = Some(run.first.0);
        let mut to = RunTracks { first: from, tracks: &mut self.tracks, camera: &mut self.camera };
        let (f, last) = follow_run(run, self.search, job.tuning, &mut to);
        self.follower = Some(f);
        Ok(last)
    }

    /// After the last frame: the marks moved into the first frame's camera where it was held
    /// in the hand, then the stages run on them.
    fn finish(self, job: &Job) -> Tracked {
        let reacquired = self.follower.as_ref().map_or(0, |f| f.refound);
        let Tracks { frames, sigma, hues } = self.tracks;
        let mut track = Track { frames, sigma };
        let camera = self.camera.finish(track.frames.len());
        let mut motion = camera.report(&track.frames);
        if motion.hand_held {
            camera.to_table(&mut track.frames, &mut track.sigma, &mut motion);
        }
        let ctx =
            StageContext { hues: &hues, new_numbering: &self.new_numbering, tuning: job.tuning };
        let stages = stages::run_all(&mut track, &ctx);
        let seen =
            if motion.hand_held { camera.to_image(&track.frames) } else { track.frames.clone() };
        Tracked {
            style: self.search.style,
            acquired_at: self.acquired_at,
            track,
            seen,
            ambiguous: self.ambiguous,
            reacquired,
            motion,
            stages,
        }
    }
}

/// Where an acquisition's run is followed: the film's first frame tracked, the tracks so
/// far, the camera's registration.
struct RunTracks<'a> {
    first: u64,
    tracks: &'a mut Tracks,
    camera: &'a mut CameraMotion,
}

/// Follows the ring from the first frame of the run that acquired it (`acquire`) through the
/// others, whose results replace those already pushed (`first`: the film's first frame
/// tracked); the last of the run is the frame in hand, whose result is returned with the
/// ambiguous marks of the whole run.
fn follow_run(
    run: acquire::Run,
    search: Search,
    tuning: &TrackTuning,
    to: &mut RunTracks,
) -> (Follower, FrameResult) {
    let (index, frame, found) = run.first;
    let mut f = Follower::new(search, &found, &frame, index, &tuning.follow);
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
    fn push(&mut self, r: &FrameResult) {
        self.frames.push(r.marks);
        self.sigma.push(r.sigma);
        self.hues.push(r.hues);
    }

    /// A frame already pushed given again (an acquisition's run followed).
    fn set(&mut self, slot: usize, r: &FrameResult) {
        if slot < self.frames.len() {
            (self.frames[slot], self.sigma[slot], self.hues[slot]) = (r.marks, r.sigma, r.hues);
        }
    }
}

/// The roi and size range searched, for a film of `info` (`Roi` given or the whole frame).
pub fn search_for(job: &Job, info: &FilmInfo) -> Search {
    let opts = job.opts;
    let roi = opts.roi.unwrap_or(Roi::whole(info));
    let r = super::mark_radius_mm(&opts.body);
    let range = match opts.px_per_mm {
        Some(s) => {
            let (lo, hi) = job.tuning.semi_major_given;
            (lo * r * s, hi * r * s)
        }
        None => (job.tuning.least_semi_major_px, info.width.min(info.height) as f64 / 2.0),
    };
    Search { style: opts.style, roi, range }
}
