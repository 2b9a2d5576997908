//! The state of the contact during a run: rolling (the paper's 8-number state, the fast path)
//! or sliding (10 numbers, `slip.rs`), each with its own stepper. The run swaps one for the
//! other at the transitions; everything else it does (events, samples, end conditions) goes
//! through this one interface.

use super::integrator::{Dop853, IntegratorError, Stats, Tolerances};
use super::model::{Model, STATE_LEN, StateVec, ix};
use super::sample::Sample;
use super::slip::{SLIDE_LEN, SlideVec, SlidingModel, sliding_energy, slip_velocity};
use super::trig::sin_cos;

// One per run: the rolling stepper stays inline (the fast path), the sliding one is boxed.
#[allow(clippy::large_enum_variant)]
pub(crate) enum Contact {
    Rolling(Dop853<Model, STATE_LEN>),
    /// Boxed: the larger stepper, and off the rolling fast path.
    Sliding(Box<Dop853<SlidingModel, SLIDE_LEN>>),
}

fn head(y: &SlideVec) -> StateVec {
    let mut out = [0.0; STATE_LEN];
    out.copy_from_slice(&y[..STATE_LEN]);
    out
}

impl Contact {
    pub fn rolling(
        model: Model,
        t0: f64,
        y0: StateVec,
        tol: Tolerances,
        h_max: f64,
    ) -> Result<Contact, IntegratorError> {
        Ok(Contact::Rolling(Dop853::new(model, t0, y0, tol, h_max)?))
    }

    pub fn sliding(
        model: SlidingModel,
        t0: f64,
        y0: SlideVec,
        tol: Tolerances,
        h_max: f64,
    ) -> Result<Contact, IntegratorError> {
        Ok(Contact::Sliding(Box::new(Dop853::new(model, t0, y0, tol, h_max)?)))
    }

    pub fn is_sliding(&self) -> bool {
        matches!(self, Contact::Sliding(_))
    }

    pub fn model(&self) -> &Model {
        match self {
            Contact::Rolling(s) => &s.system,
            Contact::Sliding(s) => &s.system.model,
        }
    }

    pub fn t(&self) -> f64 {
        match self {
            Contact::Rolling(s) => s.t(),
            Contact::Sliding(s) => s.t(),
        }
    }

    pub fn t_prev(&self) -> f64 {
        match self {
            Contact::Rolling(s) => s.t_prev(),
            Contact::Sliding(s) => s.t_prev(),
        }
    }

    pub fn stats(&self) -> Stats {
        match self {
            Contact::Rolling(s) => s.stats(),
            Contact::Sliding(s) => s.stats(),
        }
    }

    pub fn step(&mut self) -> Result<(), IntegratorError> {
        match self {
            Contact::Rolling(s) => s.step(),
            Contact::Sliding(s) => s.step(),
        }
    }

    /// One step to exactly `t_target` ([`Dop853::step_to`]).
    pub fn step_to(&mut self, t_target: f64, max_err: f64) -> bool {
        match self {
            Contact::Rolling(s) => s.step_to(t_target, max_err),
            Contact::Sliding(s) => s.step_to(t_target, max_err),
        }
    }

    /// The rolling part of the current state (all of it while rolling).
    pub fn state(&self) -> &StateVec {
        match self {
            Contact::Rolling(s) => s.y(),
            Contact::Sliding(s) => {
                let y: &[f64] = &s.y()[..STATE_LEN];
                y.try_into().expect("the sliding state starts with the rolling one")
            }
        }
    }

    /// The whole sliding state, while sliding.
    pub fn sliding_state(&self) -> Option<&SlideVec> {
        match self {
            Contact::Rolling(_) => None,
            Contact::Sliding(s) => Some(s.y()),
        }
    }

    /// The rolling part of the state at `t` within the last step.
    pub fn dense(&mut self, t: f64) -> StateVec {
        match self {
            Contact::Rolling(s) => s.dense(t),
            Contact::Sliding(s) => head(&s.dense(t)),
        }
    }

    /// The whole sliding state at `t` within the last step (None while rolling).
    pub fn dense_sliding(&mut self, t: f64) -> Option<SlideVec> {
        match self {
            Contact::Rolling(_) => None,
            Contact::Sliding(s) => Some(s.dense(t)),
        }
    }

    /// The sample at `t` within the last step.
    pub fn sample_at(&mut self, t: f64) -> Sample {
        match self {
            Contact::Rolling(s) => {
                let y = s.dense(t);
                Sample::new(&s.system, t, &y)
            }
            Contact::Sliding(s) => {
                let y = s.dense(t);
                Sample::sliding(&s.system, t, &y)
            }
        }
    }

    /// The position sample at `t` within the last step ([`Sample::position`]).
    pub fn position_at(&mut self, t: f64) -> Sample {
        match self {
            Contact::Rolling(s) => {
                let y = s.dense(t);
                Sample::position(&s.system, t, &y, false)
            }
            Contact::Sliding(s) => {
                let y = head(&s.dense(t));
                Sample::position(&s.system.model, t, &y, true)
            }
        }
    }

    /// The sample at the current time.
    pub fn sample_now(&self) -> Sample {
        match self {
            Contact::Rolling(s) => Sample::new(&s.system, s.t(), s.y()),
            Contact::Sliding(s) => Sample::sliding(&s.system, s.t(), s.y()),
        }
    }

    /// Kinetic energy at the current time.
    pub fn kinetic_energy(&self) -> f64 {
        let potential = |m: &Model, y: &[f64]| {
            let (st, ct) = sin_cos(y[ix::THETA]);
            m.g * (0.5 * m.body.h * st + m.body.r * ct)
        };
        match self {
            Contact::Rolling(s) => s.system.kinetic_energy(s.y()),
            Contact::Sliding(s) => {
                sliding_energy(&s.system.model, s.y()) - potential(&s.system.model, s.y())
            }
        }
    }

    /// While sliding: the slip speed at `t` within the last step (0 while rolling).
    pub fn slip_speed_at(&mut self, t: f64) -> f64 {
        match self {
            Contact::Rolling(_) => 0.0,
            Contact::Sliding(s) => {
                let y = s.dense(t);
                let v = slip_velocity(&s.system.model, &y);
                v[0].hypot(v[1])
            }
        }
    }

    /// While sliding: the slip velocity's component along the reference direction at `t`
    /// within the last step (the stick event's function).
    pub fn slip_along_reference(&mut self, t: f64) -> f64 {
        match self {
            Contact::Rolling(_) => 0.0,
            Contact::Sliding(s) => {
                let y = s.dense(t);
                let v = slip_velocity(&s.system.model, &y);
                let r = s.system.reference();
                v[0] * r[0] + v[1] * r[1]
            }
        }
    }
}
