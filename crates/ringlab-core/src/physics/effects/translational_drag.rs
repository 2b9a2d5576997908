//! `translational_drag`: quadratic air drag on the centre of mass, `F = -k |v_C| v_C` per unit
//! mass (`k` is 1/length). Strength `k R`.
//!
//! Realistic `kR` in [0.01, 0.1]: for the paper's 18 g steel ring `k = rho_air C_D A / (2 m)`
//! gives 6e-4, invisible; light rings (plastic, thin aluminium) reach 0.01 to 0.1.

use super::{USUAL_IN_PLAN, 
    At, Descriptor, Role, Terms, Words, from_zero, no_camera, non_negative, usual_scan,
    usual_search,
};
use crate::physics::body::{ParamError, check_non_negative};
use nalgebra::Vector3;

pub struct Effect;
impl Terms for Effect {
    /// `k` (1 / model length; 0: off).
    type Params = f64;
    fn in_units(k: &f64, length: f64, _time: f64) -> f64 {
        *k / length
    }
    #[inline]
    fn active(k: &f64) -> bool {
        *k != 0.0
    }
    #[inline]
    fn force_at_centre(k: &f64, at: &At) -> Option<Vector3<f64>> {
        Some(-*k * at.v_c.norm() * at.v_c)
    }
    fn validate(k: &f64) -> Result<(), ParamError> {
        check_non_negative("translational_drag", *k).map(|_| ())
    }
}

fn words(w: &Words) -> String {
    format!(
        "Air drag on the centre of mass slows the travel of the ring while the rotational drag of eq. 5 acts on its spin; the two leave different marks on the path's arcs, which the drag coefficients alone cannot reproduce.{}{}",
        w.late, w.end
    )
}

pub const DESCRIPTOR: Descriptor = Descriptor {
    name: "translational_drag",
    parameter: "translational drag k R",
    what: "air drag on the travel of the ring (on its centre of mass), not only on its rotation",
    role: Role::Physical,
    realistic: (0.01, 0.1),
    baseline: Some(0.0),
    apply: |s, at, e| {
        e.translational_drag = non_negative(s)? / at.r;
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
