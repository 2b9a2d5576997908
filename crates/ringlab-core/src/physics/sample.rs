//! One sample of a run: the state and everything derived from it at one time (positions of
//! A and P, the contact force, energy, Reynolds number, and whether the contact slides).

use super::body::Body;
use super::model::{Dynamics, Model, StateVec, ix};
use super::slip::{SlideVec, SlidingModel, sliding_energy};
use super::trig::sin_cos;
use nalgebra::Vector3;

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
    /// Whether the contact slides (only with the slip effect).
    pub sliding: bool,
    /// Speed of the contact point over the table, `|v_C - omega x r_G|` (0 while rolling).
    pub slip_speed: f64,
}

/// Point A, the centre of the top edge, on the table's axes: `r_A = r_C + (h/2) e2`.
pub fn top_centre(body: &Body, y: &StateVec) -> (f64, f64) {
    top_centre_sc(body, y, sin_cos(y[ix::THETA]), sin_cos(y[ix::PHI]))
}

/// [`top_centre`] from the sines and cosines of `theta` and `phi`.
#[inline]
fn top_centre_sc(
    body: &Body,
    y: &StateVec,
    (_, ct): (f64, f64),
    (sp, cp): (f64, f64),
) -> (f64, f64) {
    // Horizontal part of e2 is cos(theta) E2', E2' = (-sin phi, cos phi).
    let a = 0.5 * body.h;
    (y[ix::X] - a * ct * sp, y[ix::Y] + a * ct * cp)
}

impl Sample {
    /// A sample of a rolling state.
    pub fn new(model: &Model, t: f64, y: &StateVec) -> Sample {
        let d = model.dynamics_of(y);
        Sample::with_dynamics(model, t, y, &d, model.energy(y))
    }

    /// A sample of where the body is and nothing more: its state, the top centre A and the
    /// centre's height; the forces, energy, speeds and Reynolds number are NaN. What a fit's
    /// prediction projects (`analysis::fit::shooting`), without a force evaluation per frame.
    pub fn position(model: &Model, t: f64, y: &StateVec, sliding: bool) -> Sample {
        let b = &model.body;
        let (st, ct) = sin_cos(y[ix::THETA]);
        let (x_a, y_a) = top_centre_sc(b, y, (st, ct), sin_cos(y[ix::PHI]));
        Sample {
            t,
            y: *y,
            z_c: 0.5 * b.h * st + b.r * ct,
            x_a,
            y_a,
            x_p: f64::NAN,
            y_p: f64::NAN,
            vx_a: f64::NAN,
            vy_a: f64::NAN,
            v_p: f64::NAN,
            f_1: f64::NAN,
            f_f: f64::NAN,
            f_n: f64::NAN,
            energy: f64::NAN,
            speed_c: f64::NAN,
            reynolds: f64::NAN,
            sliding,
            slip_speed: f64::NAN,
        }
    }

    /// A sample of a sliding state (the first eight numbers of `y` are as while rolling).
    pub fn sliding(model: &SlidingModel, t: f64, y: &SlideVec) -> Sample {
        let d = model.dynamics(y);
        let mut y8 = [0.0; super::model::STATE_LEN];
        y8.copy_from_slice(&y[..super::model::STATE_LEN]);
        let mut s = Sample::with_dynamics(
            &model.model,
            t,
            &y8,
            &d.dynamics,
            sliding_energy(&model.model, y),
        );
        s.sliding = true;
        s.slip_speed = d.v_slip[0].hypot(d.v_slip[1]);
        s
    }

    fn with_dynamics(model: &Model, t: f64, y: &StateVec, d: &Dynamics, energy: f64) -> Sample {
        let b = &model.body;
        let (st, ct) = sin_cos(y[ix::THETA]);
        let (sp, cp) = sin_cos(y[ix::PHI]);
        let a = 0.5 * b.h;
        let (x_a, y_a) = top_centre_sc(b, y, (st, ct), (sp, cp));
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
            energy,
            speed_c,
            reynolds: model.reynolds(speed_c),
            sliding: false,
            slip_speed: 0.0,
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
