//! `rolling_friction`: rolling resistance, a torque `-k F_N w_h / |w_h|` against the horizontal
//! (rolling) part `w_h` of omega; `k` is a length (the forward shift of the normal force in the
//! contact). Strength `k / R`.
//!
//! Realistic `k/R` in [0.001, 0.01]: the rolling-resistance coefficients of hard bodies on wood
//! and glass. (The closed-form normal force of `losses.rs` needs `k` below half of `|r_G|`,
//! `Model::check_effects`.)

use super::{USUAL_IN_PLAN, 
    At, Descriptor, Role, Terms, Words, from_zero, no_camera, non_negative, usual_scan,
    usual_search,
};
use crate::physics::body::{ParamError, check_non_negative};
use nalgebra::Vector3;

pub struct Effect;
impl Terms for Effect {
    /// `k` (model units; 0: off).
    type Params = f64;
    fn in_units(k: &f64, length: f64, _time: f64) -> f64 {
        *k * length
    }
    #[inline]
    fn active(k: &f64) -> bool {
        *k != 0.0
    }
    #[inline]
    fn torque_against(k: &f64, at: &At) -> Option<Vector3<f64>> {
        if *k > 0.0 {
            let w_h = at.w - at.z * at.w.dot(at.z);
            Some(*k * w_h / (w_h.norm_squared() + at.eps * at.eps).sqrt())
        } else {
            None
        }
    }
    fn validate(k: &f64) -> Result<(), ParamError> {
        check_non_negative("rolling_friction", *k).map(|_| ())
    }
}

fn words(w: &Words) -> String {
    format!(
        "A rolling-resistance torque k F_N takes energy at a rate that does not grow with the square of the speed as air drag does, so the fitted drag cannot match the decay of the fast start and of the slow end together.{}{} Here the normal force acts {} ahead of the contact point.",
        w.late,
        w.end,
        super::mm(w.strength * w.r_mm)
    )
}

pub const DESCRIPTOR: Descriptor = Descriptor {
    name: "rolling_friction",
    parameter: "rolling-resistance arm k/R",
    what: "rolling friction: a torque proportional to the normal force that resists the rolling",
    role: Role::Physical,
    realistic: (0.001, 0.01),
    baseline: Some(0.0),
    apply: |s, at, e| {
        e.rolling_friction = non_negative(s)? * at.r;
        Ok(())
    },
    camera: no_camera,
    read: from_zero,
    extras: &[],
    scan: usual_scan,
    search: usual_search,
    blind: super::no_blind,
    words,
    plan: USUAL_IN_PLAN,
};
