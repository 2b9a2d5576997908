//! `reynolds_drag`: drag coefficients that grow as the Reynolds number falls (the paper,
//! section III: "as the motion of the ring slows down, Re decreases and the drag coefficients
//! increase"): `C_i(Re) = C_i (Re_0 / Re)^n`, `Re_0` the Reynolds number at the start; strength
//! `n`, with the rim's share of the speed that sets `Re` a second fitted number.
//!
//! Realistic `n` in [0.25, 0.75]: laminar skin friction gives `n` = 1/2 (the paper, section
//! IV). It rescales eq. 5 in the hot path (`Model::drag_coefficients`), no cold-path term.

use super::{USUAL_IN_PLAN, InPlan, 
    ApplyAt, CameraNumbers, Descriptor, Effects, Extra, Role, Step, Terms, Words, from_zero,
    never_held, no_camera, non_negative, usual_scan, usual_search,
};
use crate::physics::body::{ParamError, check_finite, check_non_negative, check_positive};

/// Multiplier cap of the Reynolds-dependent drag (the law is not followed to Re -> 0). Ten
/// times the start's `C_i`: with n = 1/2 the cap is reached at Re = Re_0 / 100, where the flow
/// round the ring is no longer a boundary layer and the ring is practically at rest.
pub const REYNOLDS_MAX_FACTOR: f64 = 10.0;

/// `C_i(Re) = C_i (Re_ref / Re)^n`, the factor capped at `max_factor` because the power law
/// does not hold as `Re -> 0`. `Re = 2 U R / nu_air` is physical, the same in every unit
/// system. Which speed `U` sets the flow round a spinning ring the paper does not pin down: it
/// takes the centre's, `|v_C|`; the rim moves at `|omega| R`. `rim_share` blends the two,
/// `U^2 = |v_C|^2 + s (|omega|^2 R^2 - |v_C|^2)` (0: the paper's, 1: the rim's), so that a
/// drag law of that other shape is still this effect.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ReynoldsDrag {
    pub re_ref: f64,
    pub exponent: f64,
    pub max_factor: f64,
    pub rim_share: f64,
}

impl ReynoldsDrag {
    /// The multiplier on `C_i` at Reynolds number `re`: `min((re_ref / re)^n, max_factor)`.
    /// Continuous in `re`, and `max_factor` at `re = 0`.
    #[inline]
    pub fn factor(&self, re: f64) -> f64 {
        if re <= 0.0 {
            return self.max_factor;
        }
        (self.re_ref / re).powf(self.exponent).min(self.max_factor)
    }
}

pub struct Effect;
impl Terms for Effect {
    type Params = Option<ReynoldsDrag>;
    fn scales_drag(p: &Option<ReynoldsDrag>) -> bool {
        p.is_some()
    }
    fn validate(p: &Option<ReynoldsDrag>) -> Result<(), ParamError> {
        let Some(r) = p else { return Ok(()) };
        check_positive("reynolds_drag re_ref", r.re_ref)?;
        check_non_negative("reynolds_drag exponent", r.exponent)?;
        check_finite("reynolds_drag max_factor", r.max_factor)?;
        if !(0.0..=1.0).contains(&r.rim_share) {
            return Err(ParamError {
                name: "reynolds_drag rim_share",
                value: r.rim_share,
                reason: "must lie in [0, 1] (0: the centre's speed, 1: the rim's)",
            });
        }
        if r.max_factor < 1.0 {
            return Err(ParamError {
                name: "reynolds_drag max_factor",
                value: r.max_factor,
                reason: "must be at least 1 (the cap bounds the growth of C_i at low Re)",
            });
        }
        Ok(())
    }
}

fn apply(s: f64, at: &ApplyAt, e: &mut Effects) -> Result<(), ParamError> {
    e.reynolds_drag = if non_negative(s)? == 0.0 {
        None
    } else {
        Some(ReynoldsDrag {
            re_ref: at.re_centre.max(1e-9),
            exponent: s,
            max_factor: REYNOLDS_MAX_FACTOR,
            rim_share: 0.0,
        })
    };
    Ok(())
}

/// The rim's share, set after the exponent: where that is zero the drag has no Reynolds law
/// for the share to shape. The reference moves with it, so that `C_i` stay those at the start.
fn write_rim_share(v: f64, at: &ApplyAt, e: &mut Effects, _: &mut CameraNumbers) -> bool {
    if !(0.0..=1.0).contains(&v) {
        return false;
    }
    if let Some(r) = e.reynolds_drag.as_mut() {
        let (c, rim) = (at.re_centre * at.re_centre, at.re_rim * at.re_rim);
        r.rim_share = v;
        r.re_ref = (c + v * (rim - c)).max(0.0).sqrt().max(1e-9);
    }
    true
}

fn words(w: &Words) -> String {
    let rim = w.extras.first().map_or(String::new(), |&(v, s)| {
        let which = if v < 0.1 {
            "the centre's speed, as the paper has it"
        } else if v > 0.9 {
            "the rim's speed |omega| R rather than the centre's (the paper's)"
        } else {
            "a speed between the centre's (the paper's) and the rim's"
        };
        format!(
            " The Reynolds number here follows {which}: the rim's share of its speed fits as {}.",
            super::pm(v, s)
        )
    });
    format!(
        "Drag that depends on the speed changes the damping within every cycloid (fast arcs, slow cusps) and grows as the ring slows, most in the final spiral.{}{} Constant coefficients cannot follow both the early and the late decay; C_i (Re_0/Re)^n can. This is the paper's own explanation of its long-lived simulated spiral (section III: as Re decreases the drag coefficients increase); laminar skin friction suggests n near 1/2.{rim}",
        w.late, w.end
    )
}

pub const DESCRIPTOR: Descriptor = Descriptor {
    name: "reynolds_drag",
    parameter: "exponent n of C(Re) = C (Re_0/Re)^n",
    what: "drag coefficients that grow as the ring slows down (C_i rising as the Reynolds number falls)",
    role: Role::Physical,
    realistic: (0.25, 0.75),
    baseline: Some(0.0),
    apply,
    camera: no_camera,
    read: from_zero,
    extras: &[Extra {
        name: "reynolds_drag rim share",
        json: Some("reynolds_rim_share"),
        start: 0.0,
        scan: &[],
        realistic: (0.0, 0.0),
        bounds: (0.0, 1.0),
        projected: true,
        step: Step::IntoBox(1e-6),
        read: |e, _| e.reynolds_drag.map_or(0.0, |r| r.rim_share),
        write: write_rim_share,
        held_at_zero: never_held,
    }],
    scan: usual_scan,
    search: usual_search,
    blind: super::no_blind,
    words,
    plan: InPlan { shape: Some(0), ..USUAL_IN_PLAN },
};
