//! How a run is set up and how it can end.

use super::super::body::{ParamError, check_finite, check_positive};
use super::super::integrator::{IntegratorError, Tolerances};
use std::f64::consts::FRAC_PI_2;
use std::fmt;

/// Default end tilt: the run stops when `theta` reaches `pi/2 - 0.02`. The frame is singular
/// at `pi/2` (`phi' = w3 / cos(theta)` diverges); by `0.02` rad the ring is flat for any camera
/// and the step size has begun to collapse. The reference solution uses the same limit.
pub const DEFAULT_THETA_FLAT: f64 = FRAC_PI_2 - 0.02;
/// Default static friction coefficient (the paper's table, `mu ~ 0.4`).
pub const DEFAULT_MU: f64 = 0.4;
/// The ring rests when its kinetic energy falls below this fraction of `g R` (speeds of about
/// 1e-6 `sqrt(g R)`).
pub const REST_KINETIC_FRACTION: f64 = 1e-12;

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunOptions {
    pub t_end: f64,
    pub tol: Tolerances,
    pub theta_flat: f64,
    /// Static friction coefficient of the would-slip check of pure rolling. With the slip
    /// effect the contact's own coefficient (`Effects::slip_mu`) decides the switches instead.
    pub mu: f64,
    /// Emit samples every `sample_dt` (none: no samples).
    pub sample_dt: Option<f64>,
    /// Largest step the integrator may take.
    pub h_max: f64,
    /// Locate lift-off and slip intervals (costs one force evaluation per step).
    pub track_validity: bool,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            t_end: 1000.0,
            tol: Tolerances::default(),
            theta_flat: DEFAULT_THETA_FLAT,
            mu: DEFAULT_MU,
            sample_dt: None,
            h_max: f64::INFINITY,
            track_validity: true,
        }
    }
}

impl RunOptions {
    pub fn validate(&self) -> Result<(), ParamError> {
        check_positive("t_end", self.t_end)?;
        check_positive("rtol", self.tol.rtol)?;
        check_positive("atol", self.tol.atol)?;
        if self.tol.rtol >= 1.0 {
            return Err(ParamError {
                name: "rtol",
                value: self.tol.rtol,
                reason: "must be below 1",
            });
        }
        check_finite("theta_flat", self.theta_flat)?;
        if !(self.theta_flat > 0.0 && self.theta_flat < FRAC_PI_2) {
            return Err(ParamError {
                name: "theta_flat",
                value: self.theta_flat,
                reason: "must lie in (0, pi/2)",
            });
        }
        check_finite("mu", self.mu)?;
        if self.mu < 0.0 {
            return Err(ParamError { name: "mu", value: self.mu, reason: "must not be negative" });
        }
        if let Some(dt) = self.sample_dt {
            check_positive("dt", dt)?;
        }
        if !(self.h_max > 0.0) {
            return Err(ParamError {
                name: "h_max",
                value: self.h_max,
                reason: "must be greater than zero",
            });
        }
        Ok(())
    }
}

/// Why a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EndReason {
    /// `theta` reached the flat limit ([`RunOptions::theta_flat`]).
    Flat,
    /// The kinetic energy fell to nothing.
    Rest,
    /// `t_end` was reached first.
    TEnd,
    /// `theta` fell below 0: the contact would jump to the other rim, which the model excludes.
    OtherRim,
    /// The state or its derivative became non-finite.
    NonFinite,
    /// The integrator could not take a step of resolvable size (a singularity).
    StepSizeTooSmall,
    /// The contact kept switching between rolling and sliding without time moving on
    /// (the sliding contact found no consistent state).
    ContactChatter,
}

impl EndReason {
    pub fn as_str(self) -> &'static str {
        match self {
            EndReason::Flat => "flat",
            EndReason::Rest => "rest",
            EndReason::TEnd => "t_end",
            EndReason::OtherRim => "other_rim",
            EndReason::NonFinite => "non_finite",
            EndReason::StepSizeTooSmall => "step_size_too_small",
            EndReason::ContactChatter => "contact_chatter",
        }
    }

    /// Whether the run ended because the motion itself ended (flat or at rest).
    pub fn is_natural(self) -> bool {
        matches!(self, EndReason::Flat | EndReason::Rest)
    }
}

impl fmt::Display for EndReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Why a run could not start.
#[derive(Clone, Debug, PartialEq)]
pub enum RunError {
    Param(ParamError),
    Integrator(IntegratorError),
    Unsupported(&'static str),
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunError::Param(e) => e.fmt(f),
            RunError::Integrator(e) => e.fmt(f),
            RunError::Unsupported(what) => f.write_str(what),
        }
    }
}

impl std::error::Error for RunError {}
