//! `pivot_friction`: a drilling torque `-k F_N sign(w . Z) Z` against spin about the table
//! normal; `k` is a length (contact-patch radius times a friction coefficient). Strength `k / R`.
//!
//! Realistic `k/R` in [0.001, 0.01]: drilling friction of a contact patch of radius `a` is
//! about `(2/3) mu a F_N`; `mu` = 0.4 and `a` from 0.05 to 0.5 mm under the 1 mm wall of the
//! paper's 20.66 mm ring give 0.0007 to 0.007.

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
            let s = at.w.dot(at.z);
            Some(*k * (s / (s * s + at.eps * at.eps).sqrt()) * at.z)
        } else {
            None
        }
    }
    fn validate(k: &f64) -> Result<(), ParamError> {
        check_non_negative("pivot_friction", *k).map(|_| ())
    }
}

fn words(w: &Words) -> String {
    format!(
        "A drilling torque k F_N against the spin about the table normal slows the precession and turns the path's heading in a way the quadratic drag on the body's axes cannot imitate.{}{} Here k = {} (contact-patch radius times a friction coefficient).",
        w.late,
        w.end,
        super::mm(w.strength * w.r_mm)
    )
}

pub const DESCRIPTOR: Descriptor = Descriptor {
    name: "pivot_friction",
    parameter: "pivot-friction arm k/R",
    what: "pivot friction: a torque proportional to the normal force that resists spinning about the vertical",
    role: Role::Physical,
    realistic: (0.001, 0.01),
    baseline: Some(0.0),
    apply: |s, at, e| {
        e.pivot_friction = non_negative(s)? * at.r;
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
