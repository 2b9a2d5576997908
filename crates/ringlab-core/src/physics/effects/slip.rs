//! `slip`: Coulomb sliding at the contact with friction coefficient `mu` (one coefficient for
//! static and kinetic friction); strength `mu`. The sliding contact is a contact model of its
//! own (`physics/slip.rs`, the run's switches in `run/switch.rs`); this file holds what the
//! rest of ringlab knows of it, and its parameters' meaning.
//!
//! Realistic `mu` in [0.25, 0.6]: static friction of steel on waxed wood, glass or steel (the
//! paper measured 0.4). Pure rolling is the limit of a large `mu` (below the body's Painleve
//! limit `mu_max`, `physics/painleve.rs`), so no strength is the baseline. Its fit adds the slip
//! velocity where the fit begins (a slide can be in progress at the first frame fitted).

use super::{USUAL_IN_PLAN, InPlan, 
    ApplyAt, CameraNumbers, Descriptor, Effects, Extra, Role, Step, Terms, Words, from_zero,
    log_spaced, no_camera, non_negative,
};
use crate::physics::body::{ParamError, check_finite, check_non_negative};

/// How a run with the slip effect begins where rolling at its start state would need more
/// friction than `mu F_N`. A recording starts where the camera does; how the contact stands at
/// the first frame is not in the data, so a fit may try both.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum SlipStart {
    /// Slide at once from zero slip (the physical reading of a state beyond the cone).
    #[default]
    Cone,
    /// Hold the contact rolling until rolling first needs no more than `mu F_N`; from then on
    /// slide where the demand crosses `mu F_N`. This is how an event-driven hybrid simulator
    /// behaves when it is started in rolling mode: it switches only at a zero crossing of the
    /// margin, so a start beyond the cone rolls on (the run reports that stretch as `slip`).
    HeldRolling,
}

/// The contact's parameters, kept in [`Effects`] beside the terms' (the run reads them):
/// `slip_mu` (None: pure rolling, the paper's model), `slip_start` ([`SlipStart`]) and
/// `slip_start_velocity`, the contact's slip velocity where a run begins at the model's start,
/// along the heading `(cos phi, sin phi)` and across it (a [`SlipStart::Cone`] start only; zero:
/// no slide in progress; runs continued from a later state of a run begin without it).
pub(super) fn validate_contact(e: &Effects) -> Result<(), ParamError> {
    if let Some(mu) = e.slip_mu {
        check_non_negative("slip mu", mu)?;
    }
    check_finite("slip start velocity (along)", e.slip_start_velocity[0])?;
    check_finite("slip start velocity (across)", e.slip_start_velocity[1])?;
    Ok(())
}

pub struct Effect;
impl Terms for Effect {
    type Params = ();
}

fn held(e: &Effects, _: &super::CameraNumbers) -> bool {
    e.slip_start == SlipStart::HeldRolling
}

fn write_along(v: f64, _: &ApplyAt, e: &mut Effects, _: &mut CameraNumbers) -> bool {
    e.slip_start_velocity[0] = v;
    true
}

fn write_across(v: f64, _: &ApplyAt, e: &mut Effects, _: &mut CameraNumbers) -> bool {
    e.slip_start_velocity[1] = v;
    true
}

fn words(w: &Words) -> String {
    let slides = if w.slides_s.is_empty() {
        "The improved model slides only briefly.".to_string()
    } else {
        let list: Vec<String> =
            w.slides_s.iter().take(6).map(|(a, b)| format!("{a:.3}-{b:.3} s")).collect();
        format!(
            "The improved model slides {} time{} ({}{}), where rolling would need more friction than mu F_N: at the launch and at the cusps of the walk.",
            w.slides_s.len(),
            if w.slides_s.len() == 1 { "" } else { "s" },
            list.join(", "),
            if w.slides_s.len() > 6 { ", ..." } else { "" }
        )
    };
    let held = if w.held_rolling {
        " The best fit starts held rolling: at the first frame rolling needs more friction than mu F_N, yet the recording shows no slide there; its contact rolls on until the demand has once come back within mu F_N and slides from where the demand next crosses it (as a contact started rolling and switched only where the demand crosses mu F_N, the way an event-driven simulator's hybrid contact does). A start that slides at once fits worse."
    } else {
        ""
    };
    let in_progress = match w.slip_start_mm_s {
        Some(v) if v != [0.0, 0.0] => format!(
            " Where the fit begins ({:.3} s) its contact already slips at {:.2} mm/s (a number of the fit: a slide can begin before the first frame fitted).",
            w.start_s,
            v[0].hypot(v[1])
        ),
        _ => String::new(),
    };
    format!(
        "A slide displaces the path at once and for good, so a model that must roll drifts from the first slide on. {slides}{held}{in_progress} The paper names slippage at cuspy turning points as a cause of its drift."
    )
}

/// More starts the scan cannot see: the middle of the realistic range, and where the run
/// begins held rolling also its low end. The scan holds the baseline's segment states, which
/// absorb a slide's drift, so it always picks the largest `mu` (no sliding), from where the
/// least squares never find the slides; they see a slide only where the model slides, and
/// from below each slide too many pulls `mu` up towards the recording's.
fn blind((lo, hi): (f64, f64), mu_max: f64, held_rolling: bool) -> Vec<f64> {
    let mid = (lo * hi).sqrt().min(0.9 * mu_max);
    if held_rolling { vec![lo.min(0.9 * mu_max), mid] } else { vec![mid] }
}

pub const DESCRIPTOR: Descriptor = Descriptor {
    name: "slip",
    parameter: "friction coefficient mu (static = kinetic)",
    what: "slipping at the contact: the ring slides where rolling would need more friction than the table gives",
    role: Role::Physical,
    realistic: (0.25, 0.6),
    baseline: None,
    apply: |s, _, e| {
        e.slip_mu = Some(non_negative(s)?);
        Ok(())
    },
    camera: no_camera,
    read: from_zero,
    extras: &[
        Extra {
            name: "slip velocity at the start, along",
            // In mm/s as `slip_start_along_mm_s` (`ModelFit::slip_start_mm_s`).
            json: None,
            start: 0.0,
            scan: &[],
            realistic: (0.0, 0.0),
            bounds: (f64::NEG_INFINITY, f64::INFINITY),
            projected: false,
            step: Step::Fixed(1e-6),
            read: |e, _| e.slip_start_velocity[0],
            write: write_along,
            held_at_zero: held,
        },
        Extra {
            name: "slip velocity at the start, across",
            json: None,
            start: 0.0,
            scan: &[],
            realistic: (0.0, 0.0),
            bounds: (f64::NEG_INFINITY, f64::INFINITY),
            projected: false,
            step: Step::Fixed(1e-6),
            read: |e, _| e.slip_start_velocity[1],
            write: write_across,
            held_at_zero: held,
        },
    ],
    // From half the low end to just below the Painleve limit.
    scan: |(lo, _), mu_max| {
        log_spaced(0.5 * lo, 0.98 * mu_max, 9).into_iter().filter(|&m| m > 0.0).collect()
    },
    search: |(lo, _), mu_max| (0.25 * lo, 0.99 * mu_max),
    blind,
    words,
    plan: InPlan { costly: true, two_starts: true, ..USUAL_IN_PLAN },
};
