//! Adaptive explicit Runge-Kutta integration with dense output and event location.
//!
//! Which and why: ringlab carries its own DOP853 (Dormand-Prince 8(5,3) with the 7th-order
//! continuous extension, Hairer, Norsett & Wanner, *Solving ODEs I*, II.10). The crates we
//! looked at did not give all three of error control, dense output and events that see every
//! step: `ode_solvers` 0.6 has a DOP853 whose dense output is wrong when the output spacing
//! spans several steps and whose stop hook only sees output points (`PHYSICS.md`). Owning the
//! stepper also lets the state be a fixed-size array (no allocation per step) and lets the
//! dense extension be computed lazily, only for steps that hold an output sample or an event.
//!
//! The stepper is generic over the state size so that models with extra state (e.g. a sliding
//! contact) reuse it. Beside it, a fixed-step fifth-order formula along the steps a DOP853 run
//! chose ([`dp5_along`]): the least squares' cheaper derivative columns.

mod along;
mod dop853;
mod roots;
#[allow(clippy::all)]
mod tableau;

pub use along::dp5_along;
pub use dop853::{Dop853, IntegratorError, Stats, Tolerances};
pub use roots::find_root;

/// A first-order system `y' = f(t, y)` with a state of `N` numbers.
pub trait System<const N: usize> {
    /// Writes `f(t, y)` into all of `dydt` (the stepper does not clear it first).
    fn rhs(&self, t: f64, y: &[f64; N], dydt: &mut [f64; N]);
}
