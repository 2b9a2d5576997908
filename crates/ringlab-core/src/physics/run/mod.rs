//! A run of the model: integration with end conditions, turning points, validity intervals
//! and samples on a fixed time grid from the dense output; with the slip effect, the switches
//! between rolling and sliding (`switch.rs`); a run's step ends kept for another to follow
//! (`steps.rs`).

mod options;
mod steps;
mod switch;

use super::contact::Contact;
use super::integrator::{IntegratorError, Stats, find_root};
use super::model::{Initial, Model, SlipStart, StateVec, ix};
use super::slip::{
    SlideVec, SlidingModel, VX, VY, onset_direction, sliding_state, slip_velocity, stick_margin,
};

use std::sync::Arc;
use steps::{FOLLOW_MAX_ERR, Steps};
use switch::Switch;

pub use super::sample::Sample;
pub use options::{
    DEFAULT_MU, DEFAULT_THETA_FLAT, EndReason, REST_KINETIC_FRACTION, RunError, RunOptions,
};

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
    /// (this includes the lift-off intervals, where `mu F_N <= 0`). With the slip effect the
    /// contact slides there instead (see `sliding`); only a start held rolling
    /// ([`SlipStart::HeldRolling`]) is listed here, up to the step where it is released.
    pub slip: Vec<Interval>,
    /// Where the contact slides (slip effect on; empty otherwise).
    pub sliding: Vec<Interval>,
    /// Largest slip speed left when the contact stuck, removed by the sticking impulse
    /// (rounding level: the stick event is located on the dense output).
    pub stick_residual: f64,
    pub stats: Stats,
    /// The integrator's error, when the run ended on one.
    pub error: Option<IntegratorError>,
    /// Where each step ended, in the order taken, when kept ([`Simulation::keep_steps`]).
    pub step_ends: Vec<f64>,
}

/// Tracks one sign condition along a stream of times and collects the intervals where it
/// holds (a run's lift-off and slip; the live view's, as the states arrive).
#[derive(Clone, Debug, Default)]
pub struct IntervalTracker {
    /// Where the interval still open began.
    pub open: Option<f64>,
    pub closed: Vec<Interval>,
}

impl IntervalTracker {
    pub fn update(&mut self, t: f64, inside: bool) {
        match (self.open, inside) {
            (None, true) => self.open = Some(t),
            (Some(s), false) => {
                self.closed.push(Interval { start: s, end: t });
                self.open = None;
            }
            _ => {}
        }
    }
    /// The intervals up to `t` (the open one, and any reaching past `t`, end there).
    pub fn until(&self, t: f64) -> Vec<Interval> {
        let mut v: Vec<Interval> = self.closed.iter().filter(|i| i.start <= t).copied().collect();
        if let Some(s) = self.open.filter(|&s| s <= t) {
            v.push(Interval { start: s, end: t });
        }
        for i in &mut v {
            i.end = i.end.min(t);
        }
        v
    }

    /// Closes the open interval at `t` and hands over all of them.
    pub fn finish(&mut self, t: f64) -> Vec<Interval> {
        if let Some(s) = self.open.take() {
            self.closed.push(Interval { start: s, end: t });
        }
        std::mem::take(&mut self.closed)
    }
}

fn add_stats(a: Stats, b: Stats) -> Stats {
    Stats {
        rhs_evaluations: a.rhs_evaluations + b.rhs_evaluations,
        steps: a.steps + b.steps,
        rejected: a.rejected + b.rejected,
    }
}

/// A run in progress. [`Simulation::advance`] integrates up to a time and hands samples to a
/// sink; the live view drives it in small slices, the CLI in one go.
///
/// With the slip effect the contact alternates between rolling (the paper's state, on the
/// fast path) and sliding (`slip.rs`); the switches are events located on the dense output
/// like the turning points, and each phase gets its own stepper.
pub struct Simulation {
    contact: Contact,
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
    sliding: IntervalTracker,
    /// Validity margins `(F_N, mu F_N - |F_t|)` at the start of the current step.
    margins: (f64, f64),
    /// The sliding contact's friction coefficient (static and kinetic), when on.
    slip_mu: Option<f64>,
    /// At the start of the current step: while rolling with slip on, `mu F_N - |F_t|`; while
    /// sliding, the slip velocity along its reference direction.
    switch_margin: f64,
    /// While sliding: the slip speed at the start of the current step.
    slip_speed_start: f64,
    /// A start held rolling beyond the friction cone ([`SlipStart::HeldRolling`]), until
    /// rolling first needs no more than `mu F_N`.
    start_held: bool,
    /// Work of the steppers of earlier phases.
    stats_done: Stats,
    /// Time of the last contact switch and how many happened there in a row.
    switches_here: (f64, u32),
    stick_residual: f64,
    steps: Steps,
    /// Whether the grid's samples carry positions only ([`Simulation::positions_only`]).
    positions_only: bool,
}

/// The sliding state at a run's start from rolling state `y0`: its slip velocity is the
/// model's `slip_start_velocity`, turned from the heading frame to the table's.
fn slide_start(model: &Model, y0: &StateVec) -> SlideVec {
    let mut ys = sliding_state(model, y0);
    let [along, across] = model.effects.slip_start_velocity;
    let (sp, cp) = y0[ix::PHI].sin_cos();
    ys[VX] += along * cp - across * sp;
    ys[VY] += along * sp + across * cp;
    ys
}

/// Time tolerance of event location, relative to `max(1, |t|)`.
const EVENT_T_TOL: f64 = 1e-13;
impl Simulation {
    /// Starts a run at `t = 0`.
    pub fn new(model: Model, initial: &Initial, opts: RunOptions) -> Result<Simulation, RunError> {
        initial.validate().map_err(RunError::Param)?;
        Simulation::from_state(model, 0.0, initial.to_state(), opts)
    }

    /// Starts a run from any rolling state (used to continue with changed parameters). With
    /// the slip effect on, a state where rolling needs more friction than `mu F_N` starts
    /// sliding, or rolls on until the margin recovers (`Effects::slip_start`).
    pub fn from_state(
        model: Model,
        t0: f64,
        y0: StateVec,
        opts: RunOptions,
    ) -> Result<Simulation, RunError> {
        opts.validate().map_err(RunError::Param)?;
        model.check_effects().map_err(RunError::Param)?;
        let slip_mu = model.effects.slip_mu;
        let beyond_cone = slip_mu.is_some_and(|mu| {
            let m = stick_margin(&model, mu, &y0);
            m < 0.0 || m.is_nan()
        });
        let held = beyond_cone && model.effects.slip_start == SlipStart::HeldRolling;
        let slide_in_progress = model.effects.slip_start == SlipStart::Cone
            && model.effects.slip_start_velocity != [0.0, 0.0];
        let contact = if let (true, false, Some(mu)) = (beyond_cone, held, slip_mu) {
            let s_ref = onset_direction(&model, &y0);
            let ys = slide_start(&model, &y0);
            Contact::sliding(SlidingModel::new(model, mu, s_ref), t0, ys, opts.tol, opts.h_max)
        } else if let (true, Some(mu)) = (slide_in_progress, slip_mu) {
            // Within the cone the slide's own direction is the reference (a small slip then
            // dies out at once, as zero slip would not begin).
            let ys = slide_start(&model, &y0);
            let s_ref = slip_velocity(&model, &ys);
            Contact::sliding(SlidingModel::new(model, mu, s_ref), t0, ys, opts.tol, opts.h_max)
        } else {
            Contact::rolling(model, t0, y0, opts.tol, opts.h_max)
        }
        .map_err(RunError::Integrator)?;
        let mut sim = Simulation::start(contact, t0, opts);
        if held {
            sim.start_held = true;
            sim.slip.update(t0, true);
        }
        // A start with theta' = 0 is itself a turning point (the paper starts at one).
        if y0[ix::W1] == 0.0 {
            let d = sim.model().dynamics_of(&[
                y0[0],
                y0[1],
                y0[2],
                0.0,
                y0[ix::W2],
                y0[ix::W3],
                y0[6],
                y0[7],
            ]);
            let kind = if d.omega_dot.x >= 0.0 { TurnKind::ThetaMin } else { TurnKind::ThetaMax };
            sim.turning_points.push(TurningPoint { kind, sample: sim.final_sample });
        }
        Ok(sim)
    }

    /// Starts a run from a sliding state `[phi, theta, psi, w1, w2, w3, x_C, y_C, vx_C, vy_C]`
    /// (`slip.rs`); needs the slip effect. Without slip it is the rolling start.
    pub fn from_sliding_state(
        model: Model,
        t0: f64,
        y0: SlideVec,
        opts: RunOptions,
    ) -> Result<Simulation, RunError> {
        let Some(mu) = model.effects.slip_mu else {
            return Err(RunError::Unsupported("a sliding start needs the slip effect (slip_mu)"));
        };
        if y0.iter().any(|v| !v.is_finite()) {
            return Err(RunError::Integrator(IntegratorError::BadInitialState));
        }
        let v_s = slip_velocity(&model, &y0);
        if v_s == [0.0, 0.0] {
            let mut y8 = [0.0; super::model::STATE_LEN];
            y8.copy_from_slice(&y0[..super::model::STATE_LEN]);
            return Simulation::from_state(model, t0, y8, opts);
        }
        opts.validate().map_err(RunError::Param)?;
        model.check_effects().map_err(RunError::Param)?;
        let contact =
            Contact::sliding(SlidingModel::new(model, mu, v_s), t0, y0, opts.tol, opts.h_max)
                .map_err(RunError::Integrator)?;
        Ok(Simulation::start(contact, t0, opts))
    }

    fn start(contact: Contact, t0: f64, opts: RunOptions) -> Simulation {
        let model = contact.model();
        let rest_kinetic = REST_KINETIC_FRACTION * model.g * model.body.r;
        let slip_mu = model.effects.slip_mu;
        let s0 = contact.sample_now();
        let mut sim = Simulation {
            contact,
            t0,
            sample_index: 0,
            rest_kinetic,
            end: None,
            error: None,
            final_sample: s0,
            turning_points: Vec::new(),
            lift_off: IntervalTracker::default(),
            slip: IntervalTracker::default(),
            sliding: IntervalTracker::default(),
            margins: (0.0, 0.0),
            slip_mu,
            switch_margin: 0.0,
            slip_speed_start: 0.0,
            start_held: false,
            stats_done: Stats::default(),
            switches_here: (t0, 0),
            stick_residual: 0.0,
            steps: Steps::Adaptive,
            positions_only: false,
            opts,
        };
        sim.margins = sim.validity_margins(&s0);
        if sim.opts.track_validity {
            sim.lift_off.update(t0, sim.margins.0 <= 0.0);
            if sim.slip_mu.is_none() {
                sim.slip.update(t0, sim.margins.1 < 0.0);
            }
        }
        sim.sliding.update(t0, sim.contact.is_sliding());
        sim.switch_margin = sim.current_switch_margin();
        sim.slip_speed_start = sim.current_slip_speed();
        sim
    }

    pub fn model(&self) -> &Model {
        self.contact.model()
    }
    pub fn options(&self) -> &RunOptions {
        &self.opts
    }
    pub fn t(&self) -> f64 {
        self.end.map(|e| e.1).unwrap_or(self.contact.t())
    }
    /// The current state (while sliding: its first eight numbers, as while rolling).
    pub fn state(&self) -> &StateVec {
        self.contact.state()
    }
    /// Whether the contact slides now.
    pub fn is_sliding(&self) -> bool {
        self.contact.is_sliding()
    }
    /// The whole sliding state, while sliding.
    pub fn sliding_state(&self) -> Option<&SlideVec> {
        self.contact.sliding_state()
    }
    pub fn end_reason(&self) -> Option<EndReason> {
        self.end.map(|e| e.0)
    }
    pub fn turning_points(&self) -> &[TurningPoint] {
        &self.turning_points
    }
    pub fn stats(&self) -> Stats {
        add_stats(self.stats_done, self.contact.stats())
    }
    /// The last sample of a finished run (or the start, before).
    pub fn final_sample(&self) -> &Sample {
        &self.final_sample
    }

    /// Keeps where each step ends, for a run of nearby parameters to follow
    /// ([`RunSummary::step_ends`], [`Self::follow_steps`]).
    pub fn keep_steps(&mut self) {
        self.steps = Steps::Keep(Vec::new());
    }

    /// Steps to the ends another run kept (`steps.rs`), adaptively where one of them does not
    /// hold and beyond the last.
    pub fn follow_steps(&mut self, ends: Arc<[f64]>) {
        self.steps = Steps::Follow { ends, next: 0 };
    }

    /// The grid's samples with positions only ([`Sample::position`]): a fit's prediction
    /// projects nothing else, and a full sample costs a force evaluation. The end's sample,
    /// the turning points and the validity checks stay whole.
    pub fn positions_only(&mut self) {
        self.positions_only = true;
    }

    fn validity_margins(&self, s: &Sample) -> (f64, f64) {
        (s.f_n, self.opts.mu * s.f_n - s.f_1.hypot(s.f_f))
    }

    /// Integrates until `t >= t_stop` or the run ends; every sample on the grid
    /// `t0 + k dt` up to the last step goes to `sink`, and the end point too.
    /// Returns the end reason once the run has ended.
    pub fn advance(&mut self, t_stop: f64, sink: &mut impl FnMut(&Sample)) -> Option<EndReason> {
        while self.end.is_none() && self.contact.t() < t_stop {
            self.one_step(sink);
        }
        self.end_reason()
    }

    /// As [`Self::advance`], stopping early (without an end) once the run has taken
    /// `max_steps` steps in all: a caller's budget (the run can go on with another call).
    pub fn advance_limited(
        &mut self,
        t_stop: f64,
        max_steps: u64,
        sink: &mut impl FnMut(&Sample),
    ) -> Option<EndReason> {
        while self.end.is_none() && self.contact.t() < t_stop && self.stats().steps < max_steps {
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
                let t = self.contact.t();
                self.final_sample = self.contact.sample_now();
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
            sliding: self.sliding.finish(t),
            stick_residual: self.stick_residual,
            stats: add_stats(self.stats_done, self.contact.stats()),
            error: self.error,
            step_ends: self.steps.into_kept(),
        }
    }

    /// Locates a sign change of `g` over `[t_prev, b]` of the last step.
    fn locate_in(
        &mut self,
        b: f64,
        mut g: impl FnMut(&mut Contact, f64) -> f64,
        g_old: f64,
        g_b: f64,
    ) -> f64 {
        let a = self.contact.t_prev();
        let tol = EVENT_T_TOL * b.abs().max(1.0);
        let contact = &mut self.contact;
        find_root(|t| g(contact, t), a, b, g_old, g_b, tol)
    }

    fn one_step(&mut self, sink: &mut impl FnMut(&Sample)) {
        let (t_old, y_old) = (self.contact.t(), *self.contact.state());
        let followed =
            self.steps.target(t_old).is_some_and(|end| self.contact.step_to(end, FOLLOW_MAX_ERR));
        if !followed && let Err(e) = self.contact.step() {
            let reason = match e {
                IntegratorError::NonFinite { .. } => EndReason::NonFinite,
                _ => EndReason::StepSizeTooSmall,
            };
            self.error = Some(e);
            self.final_sample = self.contact.sample_now();
            self.end = Some((reason, t_old));
            sink(&self.final_sample);
            return;
        }
        let (t_new, y_new) = (self.contact.t(), *self.contact.state());
        self.steps.taken(t_new);

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
            let t = self.locate_in(t_new, |c, t| c.dense(t)[ix::W1], w_old, w_new);
            let y = self.contact.dense(t);
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
        if let Some((b, th_b)) =
            peak.or((y_new[ix::THETA] >= flat).then_some((t_new, y_new[ix::THETA])))
        {
            let t =
                self.locate_in(b, |c, t| c.dense(t)[ix::THETA] - flat, th_old - flat, th_b - flat);
            earliest(&mut cut, EndReason::Flat, t);
        }
        let trough = match turn {
            Some((TurnKind::ThetaMin, t, y)) if y[ix::THETA] < 0.0 => Some((t, y[ix::THETA])),
            _ => None,
        };
        if let Some((b, th_b)) =
            trough.or((y_new[ix::THETA] < 0.0).then_some((t_new, y_new[ix::THETA])))
        {
            let t = self.locate_in(b, |c, t| c.dense(t)[ix::THETA], th_old, th_b);
            earliest(&mut cut, EndReason::OtherRim, t);
        }
        if t_new >= self.opts.t_end {
            earliest(&mut cut, EndReason::TEnd, self.opts.t_end);
        }
        if self.contact.kinetic_energy() < self.rest_kinetic {
            earliest(&mut cut, EndReason::Rest, t_new);
        }
        let t_cut = cut.map(|c| c.1).unwrap_or(t_new);

        // A switch between rolling and sliding before the end: the step counts only up to it.
        let switch = match self.slip_mu {
            Some(mu) => self.find_switch(mu, t_new).filter(|&(t, _)| t < t_cut),
            None => None,
        };
        let switch_t = switch.map(|s| s.0);
        let t_limit = switch_t.unwrap_or(t_cut);

        if let Some((kind, t, y)) = turn
            && t <= t_limit
        {
            let sample = self.contact.sample_at(t);
            debug_assert_eq!(sample.y, y);
            self.turning_points.push(TurningPoint { kind, sample });
        }

        if self.opts.track_validity {
            self.track_validity(switch_t.unwrap_or(t_new), t_limit);
        }

        // Samples on the grid up to the cut.
        if let Some(dt) = self.opts.sample_dt {
            loop {
                let ts = self.t0 + self.sample_index as f64 * dt;
                if ts > t_limit {
                    break;
                }
                let sample = if self.positions_only {
                    self.contact.position_at(ts)
                } else {
                    self.contact.sample_at(ts)
                };
                sink(&sample);
                self.sample_index += 1;
            }
        }

        match switch {
            Some((t, Switch::Contact)) => {
                self.switch_contact(t, sink);
                return;
            }
            Some((t, Switch::Reference)) => {
                self.restart_sliding_at(t, sink);
                return;
            }
            None => {}
        }

        if let Some((reason, t)) = cut {
            self.final_sample =
                if t == t_new { self.contact.sample_now() } else { self.contact.sample_at(t) };
            let on_grid = self.opts.sample_dt.is_some_and(|dt| {
                let k = ((t - self.t0) / dt).round();
                (self.t0 + k * dt - t).abs() <= 1e-12 * t.abs().max(1.0)
            });
            if !on_grid {
                sink(&self.final_sample);
            }
            self.end = Some((reason, t));
            return;
        }

        self.follow_slip();
    }

    /// Lift-off (`F_N <= 0`) and, in pure rolling, would-slip (`|F_t| > mu F_N`) intervals
    /// over the last step up to `b`, keeping those that start before `t_cut`.
    fn track_validity(&mut self, b: f64, t_cut: f64) {
        let s_b = self.contact.sample_at(b);
        let (n_b, m_b) = self.validity_margins(&s_b);
        let (n_old, m_old) = self.margins;
        let mu = self.opts.mu;
        // Both conditions can change in one step; apply them in time order per tracker.
        if (n_old <= 0.0) != (n_b <= 0.0) {
            let t = self.locate_in(b, |c, t| c.sample_at(t).f_n, n_old, n_b);
            if t <= t_cut {
                self.lift_off.update(t, n_b <= 0.0);
            }
        }
        if self.slip_mu.is_none() && (m_old < 0.0) != (m_b < 0.0) {
            let margin = move |c: &mut Contact, t: f64| {
                let s = c.sample_at(t);
                mu * s.f_n - s.f_1.hypot(s.f_f)
            };
            let t = self.locate_in(b, margin, m_old, m_b);
            if t <= t_cut {
                self.slip.update(t, m_b < 0.0);
            }
        }
        self.margins = (n_b, m_b);
    }
}

/// Runs a model from an initial state to its end, collecting samples every `opts.sample_dt`.
pub fn simulate(
    model: Model,
    initial: &Initial,
    opts: RunOptions,
) -> Result<(RunSummary, Vec<Sample>), RunError> {
    let sim = Simulation::new(model, initial, opts)?;
    let mut samples = Vec::new();
    let summary = sim.run(&mut |s| samples.push(*s));
    Ok((summary, samples))
}
