//! The switches of the sliding contact (slip effect): rolling to sliding where rolling needs
//! more friction than `mu F_N`, sliding to rolling where the slip has run out and rolling needs
//! no more, and the sliding contact's reference direction (`slip.rs`). Each is an event on the
//! dense output, like the turning points; the run restarts the stepper at it.

use super::super::contact::Contact;
use super::super::integrator::IntegratorError;
use super::super::slip::{
    REFERENCE_FREE_SPEEDS, SlidingModel, onset_direction, sliding_state, slip_velocity, stick,
    stick_margin,
};
use super::{EVENT_T_TOL, EndReason, Sample, Simulation, add_stats};

/// What happens at a switch found inside a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Switch {
    /// Rolling to sliding, or a stick.
    Contact,
    /// The slip enters the creep range: the sliding contact's reference is set.
    Reference,
}

/// The sliding contact's reference direction is turned to the slip's when they part by more
/// than 30 degrees (cosine).
const REFERENCE_TURN_COS: f64 = 0.866;
/// Contact switches at one instant after which the run gives up (`ContactChatter`).
const MAX_SWITCHES_AT_ONCE: u32 = 16;

impl Simulation {
    /// The switch event's function at the current point (see `switch_margin`).
    pub(super) fn current_switch_margin(&self) -> f64 {
        match (self.slip_mu, self.contact.sliding_state()) {
            (None, _) => 0.0,
            (Some(mu), None) => stick_margin(self.model(), mu, self.contact.state()),
            (Some(_), Some(y)) => {
                let v = slip_velocity(self.model(), y);
                match &self.contact {
                    Contact::Sliding(s) => {
                        let r = s.system.reference();
                        v[0] * r[0] + v[1] * r[1]
                    }
                    Contact::Rolling(_) => 0.0,
                }
            }
        }
    }

    pub(super) fn current_slip_speed(&self) -> f64 {
        self.contact.sliding_state().map_or(0.0, |y| {
            let v = slip_velocity(self.model(), y);
            v[0].hypot(v[1])
        })
    }

    /// With the slip effect: the time within the last step at which the contact switches,
    /// if it does. Rolling turns to sliding where `mu F_N - |F_t|` falls below zero (checked
    /// at the step's middle and end, so a short excursion inside a step is not missed);
    /// sliding sticks where the slip velocity's component along its reference direction
    /// reaches zero (only once it has been positive: at the onset it starts at zero). Before
    /// that, where the slip speed falls into the creep range (40 creep speeds, see
    /// `SlidingModel::may_update_reference`), the reference direction is set to the slip's
    /// there: a restart at a time fixed by the solution, not by the steps.
    pub(super) fn find_switch(&mut self, mu: f64, t_new: f64) -> Option<(f64, Switch)> {
        let t_old = self.contact.t_prev();
        let m_old = self.switch_margin;
        if !self.contact.is_sliding() {
            let margin = move |c: &mut Contact, t: f64| {
                let y = c.dense(t);
                stick_margin(c.model(), mu, &y)
            };
            if m_old < 0.0 || m_old.is_nan() {
                if self.start_held {
                    return None;
                }
                // Rolling although the margin is negative can only be the instant of a stick
                // with no friction to spare: slide at once.
                return Some((t_old, Switch::Contact));
            }
            let t_mid = 0.5 * (t_old + t_new);
            for b in [t_mid, t_new] {
                let m_b = margin(&mut self.contact, b);
                if m_b < 0.0 {
                    return Some((self.locate_in(b, margin, m_old, m_b), Switch::Contact));
                }
            }
            None
        } else {
            let creep = match &self.contact {
                Contact::Sliding(s) => s.system.creep_speed() * REFERENCE_FREE_SPEEDS,
                Contact::Rolling(_) => 0.0,
            };
            let g_old = self.slip_speed_start - creep;
            if g_old > 0.0 {
                let t_mid = 0.5 * (t_old + t_new);
                for b in [t_mid, t_new] {
                    let g_b = self.contact.slip_speed_at(b) - creep;
                    if g_b <= 0.0 {
                        let t = self.locate_in(b, |c, t| c.slip_speed_at(t) - creep, g_old, g_b);
                        return Some((t, Switch::Reference));
                    }
                }
            }
            if m_old <= 0.0 || m_old.is_nan() {
                return None;
            }
            let m_new = self.contact.slip_along_reference(t_new);
            if m_new > 0.0 {
                return None;
            }
            Some((
                self.locate_in(t_new, |c, t| c.slip_along_reference(t), m_old, m_new),
                Switch::Contact,
            ))
        }
    }

    /// Restarts the sliding stepper at `t` within the last step with the reference direction
    /// set to the slip's there (the entry into the creep range).
    pub(super) fn restart_sliding_at(&mut self, t: f64, sink: &mut impl FnMut(&Sample)) {
        let Some(ys) = self.contact.dense_sliding(t) else { return };
        let Contact::Sliding(old) = &self.contact else { return };
        let mut system = old.system.clone();
        system.set_reference(slip_velocity(&system.model, &ys));
        let next = Contact::sliding(system, t, ys, self.opts.tol, self.opts.h_max);
        if !self.install(next, t, sink) {
            return;
        }
        let s = self.contact.sample_now();
        self.margins = self.validity_margins(&s);
        self.switch_margin = self.current_switch_margin();
        // At the creep boundary now: no second entry until a step has left it.
        self.slip_speed_start = 0.0;
    }

    /// Puts the new contact in place at `t` (the old one's work counted), or ends the run
    /// there when it could not be started. False when the run ended.
    fn install(
        &mut self,
        next: Result<Contact, IntegratorError>,
        t: f64,
        sink: &mut impl FnMut(&Sample),
    ) -> bool {
        let done = self.contact.stats();
        match next {
            Ok(c) => {
                self.stats_done = add_stats(self.stats_done, done);
                self.contact = c;
                true
            }
            Err(e) => {
                self.final_sample = self.contact.sample_at(t);
                self.error = Some(e);
                self.end = Some((EndReason::NonFinite, t));
                sink(&self.final_sample);
                false
            }
        }
    }

    /// Switches the contact at `t` within the last step (rolling to sliding, or a stick).
    pub(super) fn switch_contact(&mut self, t: f64, sink: &mut impl FnMut(&Sample)) {
        let Some(mu) = self.slip_mu else { return };
        let model = self.contact.model().clone();
        let (tol, h_max) = (self.opts.tol, self.opts.h_max);
        let next = match self.contact.dense_sliding(t) {
            None => {
                // Onset of sliding.
                let y = self.contact.dense(t);
                let s_ref = onset_direction(&model, &y);
                let ys = sliding_state(&model, &y);
                Contact::sliding(SlidingModel::new(model, mu, s_ref), t, ys, tol, h_max)
            }
            Some(ys) => {
                // The slip has run out along its reference. If more than the creep speed is
                // left, the slip has turned (it passes by zero, or curls into it): slide on
                // with the reference turned to it. Otherwise it has come to rest: stick if
                // rolling needs no more than mu F_N (the creep-level slip left goes with a
                // plastic impulse), else slide on from zero slip in the onset direction.
                let v = slip_velocity(&model, &ys);
                let residual = v[0].hypot(v[1]);
                let creep = SlidingModel::new(model.clone(), mu, v).creep_speed();
                if residual > creep {
                    Contact::sliding(SlidingModel::new(model, mu, v), t, ys, tol, h_max)
                } else {
                    let (y, _) = stick(&model, &ys);
                    if stick_margin(&model, mu, &y) >= 0.0 {
                        self.stick_residual = self.stick_residual.max(residual);
                        Contact::rolling(model, t, y, tol, h_max)
                    } else {
                        let s_ref = onset_direction(&model, &y);
                        let ys = sliding_state(&model, &y);
                        Contact::sliding(SlidingModel::new(model, mu, s_ref), t, ys, tol, h_max)
                    }
                }
            }
        };
        if !self.install(next, t, sink) {
            return;
        }
        let s = self.contact.sample_now();
        self.sliding.update(t, s.sliding);
        self.margins = self.validity_margins(&s);
        if self.opts.track_validity {
            self.lift_off.update(t, self.margins.0 <= 0.0);
        }
        self.switch_margin = self.current_switch_margin();
        self.slip_speed_start = s.slip_speed;
        // Zeno guard: switches that do not let time move on.
        let (t_last, n) = self.switches_here;
        let n = if t - t_last <= EVENT_T_TOL * t.abs().max(1.0) { n + 1 } else { 1 };
        self.switches_here = (t, n);
        if n > MAX_SWITCHES_AT_ONCE {
            self.final_sample = s;
            self.end = Some((EndReason::ContactChatter, t));
            sink(&self.final_sample);
        }
    }

    /// After a step without a switch: the sliding contact's reference direction follows the
    /// slip once it is well above the creep speed (where the reference does not enter the
    /// friction), so that the stick event, the zero of the slip along the reference, means a
    /// stick; it is turned only when the slip has turned by 30 degrees from it. Then the
    /// switch functions at the new step's start.
    pub(super) fn follow_slip(&mut self) {
        if let Contact::Sliding(s) = &mut self.contact {
            let v = slip_velocity(&s.system.model, s.y());
            let r = s.system.reference();
            let turned = v[0] * r[0] + v[1] * r[1] < REFERENCE_TURN_COS * v[0].hypot(v[1]);
            if turned && s.system.may_update_reference(v) {
                s.update_system(|m| m.set_reference(v));
            }
        }
        self.switch_margin = self.current_switch_margin();
        self.slip_speed_start = self.current_slip_speed();
        self.release_held_start();
    }

    /// A start held rolling is released at the first step that begins with friction to
    /// spare; from there the switches are the margin's zero crossings.
    fn release_held_start(&mut self) {
        if self.start_held && self.switch_margin >= 0.0 {
            self.start_held = false;
            self.slip.update(self.contact.t(), false);
        }
    }
}
