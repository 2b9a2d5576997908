//! The losses beyond the paper's drag that change the contact force: rolling and pivot
//! friction (torques proportional to `F_N`) and quadratic air drag on the centre of mass. This
//! is the cold path of the rolling right-hand side ([`Model::dynamics_sc`]); the sliding contact
//! (`slip.rs`) applies the same torques and force.
//!
//! Mechanics (m = 1, frame components, `Z = (0, sin(theta), cos(theta))`):
//! - A couple `T` about C and a force `F_d` at C change eqs. 1-2 to
//!   `I w' + Omega x I w = -r_G x F + T_drag + T` and `a_C = F - g Z + F_d`; with rolling
//!   (`a_C = w' x r_G + Omega x v_C`) this is eq. 4 with `f -> f + r_G x F_d + T`, and the
//!   contact force becomes `F = w' x r_G + Omega x v_C + g Z - F_d`.
//! - Rolling friction `T = -k_r F_N w_h / |w_h|` (`w_h = w - (w . Z) Z`, the rolling part of
//!   omega) and pivot friction `T = -k_p F_N sign(w . Z) Z` are `T = F_N u`: `F_N` appears on
//!   both sides. `w' = w'_0 + F_N J^-1 u`, so `F_N = F_N0 + F_N ((J^-1 u) x r_G) . Z`, and since
//!   `(x x r_G) . Z = x . (r_G x Z) = kappa x_1` with `kappa = (h/2) cos(theta) - R sin(theta)`,
//!   `F_N = F_N0 / (1 - kappa (J^-1 u)_1)`. Only rolling friction has `u_1 != 0`, and
//!   `|kappa (J^-1 u)_1| <= k_r |r_G| / J_11 <= k_r / |r_G|` (`J_11 = I_1 + |r_G|^2`), so the
//!   solve is well posed whenever `k_r < |r_G|` ([`Model::check_effects`] asks `k_r <= |r_G|/2`).
//! - The table cannot pull: when the solve gives `F_N < 0` the friction torques vanish (their
//!   `F_N` is `max(F_N, 0)`), which is continuous at `F_N = 0`; the run reports the lift-off.
//! - Power: `T . w = -k_r F_N |w_h| - k_p F_N |w . Z| <= 0`, `F_d . v_C = -k |v_C|^3 <= 0`;
//!   the contact force does no work while rolling, so none of these can raise the energy.

use super::effects::At;
use super::model::{Dynamics, Model};
use nalgebra::Vector3;

/// Angular rate, relative to `sqrt(g / R)`, below which the directions of the friction torques
/// are smoothed (`x / sqrt(|x|^2 + eps^2)` instead of `x / |x|`). Coulomb's law is
/// discontinuous at zero rate and, once friction holds a rate at zero (pivot friction can stop
/// the spin about the normal), the smoothed law is stiff with rate `k F_N / (eps J)`, which an
/// explicit integrator pays for in steps. Real contacts creep below some rate, so a small band
/// is physical; at 1e-4 (2e-3 rad/s for the paper's steel ring) the paper ring's runs over the
/// realistic strengths agree with 1e-6 to 1e-3 in their end time, at a fraction of the cost
/// (pivot friction k/R = 0.03: 16,000 evaluations instead of 130,000).
pub const FRICTION_SMOOTHING: f64 = 1e-4;

impl Model {
    /// The rate below which friction directions are smoothed, in the model's units.
    #[inline]
    pub fn friction_smoothing_rate(&self) -> f64 {
        FRICTION_SMOOTHING * (self.g / self.body.r).sqrt()
    }

    /// Where the effects' terms are evaluated (see [`At`]).
    #[inline]
    pub fn terms_at<'a>(
        &self,
        w: &'a Vector3<f64>,
        z: &'a Vector3<f64>,
        v_c: &'a Vector3<f64>,
        theta: (f64, f64),
        heading: (f64, f64),
    ) -> At<'a> {
        At { w, z, v_c, theta, heading, g: self.g, eps: self.friction_smoothing_rate() }
    }

    /// `u`: the torque of the effects (rolling and pivot friction) per unit normal force, for
    /// angular velocity `w` with table normal `z` (frame components).
    #[inline]
    pub fn contact_torque_per_normal_force(
        &self,
        w: &Vector3<f64>,
        z: &Vector3<f64>,
    ) -> Vector3<f64> {
        let v = Vector3::zeros();
        self.effects.torque_per_normal_force(&self.terms_at(w, z, &v, (z.y, z.z), (0.0, 1.0)))
    }

    /// The rolling dynamics with the losses of this module (see the module doc).
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    pub(super) fn dynamics_with_losses(
        &self,
        mut f: Vector3<f64>,
        tau: Vector3<f64>,
        w: &Vector3<f64>,
        om_x_vc: &Vector3<f64>,
        v_c: &Vector3<f64>,
        (st, ct): (f64, f64),
        heading: (f64, f64),
    ) -> Dynamics {
        let b = &self.body;
        let r_g = b.r_g();
        let z = Vector3::new(0.0, st, ct);
        let g_z = self.g * z;
        let at = self.terms_at(w, &z, v_c, (st, ct), heading);
        let f_d = self.effects.force_at_centre(&at);
        f += r_g.cross(&f_d);
        let u = self.effects.torque_per_normal_force(&at);
        let wd0 = b.j_inv * f + tau;
        let f_n0 = (wd0.cross(&r_g) + om_x_vc + g_z - f_d).dot(&z);
        let ju = b.j_inv * u;
        let kappa = 0.5 * b.h * ct - b.r * st;
        let gain = kappa * ju.x;
        // 1 - gain >= 1/2 by the check on k_r; the friction torques need a pressing contact.
        let f_n = (f_n0 / (1.0 - gain)).max(0.0);
        let omega_dot = wd0 + f_n * ju;
        let force = omega_dot.cross(&r_g) + om_x_vc + g_z - f_d;
        let mut d = Dynamics::from_force(omega_dot, force, st, ct, *v_c);
        d.contact_torque = f_n * u;
        d.drag_force = f_d;
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::model::Effects;
    use crate::physics::paper;

    fn model(e: Effects) -> Model {
        paper::ring_model(paper::C_RING).with_effects(e).unwrap()
    }

    /// A state with every rate non-zero, so no direction is degenerate.
    fn state() -> (f64, Vector3<f64>) {
        (0.9, Vector3::new(0.7, -1.3, 2.1))
    }

    /// Newton-Euler with the reported force, checked directly (eqs. 1-2 with the extra terms):
    /// `I w' + Omega x I w = -r_G x F + J tau + T` and `w' x r_G + Omega x v_C = F - g Z + F_d`.
    fn newton_euler_residual(m: &Model, theta: f64, w: &Vector3<f64>) -> f64 {
        let d = m.dynamics(theta, w);
        let b = &m.body;
        let (st, ct) = theta.sin_cos();
        let om = Vector3::new(w.x, w.z * st / ct, w.z);
        let i_w = b.inertia.component_mul(w);
        let c = m.drag_coefficients(&d.v_c, w);
        let tau =
            Vector3::new(-c[0] * w.x.abs() * w.x, -c[1] * w.y.abs() * w.y, -c[2] * w.z.abs() * w.z);
        let r_g = b.r_g();
        let rot = b.inertia.component_mul(&d.omega_dot) + om.cross(&i_w) + r_g.cross(&d.force)
            - b.j * tau
            - d.contact_torque;
        let z = Vector3::new(0.0, st, ct);
        let trans = d.omega_dot.cross(&r_g) + om.cross(&d.v_c) - d.force + m.g * z - d.drag_force;
        rot.norm() + trans.norm()
    }

    #[test]
    fn the_closed_form_normal_force_satisfies_newton_euler() {
        let (theta, w) = state();
        for e in [
            Effects { rolling_friction: 0.05, ..Default::default() },
            Effects { pivot_friction: 0.05, ..Default::default() },
            Effects { translational_drag: 0.3, ..Default::default() },
            Effects {
                rolling_friction: 0.2,
                pivot_friction: 0.1,
                translational_drag: 0.3,
                ..Default::default()
            },
        ] {
            let m = model(e);
            let d = m.dynamics(theta, &w);
            assert!(d.f_n > 0.0);
            assert!(newton_euler_residual(&m, theta, &w) < 1e-13, "{e:?}");
            // The torque used is the one the reported F_N gives.
            let u =
                m.contact_torque_per_normal_force(&w, &Vector3::new(0.0, theta.sin(), theta.cos()));
            assert!((d.contact_torque - d.f_n * u).norm() < 1e-14, "{e:?}");
        }
    }

    #[test]
    fn friction_torques_have_the_defining_directions() {
        let (theta, w) = state();
        let z = Vector3::new(0.0, theta.sin(), theta.cos());
        let w_h = w - z * w.dot(&z);
        let k = 0.05;
        let d = model(Effects { rolling_friction: k, ..Default::default() }).dynamics(theta, &w);
        // Antiparallel to the rolling part of omega, of size k F_N (to the smoothing,
        // (eps/|w_h|)^2 / 2 ~ 1e-8 here).
        assert!((d.contact_torque + k * d.f_n * w_h.normalize()).norm() < 1e-7 * d.f_n);
        assert!(d.contact_torque.dot(&z).abs() < 1e-15);
        let d = model(Effects { pivot_friction: k, ..Default::default() }).dynamics(theta, &w);
        assert!((d.contact_torque + k * d.f_n * w.dot(&z).signum() * z).norm() < 1e-7 * d.f_n);
        // Spin the other way: the torque turns round.
        let d2 = model(Effects { pivot_friction: k, ..Default::default() }).dynamics(theta, &(-w));
        assert!(d2.contact_torque.dot(&z) * d.contact_torque.dot(&z) < 0.0);
    }

    #[test]
    fn air_drag_opposes_the_velocity_quadratically() {
        let (theta, w) = state();
        let k = 0.3;
        let d = model(Effects { translational_drag: k, ..Default::default() }).dynamics(theta, &w);
        let v = d.v_c;
        assert!((d.drag_force + k * v.norm() * v).norm() < 1e-15);
        let d2 = model(Effects { translational_drag: k, ..Default::default() })
            .dynamics(theta, &(2.0 * w));
        assert!((d2.drag_force.norm() / d.drag_force.norm() - 4.0).abs() < 1e-12);
    }

    #[test]
    fn friction_torques_vanish_when_the_table_would_pull() {
        // A fast precession without spin lifts the ring (F_N < 0 without the torques).
        let theta: f64 = 0.55;
        let w = Vector3::new(0.0, 8.0 * theta.sin(), 8.0 * theta.cos());
        let base = paper::ring_model(paper::C_RING).dynamics(theta, &w);
        assert!(base.f_n < 0.0, "not a lift-off state: F_N = {}", base.f_n);
        let d =
            model(Effects { rolling_friction: 0.05, pivot_friction: 0.05, ..Default::default() })
                .dynamics(theta, &w);
        assert_eq!(d.contact_torque, Vector3::zeros());
        assert!((d.f_n - base.f_n).abs() < 1e-14);
    }

    #[test]
    fn losses_never_supply_power() {
        let m = model(Effects {
            rolling_friction: 0.1,
            pivot_friction: 0.1,
            translational_drag: 0.5,
            ..Default::default()
        });
        for k in 0..200 {
            let x = k as f64;
            let theta = 0.05 + 1.4 * (0.37 * x).sin().abs();
            let w = Vector3::new((1.3 * x).sin(), 3.0 * (0.7 * x).cos(), 2.0 * (0.23 * x).sin());
            let d = m.dynamics(theta, &w);
            assert!(d.contact_torque.dot(&w) <= 0.0);
            assert!(d.drag_force.dot(&d.v_c) <= 0.0);
        }
    }
}
