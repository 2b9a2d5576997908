//! Recordings: video-tracked marks on a ring's top edge (`RECORDING_FORMAT.md`, format v1).
//!
//! - [`read`]: the reader, every problem the format names as a typed [`ReadError`] with file
//!   and line; [`mod@write`]: the writer.
//! - [`camera`]: table (mm) to pixels and back (orthographic or a pinhole, optionally tilted,
//!   optional radial lens distortion); [`marks`]: where the four marks sit for a given pose.
//! - [`pose`] and [`mod@recover`]: the ring's motion recovered from the marks, frame by frame,
//!   with uncertainties from the pixel noise ([`smooth`]: local fits and turning points);
//!   [`motion_table`] writes it as CSV.
//! - [`noise`], [`glitches`], [`tracks`]: what the tracks say alone, before any model: the
//!   pixel noise, a tracker's outliers and swapped labels, and the recording without them.
//! - [`synth`]: recordings made from the model (for tests, the fit's checks and the diagnosis),
//!   with its own seeded noise ([`rng`]).
//!
//! For a window: [`read_recording`] on the UI thread (errors are values to show), then
//! [`fn@recover`] for the path, pose and `v_p`, and `analysis::fit::fit` on a worker thread with
//! its progress callback and cancel flag.

pub mod camera;
pub mod glitches;
pub mod import;
pub mod marks;
pub mod motion_table;
pub mod noise;
pub mod pose;
pub mod pose_seen;
pub mod read;
pub mod recover;
pub mod rng;
pub mod smooth;
pub mod synth;
pub mod tracks;
pub mod write;

pub use camera::Camera;
pub use read::{ReadError, ReadErrorKind, parse_recording, read_recording};
pub use recover::{RecoveredMotion, recover};
pub use write::{write_recording, write_recording_exact};

use crate::physics::{Body, ParamError, Shape};

/// Number of marks on the top edge.
pub const MARKS: usize = 4;

/// The pixel positions of the four marks in one frame; `None` where a mark was not tracked.
pub type FrameMarks = [Option<[f64; 2]>; MARKS];

/// The `# key = value` lines of a recording.
#[derive(Clone, Debug, PartialEq)]
pub struct Header {
    pub fps: f64,
    pub px_per_mm: f64,
    pub shape: Shape,
    pub outer_radius_mm: f64,
    pub width_mm: f64,
    /// Ring wall; a disk may leave it out (it is then the outer radius).
    pub thickness_mm: Option<f64>,
    pub image_width_px: Option<f64>,
    pub image_height_px: Option<f64>,
    /// The camera's distance (mm) and tilt (degrees) where the lab measured them (see
    /// [`Camera`]); absent: unknown.
    pub camera_distance_mm: Option<f64>,
    pub camera_tilt_deg: Option<f64>,
    /// Keys this reader does not know, in file order (kept, not interpreted).
    pub extra: Vec<(String, String)>,
}

impl Header {
    /// The body in mm.
    pub fn body_mm(&self) -> Result<Body, ParamError> {
        let w = self.thickness_mm.unwrap_or(self.outer_radius_mm);
        Body::new(self.shape, self.outer_radius_mm, self.width_mm, w)
    }
}

/// A whole recording: header and frames `first_frame, first_frame + 1, ...`.
#[derive(Clone, Debug, PartialEq)]
pub struct Recording {
    pub header: Header,
    /// Number of the first frame (frame `n` is at time `n / fps`).
    pub first_frame: u64,
    pub frames: Vec<FrameMarks>,
}

impl Recording {
    /// Time of the `i`-th stored frame, in s.
    pub fn time_s(&self, i: usize) -> f64 {
        (self.first_frame + i as u64) as f64 / self.header.fps
    }

    /// Frame number of the `i`-th stored frame.
    pub fn frame_number(&self, i: usize) -> u64 {
        self.first_frame + i as u64
    }

    /// Number of marks tracked in all frames together.
    pub fn mark_count(&self) -> usize {
        self.frames.iter().map(|f| f.iter().flatten().count()).sum()
    }
}

/// Whether point A can be found from a frame: both marks of an opposite pair (1-3 or 2-4).
pub fn is_usable(marks: &FrameMarks) -> bool {
    (marks[0].is_some() && marks[2].is_some()) || (marks[1].is_some() && marks[3].is_some())
}
