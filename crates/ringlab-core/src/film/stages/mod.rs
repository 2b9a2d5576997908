//! The stages after the follower: passes over the whole track, each a rule that many frames
//! together show and one frame cannot, that leaves out the marks breaking it (or, `join`,
//! numbers them again), and says how many. They run in the order of [`STAGES`], each on what
//! the one before left; the report lists each by its name with what it left out. A new
//! stage: a file here with a type that is a [`Stage`], and a line in [`STAGES`] (its numbers,
//! where it has any, a field of [`TrackTuning`]).

pub mod brief;
pub mod few;
pub mod join;
pub mod spread;
pub mod stray_hue;

use super::tuning::TrackTuning;
use crate::recording::FrameMarks;

/// The marks tracked by frame, with their centres' errors (px, per coordinate): what the
/// stages work on. A mark left out is `None` in both.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Track {
    pub frames: Vec<FrameMarks>,
    pub sigma: Vec<[Option<f64>; 4]>,
}

impl Track {
    /// Frame `i`'s marks all left out; returns how many there were.
    pub fn leave_out_frame(&mut self, i: usize) -> usize {
        let n = self.frames[i].iter().flatten().count();
        self.frames[i] = [None; 4];
        self.sigma[i] = [None; 4];
        n
    }
}

/// What the follower said beside the marks, that stages read.
pub struct StageContext<'a> {
    /// Colours: the hue each mark found showed, by frame (radians; `None` for dots).
    pub hues: &'a [[Option<f64>; 4]],
    /// The frames' slots (ascending) where dots were found anew and numbered by a guess.
    pub new_numbering: &'a [usize],
    pub tuning: &'a TrackTuning,
}

/// What one stage did.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct StageReport {
    /// The stage's name ([`Stage::name`]).
    pub name: &'static str,
    /// Marks it left out.
    pub left_out: usize,
    /// Stretches of frames it numbered again (`join`; 0 for the others).
    pub renumbered: usize,
    /// What it left out in words, for the report's notes; `None` where it left nothing out.
    #[serde(skip)]
    pub note: Option<String>,
}

impl StageReport {
    /// A stage that left out `left_out` marks, said by `note` where it left out any.
    pub fn left_out(name: &'static str, left_out: usize, note: impl FnOnce() -> String) -> Self {
        StageReport { name, left_out, renumbered: 0, note: (left_out > 0).then(note) }
    }
}

/// A pass over the whole track.
pub trait Stage {
    /// The stage's name in the report: its module's.
    fn name(&self) -> &'static str;
    /// Leaves out (or numbers again) what its rule finds in `track`.
    fn run(&self, track: &mut Track, ctx: &StageContext) -> StageReport;
}

/// The stages, in the order they run.
pub const STAGES: &[&dyn Stage] =
    &[&join::Join, &spread::Spread, &stray_hue::StrayHue, &few::Few, &brief::Brief];

/// Runs every stage of [`STAGES`] on `track` in turn; their reports in that order.
pub fn run_all(track: &mut Track, ctx: &StageContext) -> Vec<StageReport> {
    STAGES.iter().map(|s| s.run(track, ctx)).collect()
}
