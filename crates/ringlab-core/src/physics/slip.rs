//! The sliding contact: Coulomb friction at the contact point P while it slips over the table.
//!
//! The paper assumes pure rolling and names slippage at the cusps as one suspect for the drift
//! between model and experiment (section III); this is that suspect as a model. While the
//! contact slides, the horizontal velocity of the centre of mass is state of its own (the
//! sliding state adds `vx_C, vy_C`), the contact force is `F_N (Z - mu s)` with one `mu` for
//! static and kinetic friction, and the normal force comes in closed form from P staying on the
//! table. A table that would have to pull exerts nothing (the run reports the lift-off).
//!
//! That closed form fails for large `mu` (Painleve's paradox): [`painleve_mu_limit`] gives the
//! bound and [`Model::check_effects`] refuses larger `mu`. The switches between rolling and
//! sliding are events of the run (`run/switch.rs`); the slip's reference direction is set by
//! events too, so the equations never depend on the steps taken
//! ([`SlidingModel::friction_direction`]).
//!
//! The equations, the energy balance and the transition rules are in `docs/slip.md`.

use super::body::Body;
use super::integrator::System;
use super::model::{Dynamics, Model, STATE_LEN, StateVec, ix};
use super::trig::sin_cos;
use nalgebra::{Matrix3, Vector3};

/// Length of the sliding state vector.
pub const SLIDE_LEN: usize = 10;
pub type SlideVec = [f64; SLIDE_LEN];
/// Indices of the horizontal velocity of C in the sliding state (the rest as in [`ix`]).
pub const VX: usize = 8;
pub const VY: usize = 9;

/// The creep speed `eps`, relative to `sqrt(g R)`: below it the friction direction is held
/// near a reference direction instead of following the slip (see
/// [`SlidingModel::friction_direction`]). Coulomb's direction `v_s/|v_s|` turns at a rate
/// `~ mu F_N / |v_s|` as the slip speed falls, a stiffness that an explicit integrator pays for
/// with steps while the slip is small (at its onset it grows from zero); below `eps` the rate
/// is `~ mu F_N / eps`. Real contacts creep below some slip speed: 3e-4 is 0.14 mm/s for the
/// paper's steel ring, under a thousandth of its rolling speed. Against 3e-5: the paper ring's
/// runs for mu 0.1, 0.3, 0.6, 1 put A at the same places to 3e-4 mean radii (6 um) all the
/// way; a ring that slides a little at every cusp of a long retrograde spiral (the diagnosis's
/// fits to slipping recordings: hundreds of slides below 1e-4) moves by 0.0017 radii (0.12 px
/// at the paper's scale, under its pixel noise) and takes 16,000 to 26,000 steps instead of
/// 34,000 to 43,000 (1e-3: 0.0063 radii, 0.4 px). It also gives the direction at the onset
/// of sliding, where `v_s = 0`.
pub const SLIP_DIRECTION_BLEND: f64 = 3e-4;

/// Slip speeds, in units of the creep speed, above which the reference direction no longer
/// enters the friction direction (`exp(-40) = 4e-18`).
pub const REFERENCE_FREE_SPEEDS: f64 = 40.0;

pub use super::painleve::PAINLEVE_REASON;

/// The largest `mu` for which the sliding solve of `model` stays well posed (see
/// [`super::painleve`]).
pub fn painleve_mu_limit(model: &Model) -> f64 {
    super::painleve::mu_limit(&model.body, model.effects.rolling_friction)
}

/// The right-hand side of the sliding contact. `s_ref` is the reference slip direction
/// (table components, unit length): the run sets it to the slip direction at the start of
/// each step; the stick event is the zero of `v_s . s_ref`.
#[derive(Clone, Debug, PartialEq)]
pub struct SlidingModel {
    pub model: Model,
    pub mu: f64,
    s_ref: [f64; 2],
}

/// The sliding dynamics at one state.
#[derive(Clone, Copy, Debug)]
pub struct SlideDynamics {
    /// `omega'`, the contact force `F` and its parts, `v_C` (frame), the friction torques
    /// and the air drag, as while rolling.
    pub dynamics: Dynamics,
    /// Horizontal acceleration of C, table components.
    pub accel: [f64; 2],
    /// Slip velocity of P, table components.
    pub v_slip: [f64; 2],
}

impl SlidingModel {
    /// `s_ref` is normalised; a zero vector is refused by using `e_x`.
    pub fn new(model: Model, mu: f64, s_ref: [f64; 2]) -> SlidingModel {
        let mut m = SlidingModel { model, mu, s_ref: [1.0, 0.0] };
        m.set_reference(s_ref);
        m
    }

    pub fn reference(&self) -> [f64; 2] {
        self.s_ref
    }

    pub fn set_reference(&mut self, s: [f64; 2]) {
        let n = s[0].hypot(s[1]);
        if n > 0.0 && n.is_finite() {
            self.s_ref = [s[0] / n, s[1] / n];
        }
    }

    /// The creep speed `eps` in the model's units.
    pub fn creep_speed(&self) -> f64 {
        SLIP_DIRECTION_BLEND * (self.model.g * self.model.body.r).sqrt()
    }

    /// Whether the reference direction may follow the slip: once the slip is so far above
    /// the creep speed that the reference no longer enters the friction direction (its weight
    /// `exp(-|v_s|/eps)` is below 1e-17), changing it leaves the right-hand side as it is, so
    /// the equations solved do not depend on the steps taken.
    pub fn may_update_reference(&self, v_s: [f64; 2]) -> bool {
        v_s[0].hypot(v_s[1]) > REFERENCE_FREE_SPEEDS * self.creep_speed()
    }

    /// The slip direction the friction uses. With the slip `c s_ref + d s_perp` in the basis
    /// of the reference direction, it is the direction of
    /// `(|c| + eps exp(-|v_s|/eps)) s_ref + d s_perp`:
    /// - at `v_s = 0` (the onset) it is `s_ref`; for slips below the creep speed `eps` it turns
    ///   from `s_ref` towards the slip's own direction (see [`SLIP_DIRECTION_BLEND`]);
    /// - above about 40 `eps` it is `v_s/|v_s|` to rounding whenever `c > 0`, whatever
    ///   `s_ref` is (the run keeps `c > 0` by updating `s_ref` then);
    /// - past `c = 0` it mirrors the slip in the line normal to `s_ref`, so the friction
    ///   carries on smoothly through the stick: the integrator can step across it and the run
    ///   finds the stick as the root of `c`.
    pub fn friction_direction(&self, v_s: [f64; 2]) -> [f64; 2] {
        let eps = self.creep_speed();
        let [sx, sy] = self.s_ref;
        let c = v_s[0] * sx + v_s[1] * sy;
        let d = -v_s[0] * sy + v_s[1] * sx;
        // Plain square roots, not `hypot`: these speeds are far from overflow, and `hypot`
        // cost as much as the rest of the sliding right-hand side's arithmetic.
        let along = c.abs() + eps * (-(c * c + d * d).sqrt() / eps).exp();
        let n = (along * along + d * d).sqrt();
        let (p, q) = (along / n, d / n);
        [p * sx - q * sy, p * sy + q * sx]
    }

    /// Everything the sliding equations give at `y` (see the module doc).
    pub fn dynamics(&self, y: &SlideVec) -> SlideDynamics {
        self.dynamics_sc(y, sin_cos(y[ix::THETA]), sin_cos(y[ix::PHI]))
    }

    /// [`SlidingModel::dynamics`] with the sines and cosines of theta and phi given (the
    /// right-hand side needs them too: they are a third of its cost).
    fn dynamics_sc(
        &self,
        y: &SlideVec,
        (st, ct): (f64, f64),
        (sp, cp): (f64, f64),
    ) -> SlideDynamics {
        let m = &self.model;
        let b = &m.body;
        let (a, r) = (0.5 * b.h, b.r);
        let w = Vector3::new(y[ix::W1], y[ix::W2], y[ix::W3]);
        let kappa = a * ct - r * st;
        let z_c = a * st + r * ct;
        // v_C in the frame: horizontal part along e1 and E2' = cos e2 - sin e3, plus z_C' Z.
        let v1 = y[VX] * cp + y[VY] * sp;
        let v2h = -y[VX] * sp + y[VY] * cp;
        let vz = kappa * w.x;
        let v_c = Vector3::new(v1, v2h * ct + vz * st, -v2h * st + vz * ct);
        let v_slip = slip_table(b, y, (st, ct), (sp, cp));
        let [dx, dy] = self.friction_direction(v_slip);
        let (d1, d2) = (dx * cp + dy * sp, -dx * sp + dy * cp);
        let s_hat = Vector3::new(d1, d2 * ct, -d2 * st);

        let z = Vector3::new(0.0, st, ct);
        let om = Vector3::new(w.x, w.z * st / ct, w.z);
        let i_w = b.inertia.component_mul(&w);
        let c = m.drag_coefficients(&v_c, &w);
        let tau =
            Vector3::new(-c[0] * w.x.abs() * w.x, -c[1] * w.y.abs() * w.y, -c[2] * w.z.abs() * w.z);
        let bv = -om.cross(&i_w) + b.j * tau;
        let at = m.terms_at(&w, &z, &v_c, (st, ct), (sp, cp));
        let f_d = m.effects.force_at_centre(&at);
        let u = m.effects.torque_per_normal_force(&at);
        let r_g = b.r_g();
        let i1 = b.inertia.x;
        let rhs_n = m.g - f_d.dot(&z) + kappa * bv.x / i1 - z_c * w.x * w.x;
        let solve = |mu: f64, u: Vector3<f64>| {
            let n = z - mu * s_hat;
            let mv = u - r_g.cross(&n);
            (rhs_n / (1.0 - kappa * mv.x / i1), n, mv, u)
        };
        let (mut f_n, mut n, mut mv, mut u_on) = solve(self.mu, u);
        if f_n < 0.0 {
            (f_n, n, mv, u_on) = solve(0.0, Vector3::zeros());
        }
        let omega_dot = (bv + f_n * mv).component_div(&b.inertia);
        let force = f_n * n;
        // Horizontal acceleration of C: friction and the horizontal part of the air drag.
        let h = force + f_d;
        let (h1, h2) = (h.x, h.y * ct - h.z * st);
        let accel = [h1 * cp - h2 * sp, h1 * sp + h2 * cp];
        let mut dynamics = Dynamics::from_force(omega_dot, force, st, ct, v_c);
        dynamics.contact_torque = f_n.max(0.0) * u_on;
        dynamics.drag_force = f_d;
        SlideDynamics { dynamics, accel, v_slip }
    }
}

impl System<SLIDE_LEN> for SlidingModel {
    fn rhs(&self, _t: f64, y: &SlideVec, dy: &mut SlideVec) {
        let (st, ct) = sin_cos(y[ix::THETA]);
        let d = self.dynamics_sc(y, (st, ct), sin_cos(y[ix::PHI]));
        dy[ix::PHI] = y[ix::W3] / ct;
        dy[ix::THETA] = y[ix::W1];
        dy[ix::PSI] = y[ix::W2] - y[ix::W3] * st / ct;
        dy[ix::W1] = d.dynamics.omega_dot.x;
        dy[ix::W2] = d.dynamics.omega_dot.y;
        dy[ix::W3] = d.dynamics.omega_dot.z;
        dy[ix::X] = y[VX];
        dy[ix::Y] = y[VY];
        dy[VX] = d.accel[0];
        dy[VY] = d.accel[1];
    }
}

/// Horizontal velocity of C while rolling (`omega x r_G`), table components: the `e1` part
/// `w2 R - w3 h/2` and the `E2'` part `-w1 z_C`.
fn rolling_velocity_table(
    b: &Body,
    y: &[f64],
    (st, ct): (f64, f64),
    (sp, cp): (f64, f64),
) -> [f64; 2] {
    let a = 0.5 * b.h;
    let along_e1 = y[ix::W2] * b.r - y[ix::W3] * a;
    let along_e2h = -y[ix::W1] * (a * st + b.r * ct);
    [along_e1 * cp - along_e2h * sp, along_e1 * sp + along_e2h * cp]
}

fn slip_table(b: &Body, y: &SlideVec, sc_theta: (f64, f64), sc_phi: (f64, f64)) -> [f64; 2] {
    let v = rolling_velocity_table(b, y, sc_theta, sc_phi);
    [y[VX] - v[0], y[VY] - v[1]]
}

/// Slip velocity of P at a sliding state, table components.
pub fn slip_velocity(model: &Model, y: &SlideVec) -> [f64; 2] {
    slip_table(&model.body, y, sin_cos(y[ix::THETA]), sin_cos(y[ix::PHI]))
}

/// The sliding state of a rolling state (zero slip).
pub fn sliding_state(model: &Model, y: &StateVec) -> SlideVec {
    let v = rolling_velocity_table(&model.body, y, sin_cos(y[ix::THETA]), sin_cos(y[ix::PHI]));
    let mut out = [0.0; SLIDE_LEN];
    out[..STATE_LEN].copy_from_slice(y);
    out[VX] = v[0];
    out[VY] = v[1];
    out
}

/// Energy `1/2 w.I w + 1/2 |v_C|^2 + g z_C` of a sliding state (m = 1).
pub fn sliding_energy(model: &Model, y: &SlideVec) -> f64 {
    let b = &model.body;
    let (st, ct) = sin_cos(y[ix::THETA]);
    let a = 0.5 * b.h;
    let w = Vector3::new(y[ix::W1], y[ix::W2], y[ix::W3]);
    let vz = (a * ct - b.r * st) * w.x;
    let rot = 0.5 * w.dot(&b.inertia.component_mul(&w));
    rot + 0.5 * (y[VX] * y[VX] + y[VY] * y[VY] + vz * vz) + model.g * (a * st + b.r * ct)
}

/// Sticking: the rolling state after a plastic impulse `L` at P that brings P to rest.
/// `dv_C = L`, `dw = I^-1 (-r_G x L)`, so `dv_P = K L` with `K = 1 + [r_G]x^T I^-1 [r_G]x`
/// (symmetric positive definite) and `L = -K^-1 v_s`. The kinetic energy falls by
/// `1/2 v_s . K^-1 v_s >= 0`. Returns the rolling state and that loss.
pub fn stick(model: &Model, y: &SlideVec) -> (StateVec, f64) {
    let b = &model.body;
    let (st, ct) = sin_cos(y[ix::THETA]);
    let (sp, cp) = sin_cos(y[ix::PHI]);
    let v = slip_table(b, y, (st, ct), (sp, cp));
    let (s1, s2) = (v[0] * cp + v[1] * sp, -v[0] * sp + v[1] * cp);
    let v_s = Vector3::new(s1, s2 * ct, -s2 * st);
    let r_g = b.r_g();
    let rx = r_g.cross_matrix();
    let i_inv = Matrix3::from_diagonal(&b.inertia.map(|i| 1.0 / i));
    let k = Matrix3::identity() + rx.transpose() * i_inv * rx;
    let mut out = [0.0; STATE_LEN];
    out.copy_from_slice(&y[..STATE_LEN]);
    // K is symmetric positive definite for any body, so the solve cannot fail; keep the
    // state unchanged if rounding ever says otherwise.
    let Some(l) = k.cholesky().map(|c| -c.solve(&v_s)) else {
        return (out, 0.0);
    };
    let dw = i_inv * (-r_g.cross(&l));
    out[ix::W1] += dw.x;
    out[ix::W2] += dw.y;
    out[ix::W3] += dw.z;
    (out, -0.5 * v_s.dot(&l))
}

/// Horizontal friction that rolling needs at a rolling state, table components, with `F_N`.
pub fn rolling_friction_demand(model: &Model, y: &StateVec) -> ([f64; 2], f64) {
    let d = model.dynamics_of(y);
    let (sp, cp) = sin_cos(y[ix::PHI]);
    ([d.f_1 * cp - d.f_f * sp, d.f_1 * sp + d.f_f * cp], d.f_n)
}

/// `mu F_N - |F_t|`: how much friction the table has to spare while rolling (negative: the
/// contact slides).
pub fn stick_margin(model: &Model, mu: f64, y: &StateVec) -> f64 {
    let (f, f_n) = rolling_friction_demand(model, y);
    mu * f_n - f[0].hypot(f[1])
}

/// The slip direction at the onset of sliding from a rolling state: opposite to the friction
/// rolling needs. (Friction saturates at `mu F_N` along the demand; the self-consistent slip
/// direction tends to this as the excess demand goes to zero.) Without any demand (a contact
/// that lifts off) the direction does not act on the motion; `e1` is used.
pub fn onset_direction(model: &Model, y: &StateVec) -> [f64; 2] {
    let (f, _) = rolling_friction_demand(model, y);
    let n = f[0].hypot(f[1]);
    if n > 0.0 && n.is_finite() {
        [-f[0] / n, -f[1] / n]
    } else {
        let (sp, cp) = sin_cos(y[ix::PHI]);
        [cp, sp]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::model::Effects;
    use crate::physics::paper;

    fn ring(mu: f64) -> Model {
        paper::ring_model(paper::C_RING)
            .with_effects(Effects { slip_mu: Some(mu), ..Default::default() })
            .unwrap()
    }

    fn some_sliding_state() -> SlideVec {
        [-0.3, 0.8, 0.2, 0.4, -1.1, 2.3, 0.1, -0.2, 0.9, -0.4]
    }

    #[test]
    fn sliding_force_obeys_newton_euler_and_coulomb() {
        let m = ring(0.3);
        let y = some_sliding_state();
        let sm = SlidingModel::new(m.clone(), 0.3, slip_velocity(&m, &y));
        let d = sm.dynamics(&y);
        let dd = &d.dynamics;
        let b = &m.body;
        assert!(dd.f_n > 0.0);
        // Coulomb: the friction has size mu F_N and opposes the slip.
        let (sp, cp) = y[ix::PHI].sin_cos();
        let ft = [dd.f_1 * cp - dd.f_f * sp, dd.f_1 * sp + dd.f_f * cp];
        let vs = slip_velocity(&m, &y);
        let vn = vs[0].hypot(vs[1]);
        assert!(
            (ft[0] + 0.3 * dd.f_n * vs[0] / vn).abs() < 1e-9
                && (ft[1] + 0.3 * dd.f_n * vs[1] / vn).abs() < 1e-9
        );
        // Eq. 1 about C.
        let (st, ct) = y[ix::THETA].sin_cos();
        let w = Vector3::new(y[3], y[4], y[5]);
        let om = Vector3::new(w.x, w.z * st / ct, w.z);
        let c = m.drag_coefficients(&dd.v_c, &w);
        let tau =
            Vector3::new(-c[0] * w.x.abs() * w.x, -c[1] * w.y.abs() * w.y, -c[2] * w.z.abs() * w.z);
        let rot = b.inertia.component_mul(&dd.omega_dot)
            + om.cross(&b.inertia.component_mul(&w))
            + b.r_g().cross(&dd.force)
            - b.j * tau;
        assert!(rot.norm() < 1e-13, "{rot}");
        // Vertical: F_N - g = z_C'' by a finite difference of z_C' = kappa w1 along the motion.
        let mut dy = [0.0; SLIDE_LEN];
        sm.rhs(0.0, &y, &mut dy);
        let h = 1e-6;
        let zdot = |k: f64| {
            let th = y[1] + k * h * dy[1];
            let w1 = y[3] + k * h * dy[3];
            (0.5 * b.h * th.cos() - b.r * th.sin()) * w1
        };
        let z_dd = (zdot(1.0) - zdot(-1.0)) / (2.0 * h);
        assert!((dd.f_n - m.g - z_dd).abs() < 1e-7, "F_N {} vs g + z'' {}", dd.f_n, m.g + z_dd);
    }

    #[test]
    fn sliding_energy_falls_at_the_friction_power() {
        let m = ring(0.3);
        let y = some_sliding_state();
        let mut sm = SlidingModel::new(m.clone(), 0.3, slip_velocity(&m, &y));
        // Without drag the only loss is the friction's power -mu F_N |v_s|.
        sm.model.c_drag = [0.0; 3];
        let mut dy = [0.0; SLIDE_LEN];
        sm.rhs(0.0, &y, &mut dy);
        let h = 1e-6;
        let e = |k: f64| {
            let mut z = y;
            for i in 0..SLIDE_LEN {
                z[i] += k * h * dy[i];
            }
            sliding_energy(&sm.model, &z)
        };
        let de = (e(1.0) - e(-1.0)) / (2.0 * h);
        let d = sm.dynamics(&y);
        let vs = d.v_slip;
        let expected = -0.3 * d.dynamics.f_n * vs[0].hypot(vs[1]);
        assert!((de - expected).abs() < 1e-6, "dE/dt {de} vs {expected}");
    }

    #[test]
    fn with_zero_slip_the_sliding_and_rolling_dynamics_agree_at_the_limit_of_friction() {
        // At the onset the friction rolling needs equals mu F_N; sliding with the onset
        // direction gives the same accelerations.
        let m0 = paper::ring_model(paper::C_RING);
        let th: f64 = 0.8;
        let y8 = [0.3, th, 0.0, 0.3, 4.5 * th.sin() - 3.0, 4.5 * th.cos(), 0.0, 0.0];
        let (f, f_n) = rolling_friction_demand(&m0, &y8);
        let mu = f[0].hypot(f[1]) / f_n;
        let m =
            m0.clone().with_effects(Effects { slip_mu: Some(mu), ..Default::default() }).unwrap();
        let roll = m.dynamics(y8[1], &Vector3::new(y8[3], y8[4], y8[5]));
        let sm = SlidingModel::new(m.clone(), mu, onset_direction(&m, &y8));
        let slide = sm.dynamics(&sliding_state(&m, &y8));
        assert!(
            (roll.omega_dot - slide.dynamics.omega_dot).norm() < 1e-8,
            "{} vs {}",
            roll.omega_dot,
            slide.dynamics.omega_dot
        );
        assert!((roll.force - slide.dynamics.force).norm() < 1e-8);
    }

    #[test]
    fn sticking_removes_the_slip_and_never_adds_energy() {
        let m = ring(0.3);
        let y = some_sliding_state();
        let (y8, loss) = stick(&m, &y);
        assert!(loss > 0.0);
        let e_before = sliding_energy(&m, &y);
        let e_after = m.energy(&y8);
        assert!((e_before - e_after - loss).abs() < 1e-12, "{e_before} - {e_after} != {loss}");
        let back = sliding_state(&m, &y8);
        let vs = slip_velocity(&m, &back);
        assert!(vs[0].hypot(vs[1]) < 1e-15);
        // The impulse acts at P, so the angular momentum about P, `I w + r_G x v_C` (frame
        // components), is the same before and after.
        let l_p = |w: Vector3<f64>, v_c: Vector3<f64>| {
            m.body.inertia.component_mul(&w) + m.body.r_g().cross(&v_c)
        };
        let sm = SlidingModel::new(m.clone(), 0.3, [1.0, 0.0]);
        let before = l_p(Vector3::new(y[3], y[4], y[5]), sm.dynamics(&y).dynamics.v_c);
        let after = l_p(Vector3::new(y8[3], y8[4], y8[5]), sm.dynamics(&back).dynamics.v_c);
        assert!((before - after).norm() < 1e-14, "{before} vs {after}");
    }

    #[test]
    fn painleve_limit_is_far_above_real_friction() {
        let m = paper::ring_model(paper::C_RING);
        let lim = painleve_mu_limit(&m);
        assert!(lim > 1.0 && lim < 2.0, "{lim}");
        assert!(
            m.clone()
                .with_effects(Effects { slip_mu: Some(lim * 1.01), ..Default::default() })
                .is_err()
        );
    }
}
