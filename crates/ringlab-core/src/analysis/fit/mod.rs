//! Fitting the model to a recording: the drag coefficients `C1..C3` (and, for the
//! diagnosis, an effect's strength) with the start state at the first inner turning point.
//!
//! **The misfit: multiple shooting on the marks' pixels.** From one start the model and a
//! ring part ways slowly and then for good: a slightly wrong start or drag shifts every
//! later cycloid, so a point-by-point RMS over the whole run from one state is ragged, full
//! of local minima and dominated by the phase error of the late path. Here the recording is
//! cut into segments of a few `theta` cycles (60 frames at first); each segment has its own
//! start state (8 numbers), the drag is shared, and the misfit is the RMS over every tracked
//! mark coordinate of model minus recording, in pixels. Within a segment the prediction stays
//! close, so the misfit is smooth in all parameters, and the drag is still told by how each
//! segment's spin, nutation and precession decay. The misfit is the same for any model (any
//! free parameters, any effect, the lens included): the marks are the data, nothing derived.
//! The states are not forced to join up between segments; the price is a little information
//! (about 8 numbers per segment), the gain a fit that does not depend on the whole run's phase.
//! The frames where the ring lies still at the end are left out: they show only the pose it
//! landed in, and the model lands when `theta` reaches its flat limit, an all-or-nothing event
//! at one of its maxima, known to a frame at best. When it stops is a feature of the coarse
//! stage instead.
//!
//! **The stages.**
//! 1. The motion is recovered (`recording::recover`); the start is the first inner turning
//!    point (`theta` minimum), as in the paper, or the first frame when it is one.
//! 2. The start state is reconstructed from the poses and their rates and refined on the
//!    first segment with the default drag.
//! 3. Coarse: a grid of drag coefficients (the sweep's machinery), each run once from the
//!    start and scored on phase-free features, the `theta` envelopes and the end time
//!    ([`coarse`]).
//! 4. Each segment's state in turn, from the previous segment's end (or the reconstruction,
//!    whichever fits better), with the coarse drag.
//! 5. Levenberg-Marquardt on everything ([`lm`]); `c_sigma` from its covariance with the
//!    residual variance. Its derivative columns are runs that follow the steps of the run at
//!    the point (`physics::run`'s `steps.rs`), by a cheaper formula for a rolling run
//!    (`physics::integrator::dp5_along`) and by DOP853 where the cheaper ones stall
//!    ([`lm::LmOptions::exact_finish`]); the run an evaluation made is kept for the Jacobian
//!    at that point ([`last_runs`]).
//! 6. Segments twice as long (pairs merged, the first state of each pair kept), fitted again,
//!    at most [`FitOptions::merges`] times and only while the misfit grows by no more than
//!    the freed parameters allow: longer segments carry more of the drag's effect (on the
//!    paper's ring `sigma(C1)` falls from about 6% with 60 frames to 0.6% with 240), but a
//!    model that is not quite the ring's follows the data over short segments only.
//!
//! The reported start state is the model's at the first inner turning point: the first
//! segment's start frame, or the turning point the model finds just after it.
//!
//! Runs off the UI thread: [`fit`] reports [`FitProgress`] through a callback and stops when
//! its cancel flag is set.

pub mod coarse;
pub mod last_runs;
pub mod lm;
pub mod params;
pub mod shooting;

mod driver;
mod options;
mod result;
mod start;

pub use driver::fit;
pub use options::{FIT_THETA_FLAT, FitError, FitOptions, FitProgress, FitStage};
pub use params::{Free, ModelSpec, StartReynolds};
pub use result::FitResult;
