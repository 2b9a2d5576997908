//! `camera_distortion`: radial lens distortion of the camera (the measurement, not the
//! physics); strength `k1` at the image half-diagonal.
//!
//! Realistic `k1` in [-0.1, -0.02]: barrel distortion of wide lenses at the image corner (the
//! paper names "image distortions"). The data decide the sign: the scan and the search go both
//! ways.

use super::{USUAL_IN_PLAN, Descriptor, Role, Terms, Words, log_spaced, no_physics};

pub struct Effect;
impl Terms for Effect {
    type Params = ();
}

fn words(w: &Words) -> String {
    format!(
        "The mismatch depends on where the ring is in the image rather than on when: {:.0}% of the baseline's squared residual points along the radius from the image centre (50% would mean no preference), and {:.0}% of the correction is radial. That is a lens's radial distortion (barrel for k1 < 0), the paper's 'image distortions'; the dynamics are unchanged.",
        100.0 * w.radial_share,
        100.0 * w.change_radial_share
    )
}

pub const DESCRIPTOR: Descriptor = Descriptor {
    name: "camera_distortion",
    parameter: "radial distortion k1 (at the image half-diagonal)",
    what: "the camera's radial lens distortion (a measurement effect; the physics is unchanged)",
    role: Role::Camera,
    realistic: (-0.1, -0.02),
    baseline: Some(0.0),
    apply: no_physics,
    camera: |k1, cam| {
        if k1.abs() > 0.5 {
            return false;
        }
        cam.k1 = k1;
        true
    },
    read: |_, cam| cam.k1,
    extras: &[],
    scan: |(lo, hi), _| {
        let mags = log_spaced(0.5 * hi.abs(), 2.0 * lo.abs(), 9);
        mags.iter().map(|m| -m).chain(mags.iter().copied()).collect()
    },
    search: |(lo, hi), _| {
        let m = 4.0 * lo.abs().max(hi.abs());
        (-m, m)
    },
    blind: super::no_blind,
    words,
    plan: USUAL_IN_PLAN,
};
