//! The pure-rolling equations of motion (eqs. 3-5) and the contact force.
//!
//! State `y = [phi, theta, psi, w1, w2, w3, x_C, y_C]`, with `w = omega` in the Resal frame.
//! `J w' = f(w, theta) + T` where `T` collects the torques of the force model: the paper's
//! quadratic drag (eq. 5, `J^-1 T_drag = -C_i |w_i| w_i`) and the optional effects of
//! [`Effects`], the one seam through which extra physics enters.

use super::body::{Body, ParamError, check_finite, check_non_negative, check_positive};
pub use super::effects::Effects;
pub use super::effects::reynolds_drag::ReynoldsDrag;
pub use super::effects::slip::SlipStart;
use super::integrator::System;
use super::trig::sin_cos;
use nalgebra::Vector3;

/// Length of the rolling state vector.
pub const STATE_LEN: usize = 8;
pub type StateVec = [f64; STATE_LEN];

/// Indices into the state vector.
pub mod ix {
    pub const PHI: usize = 0;
    pub const THETA: usize = 1;
    pub const PSI: usize = 2;
    pub const W1: usize = 3;
    pub const W2: usize = 4;
    pub const W3: usize = 5;
    pub const X: usize = 6;
    pub const Y: usize = 7;
}

/// The complete force model of one body on the table.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Model {
    pub body: Body,
    /// Gravity in the model's units.
    pub g: f64,
    /// Rotational drag coefficients `(C1, C2, C3)` of eq. 5 (dimensionless).
    pub c_drag: [f64; 3],
    /// Air's kinematic viscosity in the model's units (for `Re = 2 |v_C| R / nu`).
    pub nu_air: f64,
    pub effects: Effects,
}

/// The parts of eqs. 4-5 shared by every force model (frame components, m = 1).
struct RollingParts {
    r_g: Vector3<f64>,
    v_c: Vector3<f64>,
    om_x_vc: Vector3<f64>,
    /// `f` of eq. 4 with gravity's torque.
    f: Vector3<f64>,
    /// Eq. 5's drag, `J^-1 T_drag`.
    tau: Vector3<f64>,
}

/// Everything eqs. 3-5 give at one state: omega', the contact force and its parts.
#[derive(Clone, Copy, Debug)]
pub struct Dynamics {
    pub omega_dot: Vector3<f64>,
    /// Contact force on the body (per unit mass times m = 1), frame components.
    pub force: Vector3<f64>,
    pub f_n: f64,
    pub f_f: f64,
    pub f_1: f64,
    /// Velocity of the centre of mass, frame components.
    pub v_c: Vector3<f64>,
    /// Torque of rolling and pivot friction on the body (frame components; zero without them).
    pub contact_torque: Vector3<f64>,
    /// Translational air drag on the centre of mass (frame components; zero without it).
    pub drag_force: Vector3<f64>,
}

impl Model {
    pub fn new(body: Body, g: f64, c_drag: [f64; 3], nu_air: f64) -> Result<Model, ParamError> {
        check_positive("gravity g", g)?;
        check_non_negative("drag C1", c_drag[0])?;
        check_non_negative("drag C2", c_drag[1])?;
        check_non_negative("drag C3", c_drag[2])?;
        check_positive("air viscosity nu", nu_air)?;
        Ok(Model { body, g, c_drag, nu_air, effects: Effects::default() })
    }

    /// Sets the effects after checking them against this body (see [`Model::check_effects`]).
    pub fn with_effects(mut self, effects: Effects) -> Result<Model, ParamError> {
        self.effects = effects;
        self.check_effects()?;
        Ok(self)
    }

    /// Checks the effects, including the limits that depend on the body: the closed-form
    /// solve for `F_N` (`losses.rs`) needs the rolling-resistance arm below half of `|r_G|`,
    /// and the sliding contact needs `mu` below the Painleve limit of the body (`slip.rs`).
    pub fn check_effects(&self) -> Result<(), ParamError> {
        self.effects.validate()?;
        let r_g = self.body.r_g().norm();
        if self.effects.rolling_friction > 0.5 * r_g {
            return Err(ParamError {
                name: "rolling_friction",
                value: self.effects.rolling_friction,
                reason: "must be below half the distance from contact to centre of mass (|r_G| / 2)",
            });
        }
        if let Some(mu) = self.effects.slip_mu {
            let limit = super::painleve::mu_limit(&self.body, self.effects.rolling_friction);
            if mu >= limit {
                return Err(ParamError {
                    name: "slip mu",
                    value: mu,
                    reason: super::painleve::PAINLEVE_REASON,
                });
            }
        }
        Ok(())
    }

    /// Reynolds number `2 |v_C| R / nu_air` for a centre-of-mass speed.
    pub fn reynolds(&self, speed_c: f64) -> f64 {
        2.0 * speed_c * self.body.r / self.nu_air
    }

    /// The speed whose Reynolds number scales the drag ([`ReynoldsDrag::rim_share`]), for the
    /// centre's velocity `v_c` and the body's rate `w`.
    #[inline]
    fn reynolds_speed(&self, re: &ReynoldsDrag, v_c: &Vector3<f64>, w: &Vector3<f64>) -> f64 {
        let centre = v_c.norm_squared();
        if re.rim_share == 0.0 {
            return centre.sqrt();
        }
        let rim = w.norm_squared() * self.body.r * self.body.r;
        (centre + re.rim_share * (rim - centre)).max(0.0).sqrt()
    }

    /// The drag coefficients `C_i` at centre velocity `v_c` and rate `w` (eq. 5, scaled with
    /// the Reynolds number when that effect is on).
    #[inline]
    pub fn drag_coefficients(&self, v_c: &Vector3<f64>, w: &Vector3<f64>) -> [f64; 3] {
        let c = self.c_drag;
        match &self.effects.reynolds_drag {
            None => c,
            Some(re) => {
                let k = re.factor(self.reynolds(self.reynolds_speed(re, v_c, w)));
                [c[0] * k, c[1] * k, c[2] * k]
            }
        }
    }

    /// Angular acceleration and contact force at `(theta, w)`, heading `phi = 0` (where the
    /// table is level, as without `table_slope`, the heading does not matter).
    #[inline]
    pub fn dynamics(&self, theta: f64, w: &Vector3<f64>) -> Dynamics {
        self.dynamics_sc(sin_cos(theta), (0.0, 1.0), w)
    }

    /// Angular acceleration and contact force at the rolling state `y`.
    #[inline]
    pub fn dynamics_of(&self, y: &StateVec) -> Dynamics {
        let w = Vector3::new(y[ix::W1], y[ix::W2], y[ix::W3]);
        self.dynamics_sc(sin_cos(y[ix::THETA]), sin_cos(y[ix::PHI]), &w)
    }

    /// [`Model::dynamics`] from `(sin(theta), cos(theta))` and `(sin(phi), cos(phi))`, which the
    /// right-hand side needs too.
    #[inline]
    pub fn dynamics_sc(
        &self,
        (st, ct): (f64, f64),
        heading: (f64, f64),
        w: &Vector3<f64>,
    ) -> Dynamics {
        let p = self.rolling_parts((st, ct), w);
        if !self.effects.has_contact_terms() {
            let omega_dot = self.body.j_inv * p.f + p.tau;
            let force = omega_dot.cross(&p.r_g) + p.om_x_vc + self.g * Vector3::new(0.0, st, ct);
            return Dynamics::from_force(omega_dot, force, st, ct, p.v_c);
        }
        self.dynamics_with_losses(p.f, p.tau, w, &p.om_x_vc, &p.v_c, (st, ct), heading)
    }

    /// `omega'` and `v_C`: what the right-hand side needs, without the contact force that
    /// [`Model::dynamics_sc`] adds.
    #[inline(always)]
    fn omega_dot_sc(
        &self,
        (st, ct): (f64, f64),
        heading: (f64, f64),
        w: &Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        // The test first: the fast path then keeps the parts in registers.
        if !self.effects.has_contact_terms() {
            let p = self.rolling_parts((st, ct), w);
            return (self.body.j_inv * p.f + p.tau, p.v_c);
        }
        let p = self.rolling_parts((st, ct), w);
        let d = self.dynamics_with_losses(p.f, p.tau, w, &p.om_x_vc, &p.v_c, (st, ct), heading);
        (d.omega_dot, d.v_c)
    }

    /// The terms of eqs. 4-5 that every force model shares: `J omega' = f + J tau`.
    #[inline(always)]
    fn rolling_parts(&self, (st, ct): (f64, f64), w: &Vector3<f64>) -> RollingParts {
        let b = &self.body;
        let tan = st / ct;
        let (a, r) = (0.5 * b.h, b.r);
        let (w1, w2, w3) = (w.x, w.y, w.z);
        // Frame rate Omega = omega - psi' e2 = (w1, w3 tan(theta), w3).
        let om = Vector3::new(w1, w3 * tan, w3);
        let l_g = Vector3::new(b.inertia.x * w1, b.inertia.y * w2, b.inertia.z * w3);
        let r_g = Vector3::new(0.0, a, r);
        // Rolling: v_C = omega x r_G.
        let v_c = Vector3::new(w2 * r - w3 * a, -w1 * r, w1 * a);
        let om_x_vc = om.cross(&v_c);
        // f of eq. 4 (m = 1).
        let mut f = -om.cross(&l_g) - r_g.cross(&om_x_vc);
        f.x += self.g * (r * st - a * ct);
        let c = self.drag_coefficients(&v_c, w);
        // Eq. 5: J^-1 T_drag = tau, tau_i = -C_i |w_i| w_i.
        let tau = Vector3::new(-c[0] * w1.abs() * w1, -c[1] * w2.abs() * w2, -c[2] * w3.abs() * w3);
        RollingParts { r_g, v_c, om_x_vc, f, tau }
    }

    /// Total energy `1/2 w.I w + 1/2 |v_C|^2 + g z_C` (m = 1).
    pub fn energy(&self, y: &StateVec) -> f64 {
        let b = &self.body;
        let (st, ct) = sin_cos(y[ix::THETA]);
        self.kinetic_energy(y) + self.g * (0.5 * b.h * st + b.r * ct)
    }

    /// Kinetic energy only (no trigonometry: the run tests it after every step).
    pub fn kinetic_energy(&self, y: &StateVec) -> f64 {
        let b = &self.body;
        let w = Vector3::new(y[ix::W1], y[ix::W2], y[ix::W3]);
        let v_c = Vector3::new(w.y * b.r - w.z * b.h / 2.0, -w.x * b.r, w.x * b.h / 2.0);
        let rot =
            0.5 * (b.inertia.x * w.x * w.x + b.inertia.y * w.y * w.y + b.inertia.z * w.z * w.z);
        rot + 0.5 * v_c.norm_squared()
    }
}

impl Dynamics {
    #[inline]
    pub(crate) fn from_force(
        omega_dot: Vector3<f64>,
        force: Vector3<f64>,
        st: f64,
        ct: f64,
        v_c: Vector3<f64>,
    ) -> Dynamics {
        Dynamics {
            omega_dot,
            force,
            f_n: force.y * st + force.z * ct,
            f_f: force.y * ct - force.z * st,
            f_1: force.x,
            v_c,
            contact_torque: Vector3::zeros(),
            drag_force: Vector3::zeros(),
        }
    }

    /// `sqrt(F_1^2 + F_f^2) / F_N`: the friction coefficient that rolling needs.
    pub fn friction_ratio(&self) -> f64 {
        (self.f_1 * self.f_1 + self.f_f * self.f_f).sqrt() / self.f_n
    }
}

impl System<STATE_LEN> for Model {
    #[inline(always)]
    fn rhs(&self, _t: f64, y: &StateVec, dy: &mut StateVec) {
        let w = Vector3::new(y[ix::W1], y[ix::W2], y[ix::W3]);
        let (st, ct) = sin_cos(y[ix::THETA]);
        let (sp, cp) = sin_cos(y[ix::PHI]);
        let (omega_dot, v_c) = self.omega_dot_sc((st, ct), (sp, cp), &w);
        // Euler-angle kinematics (PHYSICS.md inverse): theta' = w1, phi' = w3/cos, psi' = w2 - w3 tan.
        dy[ix::PHI] = w.z / ct;
        dy[ix::THETA] = w.x;
        dy[ix::PSI] = w.y - w.z * st / ct;
        dy[ix::W1] = omega_dot.x;
        dy[ix::W2] = omega_dot.y;
        dy[ix::W3] = omega_dot.z;
        // v_C rotated to the table: e1 = (cos phi, sin phi), horizontal part of e2, e3 along E2'.
        let along_e2h = v_c.y * ct - v_c.z * st;
        dy[ix::X] = v_c.x * cp - along_e2h * sp;
        dy[ix::Y] = v_c.x * sp + along_e2h * cp;
    }
}

/// The state at the start of a run, in the model's units.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Initial {
    pub phi: f64,
    pub theta: f64,
    pub psi: f64,
    pub theta_dot: f64,
    pub phi_dot: f64,
    pub psi_dot: f64,
    pub x_c: f64,
    pub y_c: f64,
}

impl Initial {
    /// The paper's start (PHYSICS.md): the first inner turning point.
    pub fn paper() -> Initial {
        Initial {
            phi: -0.38,
            theta: 0.55,
            psi: 0.0,
            theta_dot: 0.0,
            phi_dot: 4.5,
            psi_dot: 0.0,
            x_c: 0.0,
            y_c: 0.0,
        }
    }

    /// Checks finiteness and that `theta` is in `[0, pi/2)`, where the model holds.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_finite("phi0", self.phi)?;
        check_finite("theta0", self.theta)?;
        check_finite("psi0", self.psi)?;
        check_finite("thetadot0", self.theta_dot)?;
        check_finite("phidot0", self.phi_dot)?;
        check_finite("psidot0", self.psi_dot)?;
        check_finite("x0", self.x_c)?;
        check_finite("y0", self.y_c)?;
        if !(0.0..std::f64::consts::FRAC_PI_2).contains(&self.theta) {
            return Err(ParamError {
                name: "theta0",
                value: self.theta,
                reason: "must lie in [0, pi/2) rad (0 = upright, pi/2 = flat)",
            });
        }
        Ok(())
    }

    /// The state vector: `w = (theta', phi' sin(theta) + psi', phi' cos(theta))`.
    pub fn to_state(&self) -> StateVec {
        let (st, ct) = sin_cos(self.theta);
        [
            self.phi,
            self.theta,
            self.psi,
            self.theta_dot,
            self.phi_dot * st + self.psi_dot,
            self.phi_dot * ct,
            self.x_c,
            self.y_c,
        ]
    }

    /// Reads the angles and rates back from a state vector.
    pub fn from_state(y: &StateVec) -> Initial {
        let (st, ct) = sin_cos(y[ix::THETA]);
        Initial {
            phi: y[ix::PHI],
            theta: y[ix::THETA],
            psi: y[ix::PSI],
            theta_dot: y[ix::W1],
            phi_dot: y[ix::W3] / ct,
            psi_dot: y[ix::W2] - y[ix::W3] * st / ct,
            x_c: y[ix::X],
            y_c: y[ix::Y],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's ring (`paper.rs`, which builds on this file) with drag `c`.
    fn ring(c: [f64; 3]) -> Model {
        Model::new(Body::paper_ring(), 1.025 * 4.5 * 4.5 / 20.2, c, 1.0e-3).expect("valid")
    }

    /// A small deterministic generator (no dependency): uniform in [lo, hi).
    fn uniform(seed: &mut u64, lo: f64, hi: f64) -> f64 {
        *seed =
            seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        lo + (hi - lo) * ((*seed >> 11) as f64 / (1u64 << 53) as f64)
    }

    #[test]
    fn the_right_hand_side_gives_the_dynamics_numbers_bit_for_bit() {
        let mut reynolds = ring([0.03, 0.063, 0.085]);
        reynolds.effects.reynolds_drag =
            Some(ReynoldsDrag { re_ref: 3.0e3, exponent: 0.5, max_factor: 4.0, rim_share: 0.3 });
        let mut rolling = ring([0.03, 0.063, 0.085]);
        rolling.effects.rolling_friction = 0.01;
        let mut seed = 7;
        let models = [ring([0.03, 0.063, 0.085]), ring([0.2, 0.063, 0.2])];
        for model in models.into_iter().chain([reynolds, rolling]) {
            for _ in 0..20_000 {
                let mut y = [0.0; STATE_LEN];
                for v in &mut y {
                    *v = uniform(&mut seed, -6.0, 6.0);
                }
                y[ix::THETA] = uniform(&mut seed, -0.2, 1.56);
                let mut dy = [0.0; STATE_LEN];
                model.rhs(0.0, &y, &mut dy);
                let d = model.dynamics_of(&y);
                for (i, v) in [d.omega_dot.x, d.omega_dot.y, d.omega_dot.z].iter().enumerate() {
                    assert_eq!(dy[ix::W1 + i].to_bits(), v.to_bits(), "w{} at {y:?}", i + 1);
                }
            }
        }
    }
}
