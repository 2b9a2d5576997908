//! A run of the model: integration with end conditions, turning points, validity intervals
//! and samples on a fixed time grid from the dense output.

use super::body::{ParamError, check_finite, check_positive};
use super::integrator::{Dop853, IntegratorError, Stats, Tolerances, find_root};
use super::model::{Dynamics, Initial, Model, STATE_LEN, StateVec, ix};
use nalgebra::Vector3;
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

#[derive(Clone, Debug, PartialEq)]
pub struct RunOptions {
    pub t_end: f64,
    pub tol: Tolerances,
    pub theta_flat: f64,
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
            return Err(ParamError { name: "rtol", value: self.tol.rtol, reason: "must be below 1" });
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
            return Err(ParamError { name: "h_max", value: self.h_max, reason: "must be greater than zero" });
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

/// The state and everything derived from it at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub t: f64,
    pub y: StateVec,
    pub z_c: f64,
    /// Point A, the centre of the top edge: `r_A = r_C + (h/2) e2`.
    pub x_a: f64,
    pub y_a: f64,
    /// Contact point P = C - r_G.
    pub x_p: f64,
    pub y_p: f64,
    /// Velocity of A parallel to the table (the paper's `v_p`), table components.
    pub vx_a: f64,
    pub vy_a: f64,
    /// `|v_p|`.
    pub v_p: f64,
    pub f_1: f64,
    pub f_f: f64,
    pub f_n: f64,
    pub energy: f64,
    /// `|v_C|`.
    pub speed_c: f64,
    /// Reynolds number `2 |v_C| R / nu_air`.
    pub reynolds: f64,
}

impl Sample {
    pub fn new(model: &Model, t: f64, y: &StateVec) -> Sample {
        let d = model.dynamics(y[ix::THETA], &Vector3::new(y[ix::W1], y[ix::W2], y[ix::W3]));
        Sample::with_dynamics(model, t, y, &d)
    }

    fn with_dynamics(model: &Model, t: f64, y: &StateVec, d: &Dynamics) -> Sample {
        let b = &model.body;
        let (st, ct) = y[ix::THETA].sin_cos();
        let (sp, cp) = y[ix::PHI].sin_cos();
        let a = 0.5 * b.h;
        // Horizontal part of e2 is cos(theta) E2', E2' = (-sin phi, cos phi).
        let (x_a, y_a) = (y[ix::X] - a * ct * sp, y[ix::Y] + a * ct * cp);
        // P = C - (h/2) e2 - R e3; its horizontal offset is (R sin - (h/2) cos) E2'.
        let lever = b.r * st - a * ct;
        let (x_p, y_p) = (y[ix::X] - lever * sp, y[ix::Y] + lever * cp);
        // v_A = v_C + Omega x (h/2) e2, Omega = (w1, w3 tan, w3).
        let om = Vector3::new(y[ix::W1], y[ix::W3] * st / ct, y[ix::W3]);
        let v_a = d.v_c + om.cross(&Vector3::new(0.0, a, 0.0));
        // Horizontal part: e1 = (cos phi, sin phi), e2 and e3 contribute along E2'.
        let along_e2h = v_a.y * ct - v_a.z * st;
        let (vx_a, vy_a) = (v_a.x * cp - along_e2h * sp, v_a.x * sp + along_e2h * cp);
        let speed_c = d.v_c.norm();
        Sample {
            t,
            y: *y,
            z_c: a * st + b.r * ct,
            x_a,
            y_a,
            x_p,
            y_p,
            vx_a,
            vy_a,
            v_p: vx_a.hypot(vy_a),
            f_1: d.f_1,
            f_f: d.f_f,
            f_n: d.f_n,
            energy: model.energy(y),
            speed_c,
            reynolds: model.reynolds(speed_c),
        }
    }

    pub fn theta(&self) -> f64 {
        self.y[ix::THETA]
    }
    pub fn phi(&self) -> f64 {
        self.y[ix::PHI]
    }
    pub fn psi(&self) -> f64 {
        self.y[ix::PSI]
    }
    pub fn omega(&self) -> Vector3<f64> {
        Vector3::new(self.y[ix::W1], self.y[ix::W2], self.y[ix::W3])
    }
    pub fn x_c(&self) -> f64 {
        self.y[ix::X]
    }
    pub fn y_c(&self) -> f64 {
        self.y[ix::Y]
    }
    /// `sqrt(F_1^2 + F_f^2) / F_N`.
    pub fn friction_ratio(&self) -> f64 {
        self.f_1.hypot(self.f_f) / self.f_n
    }
    /// `phi'`, the precession rate of the line of nodes.
    pub fn phi_dot(&self) -> f64 {
        self.y[ix::W3] / self.theta().cos()
    }
}

/// Where `theta' = w1` vanishes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TurnKind {
    /// Highest centre of mass: `theta` at a minimum.
    ThetaMin,
    /// Lowest centre of mass: `theta` at a maximum (the cusps of the walk).
    ThetaMax,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TurningPoint {
    pub kind: TurnKind,
    pub sample: Sample,
}

/// A closed time interval `[start, end]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    pub start: f64,
    pub end: f64,
}

/// The outcome of a finished run.
#[derive(Clone, Debug)]
pub struct RunSummary {
    pub end_reason: EndReason,
    pub t_end: f64,
    pub final_sample: Sample,
    pub turning_points: Vec<TurningPoint>,
    /// Where `F_N <= 0`: the body would leave the table.
    pub lift_off: Vec<Interval>,
    /// Where `sqrt(F_1^2 + F_f^2) > mu F_N`: rolling needs more friction than the table gives
    /// (this includes the lift-off intervals, where `mu F_N <= 0`).
    pub slip: Vec<Interval>,
    pub stats: Stats,
    /// The integrator's error, when the run ended on one.
    pub error: Option<IntegratorError>,
}

/// Tracks one sign condition along the run and collects the intervals where it holds.
#[derive(Clone, Debug, Default)]
struct IntervalTracker {
    open: Option<f64>,
    closed: Vec<Interval>,
}

impl IntervalTracker {
    fn update(&mut self, t: f64, inside: bool) {
        match (self.open, inside) {
            (None, true) => self.open = Some(t),
            (Some(s), false) => {
                self.closed.push(Interval { start: s, end: t });
                self.open = None;
            }
            _ => {}
        }
    }
    fn finish(&mut self, t: f64) -> Vec<Interval> {
        if let Some(s) = self.open.take() {
            self.closed.push(Interval { start: s, end: t });
        }
        std::mem::take(&mut self.closed)
    }
}

/// A run in progress. [`Simulation::advance`] integrates up to a time and hands samples to a
/// sink; the live view drives it in small slices, the CLI in one go.
pub struct Simulation {
    stepper: Dop853<Model, STATE_LEN>,
    opts: RunOptions,
    t0: f64,
    sample_index: u64,
    rest_kinetic: f64,
    end: Option<(EndReason, f64)>,
    error: Option<IntegratorError>,
    final_sample: Sample,
    turning_points: Vec<TurningPoint>,
    lift_off: IntervalTracker,
    slip: IntervalTracker,
    /// Validity margins `(F_N, mu F_N - |F_t|)` at the start of the current step.
    margins: (f64, f64),
}

/// Time tolerance of event location, relative to `max(1, |t|)`.
const EVENT_T_TOL: f64 = 1e-13;

impl Simulation {
    /// Starts a run at `t = 0`.
    pub fn new(model: Model, initial: &Initial, opts: RunOptions) -> Result<Simulation, RunError> {
        initial.validate().map_err(RunError::Param)?;
        Simulation::from_state(model, 0.0, initial.to_state(), opts)
    }

    /// Starts a run from any state (used to continue with changed parameters).
    pub fn from_state(model: Model, t0: f64, y0: StateVec, opts: RunOptions) -> Result<Simulation, RunError> {
        opts.validate().map_err(RunError::Param)?;
        model.effects.validate().map_err(RunError::Param)?;
        if model.effects.slip_mu.is_some() {
            return Err(RunError::Unsupported("the sliding contact (slip) is not available yet"));
        }
        let rest_kinetic = REST_KINETIC_FRACTION * model.g * model.body.r;
        let stepper = Dop853::new(model, t0, y0, opts.tol, opts.h_max).map_err(RunError::Integrator)?;
        let s0 = Sample::new(&stepper.system, t0, &y0);
        let mut sim = Simulation {
            stepper,
            t0,
            sample_index: 0,
            rest_kinetic,
            end: None,
            error: None,
            final_sample: s0,
            turning_points: Vec::new(),
            lift_off: IntervalTracker::default(),
            slip: IntervalTracker::default(),
            margins: (0.0, 0.0),
            opts,
        };
        sim.margins = sim.validity_margins(&s0);
        if sim.opts.track_validity {
            sim.lift_off.update(t0, sim.margins.0 <= 0.0);
            sim.slip.update(t0, sim.margins.1 < 0.0);
        }
        // A start with theta' = 0 is itself a turning point (the paper starts at one).
        if y0[ix::W1] == 0.0 {
            let d = sim.model().dynamics(y0[ix::THETA], &Vector3::new(0.0, y0[ix::W2], y0[ix::W3]));
            let kind = if d.omega_dot.x >= 0.0 { TurnKind::ThetaMin } else { TurnKind::ThetaMax };
            sim.turning_points.push(TurningPoint { kind, sample: s0 });
        }
        Ok(sim)
    }

    pub fn model(&self) -> &Model {
        &self.stepper.system
    }
    pub fn options(&self) -> &RunOptions {
        &self.opts
    }
    pub fn t(&self) -> f64 {
        self.end.map(|e| e.1).unwrap_or(self.stepper.t())
    }
    pub fn state(&self) -> &StateVec {
        self.stepper.y()
    }
    pub fn end_reason(&self) -> Option<EndReason> {
        self.end.map(|e| e.0)
    }
    pub fn turning_points(&self) -> &[TurningPoint] {
        &self.turning_points
    }
    pub fn stats(&self) -> Stats {
        self.stepper.stats()
    }
    /// The last sample of a finished run (or the start, before).
    pub fn final_sample(&self) -> &Sample {
        &self.final_sample
    }

    fn validity_margins(&self, s: &Sample) -> (f64, f64) {
        (s.f_n, self.opts.mu * s.f_n - s.f_1.hypot(s.f_f))
    }

    /// Integrates until `t >= t_stop` or the run ends; every sample on the grid
    /// `t0 + k dt` up to the last step goes to `sink`, and the end point too.
    /// Returns the end reason once the run has ended.
    pub fn advance(&mut self, t_stop: f64, sink: &mut impl FnMut(&Sample)) -> Option<EndReason> {
        while self.end.is_none() && self.stepper.t() < t_stop {
            self.one_step(sink);
        }
        self.end_reason()
    }

    /// Runs to the end (`t_end` at the latest).
    pub fn run(mut self, sink: &mut impl FnMut(&Sample)) -> RunSummary {
        let t_end = self.opts.t_end;
        self.advance(t_end, sink);
        self.finish()
    }

    /// Closes the run (at its current time if it has not ended) and returns the summary.
    pub fn finish(mut self) -> RunSummary {
        let (reason, t) = match self.end {
            Some(e) => e,
            None => {
                let t = self.stepper.t();
                self.final_sample = Sample::new(self.model(), t, self.stepper.y());
                (EndReason::TEnd, t)
            }
        };
        RunSummary {
            end_reason: reason,
            t_end: t,
            final_sample: self.final_sample,
            turning_points: self.turning_points,
            lift_off: self.lift_off.finish(t),
            slip: self.slip.finish(t),
            stats: self.stepper.stats(),
            error: self.error,
        }
    }

    /// Locates a sign change of `g` over the last step, or over `[t_prev, b]` when `b` is given.
    fn locate(&mut self, g: impl Fn(&Model, f64, &StateVec) -> f64, g_old: f64, g_new: f64) -> f64 {
        let b = self.stepper.t();
        self.locate_in(b, g, g_old, g_new)
    }

    fn locate_in(&mut self, b: f64, g: impl Fn(&Model, f64, &StateVec) -> f64, g_old: f64, g_b: f64) -> f64 {
        let a = self.stepper.t_prev();
        let tol = EVENT_T_TOL * b.abs().max(1.0);
        let stepper = &mut self.stepper;
        find_root(
            |t| {
                let y = stepper.dense(t);
                g(&stepper.system, t, &y)
            },
            a,
            b,
            g_old,
            g_b,
            tol,
        )
    }

    fn one_step(&mut self, sink: &mut impl FnMut(&Sample)) {
        let (t_old, y_old) = (self.stepper.t(), *self.stepper.y());
        if let Err(e) = self.stepper.step() {
            let reason = match e {
                IntegratorError::NonFinite { .. } => EndReason::NonFinite,
                _ => EndReason::StepSizeTooSmall,
            };
            self.error = Some(e);
            self.final_sample = Sample::new(self.model(), t_old, &y_old);
            self.end = Some((reason, t_old));
            sink(&self.final_sample);
            return;
        }
        let (t_new, y_new) = (self.stepper.t(), *self.stepper.y());

        // Turning point: theta' = w1 changes sign (at most one per step at these tolerances).
        let (w_old, w_new) = (y_old[ix::W1], y_new[ix::W1]);
        let kind = if w_old < 0.0 && w_new >= 0.0 {
            Some(TurnKind::ThetaMin)
        } else if w_old > 0.0 && w_new <= 0.0 {
            Some(TurnKind::ThetaMax)
        } else {
            None
        };
        let turn = kind.map(|kind| {
            let t = self.locate(|_, _, y| y[ix::W1], w_old, w_new);
            let y = self.stepper.dense(t);
            (kind, t, y)
        });

        // End conditions inside this step: the earliest wins. A theta limit can be crossed
        // and recrossed within one step, so theta is also checked at the step's extremum.
        let mut cut: Option<(EndReason, f64)> = None;
        let earliest = |c: &mut Option<(EndReason, f64)>, r: EndReason, t: f64| {
            if c.is_none_or(|(_, tc)| t < tc) {
                *c = Some((r, t));
            }
        };
        let flat = self.opts.theta_flat;
        let th_old = y_old[ix::THETA];
        let peak = match turn {
            Some((TurnKind::ThetaMax, t, y)) if y[ix::THETA] >= flat => Some((t, y[ix::THETA])),
            _ => None,
        };
        if let Some((b, th_b)) = peak.or((y_new[ix::THETA] >= flat).then_some((t_new, y_new[ix::THETA]))) {
            let t = self.locate_in(b, |_, _, y| y[ix::THETA] - flat, th_old - flat, th_b - flat);
            earliest(&mut cut, EndReason::Flat, t);
        }
        let trough = match turn {
            Some((TurnKind::ThetaMin, t, y)) if y[ix::THETA] < 0.0 => Some((t, y[ix::THETA])),
            _ => None,
        };
        if let Some((b, th_b)) = trough.or((y_new[ix::THETA] < 0.0).then_some((t_new, y_new[ix::THETA]))) {
            let t = self.locate_in(b, |_, _, y| y[ix::THETA], th_old, th_b);
            earliest(&mut cut, EndReason::OtherRim, t);
        }
        if t_new >= self.opts.t_end {
            earliest(&mut cut, EndReason::TEnd, self.opts.t_end);
        }
        if self.model().kinetic_energy(&y_new) < self.rest_kinetic {
            earliest(&mut cut, EndReason::Rest, t_new);
        }
        let t_cut = cut.map(|c| c.1).unwrap_or(t_new);

        if let Some((kind, t, y)) = turn {
            if t <= t_cut {
                let sample = Sample::new(self.model(), t, &y);
                self.turning_points.push(TurningPoint { kind, sample });
            }
        }

        if self.opts.track_validity {
            self.track_validity(t_new, &y_new, t_cut);
        }

        // Samples on the grid up to the cut.
        if let Some(dt) = self.opts.sample_dt {
            loop {
                let ts = self.t0 + self.sample_index as f64 * dt;
                if ts > t_cut {
                    break;
                }
                let y = self.stepper.dense(ts);
                sink(&Sample::new(self.model(), ts, &y));
                self.sample_index += 1;
            }
        }

        if let Some((reason, t)) = cut {
            let y = if t == t_new { y_new } else { self.stepper.dense(t) };
            self.final_sample = Sample::new(self.model(), t, &y);
            let on_grid = self.opts.sample_dt.is_some_and(|dt| {
                let k = ((t - self.t0) / dt).round();
                (self.t0 + k * dt - t).abs() <= 1e-12 * t.abs().max(1.0)
            });
            if !on_grid {
                sink(&self.final_sample);
            }
            self.end = Some((reason, t));
        }
    }

    fn track_validity(&mut self, t_new: f64, y_new: &StateVec, t_cut: f64) {
        let s_new = Sample::new(self.model(), t_new, y_new);
        let (n_new, m_new) = self.validity_margins(&s_new);
        let (n_old, m_old) = self.margins;
        let mu = self.opts.mu;
        let f_n = |m: &Model, t: f64, y: &StateVec| Sample::new(m, t, y).f_n;
        let margin = move |m: &Model, t: f64, y: &StateVec| {
            let s = Sample::new(m, t, y);
            mu * s.f_n - s.f_1.hypot(s.f_f)
        };
        // Both conditions can change in one step; apply them in time order per tracker.
        if (n_old <= 0.0) != (n_new <= 0.0) {
            let t = self.locate(f_n, n_old, n_new);
            if t <= t_cut {
                self.lift_off.update(t, n_new <= 0.0);
            }
        }
        if (m_old < 0.0) != (m_new < 0.0) {
            let t = self.locate(margin, m_old, m_new);
            if t <= t_cut {
                self.slip.update(t, m_new < 0.0);
            }
        }
        self.margins = (n_new, m_new);
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

/// Runs a model from an initial state to its end, collecting samples every `opts.sample_dt`.
pub fn simulate(model: Model, initial: &Initial, opts: RunOptions) -> Result<(RunSummary, Vec<Sample>), RunError> {
    let sim = Simulation::new(model, initial, opts)?;
    let mut samples = Vec::new();
    let summary = sim.run(&mut |s| samples.push(*s));
    Ok((summary, samples))
}
