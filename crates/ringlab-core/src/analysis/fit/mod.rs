//! Fitting the model to a recording: the drag coefficients `C1..C3` (and an effect's numbers
//! where asked) with the start state at the first inner turning point.
//!
//! The misfit is multiple shooting on the marks' pixels: the recording is cut into segments of
//! a few `theta` cycles, each with its own start state, the drag shared; within a segment the
//! prediction stays close, so the misfit is smooth in every parameter and independent of the
//! whole run's phase, and it is the same for any model (the marks are the data, nothing
//! derived). The frames where the ring lies still at the end are left out: the model lands in
//! an all-or-nothing event known to a frame at best.
//!
//! The stages ([`fit`], `driver.rs`): the motion recovered and the start reconstructed, a
//! coarse drag grid scored on phase-free features ([`coarse`]), each segment's state, then
//! Levenberg-Marquardt on everything ([`lm`]: derivative columns along the kept steps of the
//! run at the point, [`last_runs`]; a camera's numbers' columns without a run, `unrun.rs`), the segments merged pairwise while the misfit allows
//! ([`FitOptions::merges`]): longer segments carry more of the drag's effect, but a model that
//! is not quite the ring's follows the data over short segments only. Runs off the UI thread
//! with a progress callback and a cancel flag. Figures: `docs/recordings.md`.

pub mod coarse;
pub mod last_runs;
pub mod lm;
pub mod params;
pub mod shooting;

mod driver;
mod options;
mod result;
mod start;
mod unrun;

pub use driver::fit;
pub use options::{FIT_THETA_FLAT, FitError, FitOptions, FitProgress, FitStage};
pub use params::{Free, ModelSpec, StartReynolds};
pub use result::FitResult;
