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
//! What the window does with a recording (read, fit, diagnose as jobs off the UI thread, the
//! file dialog) is [`crate::session`]'s.

pub mod event;
pub mod player;
pub mod track;
pub mod worker;

pub use player::{Player, SPEED_MAX, SPEED_MIN};
pub use track::{PathPoint, StateAt, Track};
pub use worker::{CHANNEL_CAPACITY, Event, RunEnd, SimHandle, Start};
