//! The named effects beyond the paper's model, and how one number (a dimensionless
//! *strength*) switches each on. Shared by `simulate`, `synth`, the window and the diagnosis,
//! so that a recording made with `--effect NAME --effect-strength X` means the same everywhere.

use super::body::ParamError;
use super::model::{Effects, ReynoldsDrag};
use std::fmt;

/// Everything the diagnosis can name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EffectKind {
    /// The recording agrees with the baseline model.
    None,
    /// `C_i(Re) = C_i (Re_0 / Re)^n`, `Re_0` the Reynolds number at the start; strength `n`.
    ReynoldsDrag,
    /// Rolling resistance torque `k F_N` against the rolling part of omega; strength `k / R`.
    RollingFriction,
    /// Pivot friction torque `k F_N` against spin about the table normal; strength `k / R`.
    PivotFriction,
    /// Coulomb sliding at the contact with kinetic friction coefficient `mu`; strength `mu`.
    Slip,
    /// Air drag on the centre of mass `-k |v_C| v_C`; strength `k R`.
    TranslationalDrag,
    /// Radial lens distortion of the camera (the measurement, not the physics); strength `k1`.
    CameraDistortion,
}

impl EffectKind {
    pub const ALL: [EffectKind; 7] = [
        EffectKind::None,
        EffectKind::ReynoldsDrag,
        EffectKind::RollingFriction,
        EffectKind::PivotFriction,
        EffectKind::Slip,
        EffectKind::TranslationalDrag,
        EffectKind::CameraDistortion,
    ];

    pub fn name(self) -> &'static str {
        match self {
            EffectKind::None => "none",
            EffectKind::ReynoldsDrag => "reynolds_drag",
            EffectKind::RollingFriction => "rolling_friction",
            EffectKind::PivotFriction => "pivot_friction",
            EffectKind::Slip => "slip",
            EffectKind::TranslationalDrag => "translational_drag",
            EffectKind::CameraDistortion => "camera_distortion",
        }
    }

    pub fn from_name(s: &str) -> Option<EffectKind> {
        EffectKind::ALL.into_iter().find(|k| k.name() == s.trim())
    }

    /// What the strength is, in words.
    pub fn parameter(self) -> &'static str {
        match self {
            EffectKind::None => "-",
            EffectKind::ReynoldsDrag => "exponent n of C(Re) = C (Re_0/Re)^n",
            EffectKind::RollingFriction => "rolling-resistance arm k/R",
            EffectKind::PivotFriction => "pivot-friction arm k/R",
            EffectKind::Slip => "kinetic friction coefficient mu",
            EffectKind::TranslationalDrag => "translational drag k R",
            EffectKind::CameraDistortion => "radial distortion k1 (at the image half-diagonal)",
        }
    }

    /// Whether the effect is in the physics (`Effects`) rather than the camera.
    pub fn is_physical(self) -> bool {
        !matches!(self, EffectKind::None | EffectKind::CameraDistortion)
    }
}

impl fmt::Display for EffectKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Multiplier cap of the Reynolds-dependent drag (the law is not followed to Re -> 0).
pub const REYNOLDS_MAX_FACTOR: f64 = 10.0;

/// Switches `kind` on in `effects` at `strength`, for a body of outer radius `r` whose run
/// starts at Reynolds number `re_start`. `None` and `CameraDistortion` leave the physics alone.
pub fn apply(
    kind: EffectKind,
    strength: f64,
    r: f64,
    re_start: f64,
    effects: &mut Effects,
) -> Result<(), ParamError> {
    if !strength.is_finite() {
        return Err(ParamError { name: "effect strength", value: strength, reason: "must be a finite number" });
    }
    let non_negative = |v: f64| {
        if v < 0.0 {
            Err(ParamError { name: "effect strength", value: v, reason: "must not be negative for this effect" })
        } else {
            Ok(v)
        }
    };
    match kind {
        EffectKind::None | EffectKind::CameraDistortion => {}
        EffectKind::ReynoldsDrag => {
            effects.reynolds_drag = Some(ReynoldsDrag {
                re_ref: re_start.max(1e-9),
                exponent: non_negative(strength)?,
                max_factor: REYNOLDS_MAX_FACTOR,
            })
        }
        EffectKind::RollingFriction => effects.rolling_friction = non_negative(strength)? * r,
        EffectKind::PivotFriction => effects.pivot_friction = non_negative(strength)? * r,
        EffectKind::Slip => effects.slip_mu = Some(non_negative(strength)?),
        EffectKind::TranslationalDrag => effects.translational_drag = non_negative(strength)? / r,
    }
    effects.validate()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for k in EffectKind::ALL {
            assert_eq!(EffectKind::from_name(k.name()), Some(k));
        }
        assert_eq!(EffectKind::from_name("wind"), None);
    }

    #[test]
    fn strengths_set_the_documented_parameters() {
        let mut e = Effects::default();
        apply(EffectKind::RollingFriction, 0.01, 2.0, 500.0, &mut e).unwrap();
        assert!((e.rolling_friction - 0.02).abs() < 1e-15);
        apply(EffectKind::ReynoldsDrag, 0.5, 2.0, 500.0, &mut e).unwrap();
        assert_eq!(e.reynolds_drag.unwrap().re_ref, 500.0);
        assert!(apply(EffectKind::PivotFriction, -1.0, 1.0, 1.0, &mut e).is_err());
        assert!(apply(EffectKind::Slip, f64::NAN, 1.0, 1.0, &mut e).is_err());
    }
}
