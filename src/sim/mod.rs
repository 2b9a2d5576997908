//! The live side of a run: an integrator thread that runs the model ahead of the display and
//! streams time-stamped states over a bounded channel ([`worker`]), what the UI keeps of them
//! ([`track`]), and the playback clock the UI advances each frame ([`player`]).
//!
//! The UI owns the clock: play, pause, step, speed and seek move [`Player`]; the worker is
//! paced by the channel alone (when the display stops pulling states, the channel fills and the
//! worker waits), so it never needs to know the speed. Runs are numbered; every event carries
//! its run's number, so states of a superseded run still in the channel are recognised and
//! dropped.
//!
//! Other work off the UI thread is a [`Job`]: a recording read and its motion recovered, a fit,
//! the file dialog ([`recorded`] holds a recording's state in the window, without egui).

pub mod file_dialog;
pub mod job;
pub mod player;
pub mod recorded;
pub mod track;
pub mod worker;

pub use job::{Job, JobContext, JobLost, Progress};
pub use player::{Player, SPEED_MAX, SPEED_MIN};
pub use recorded::{Diagnosed, DiagnosedModel, LoadError, LoadedRecording, PendingImport, RecordingSession, SessionEvent};
pub use track::{PathPoint, StateAt, Track};
pub use worker::{CHANNEL_CAPACITY, Event, RunEnd, SimHandle, Start};
