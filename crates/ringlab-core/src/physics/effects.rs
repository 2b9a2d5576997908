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
    /// Coulomb sliding at the contact with friction coefficient `mu` (one coefficient for
    /// static and kinetic friction); strength `mu`.
    Slip,
    /// Air drag on the centre of mass `-k |v_C| v_C`; strength `k R`.
    TranslationalDrag,
    /// Radial lens distortion of the camera (the measurement, not the physics); strength `k1`.
    CameraDistortion,
    /// A pinhole camera at a finite distance `D` from the table (marks above the table look
    /// farther from the image centre), optionally tilted; strength `1000 mm / D` (0: the
    /// orthographic camera), the tilt a second free number where it is fitted.
    CameraPerspective,
}

impl EffectKind {
    pub const ALL: [EffectKind; 8] = [
        EffectKind::None,
        EffectKind::ReynoldsDrag,
        EffectKind::RollingFriction,
        EffectKind::PivotFriction,
        EffectKind::Slip,
        EffectKind::TranslationalDrag,
        EffectKind::CameraDistortion,
        EffectKind::CameraPerspective,
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
            EffectKind::CameraPerspective => "camera_perspective",
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
            EffectKind::Slip => "friction coefficient mu (static = kinetic)",
            EffectKind::TranslationalDrag => "translational drag k R",
            EffectKind::CameraDistortion => "radial distortion k1 (at the image half-diagonal)",
            EffectKind::CameraPerspective => "inverse camera distance 1000 mm / D",
        }
    }

    /// Whether the effect is in the physics (`Effects`) rather than the camera.
    pub fn is_physical(self) -> bool {
        !matches!(
            self,
            EffectKind::None | EffectKind::CameraDistortion | EffectKind::CameraPerspective
        )
    }

    /// The free numbers a fit of the effect adds: its strength, and for `camera_perspective`
    /// the camera's tilt as well, for `reynolds_drag` the rim's share of its speed
    /// (`ReynoldsDrag::rim_share`), for `slip` the slip velocity at the fit's start (two
    /// components, `Effects::slip_start_velocity`).
    pub fn free_count(self) -> usize {
        match self {
            EffectKind::None => 0,
            EffectKind::CameraPerspective | EffectKind::ReynoldsDrag => 2,
            EffectKind::Slip => 3,
            _ => 1,
        }
    }

    /// Whether the effect belongs to the camera (the measurement) rather than the motion.
    pub fn is_camera(self) -> bool {
        matches!(self, EffectKind::CameraDistortion | EffectKind::CameraPerspective)
    }

    /// The strength that leaves the physics as the paper's model has it. For `slip` that is
    /// no strength: pure rolling is the limit of a large `mu` (one above the friction that
    /// rolling needs everywhere, and below the body's Painleve limit, see `slip.rs`).
    pub fn baseline_strength(self) -> Option<f64> {
        match self {
            EffectKind::Slip => None,
            _ => Some(0.0),
        }
    }

    /// Strengths where the effect is physically plausible for a ring like the paper's AND
    /// visibly changes the paper ring's run (its end at t = 126.1, the inflection at 27.9,
    /// the end point of A at (-3.92, -0.79) mean radii), for tests and the diagnosis to draw
    /// from. Figures from `ringlab simulate --effect NAME --effect-strength X` on the paper
    /// ring, rtol 1e-10:
    /// - `reynolds_drag` n in [0.25, 0.75]: laminar skin friction gives n = 1/2 (the paper,
    ///   section IV); the spiral lives shorter as it should: the run ends at 95 (n = 0.25),
    ///   69 (0.5), 46 (0.75), the retrograde turning falls from 1,500 to 350 degrees.
    /// - `rolling_friction` k/R in [0.001, 0.01]: rolling-resistance coefficients of hard
    ///   bodies on wood and glass are 1e-3 to 1e-2; the run ends at 110 (0.001) to 62 (0.01).
    /// - `pivot_friction` k/R in [0.001, 0.01]: drilling friction of a contact patch of radius
    ///   a is about (2/3) mu a F_N; mu = 0.4 and a from 0.05 to 0.5 mm under the 1 mm wall of
    ///   the 20.66 mm ring give k/R from 0.0007 to 0.007. The run ends at 122 (0.001) to 76
    ///   (0.01), and the inflection moves (to 104 at 0.003).
    /// - `slip` mu in [0.25, 0.6]: static friction of steel on waxed wood, glass or steel
    ///   (the paper measured 0.4). The paper's start needs 4.2 times F_N in friction and lifts
    ///   off three times before t = 1.8, so every mu slides there: at 0.4 the ring slides
    ///   three times in the first 9 time units and its end point drifts by 5 mean radii; at 0.25
    ///   it slides at dozens of cusps. Below 0.25 it skids through most of its run.
    /// - `translational_drag` kR in [0.01, 0.1]: honest caveat: for the paper's 18 g steel ring,
    ///   k = rho_air C_D A / (2 m) gives kR = 6e-4, invisible. Light rings (plastic, thin
    ///   aluminium) reach 0.01 to 0.1, the order of the paper's fitted rotational C_i (which
    ///   absorb more than air). At 0.01 the end point of A moves by 0.55 mean radii (37 px in
    ///   the paper's video), at 0.1 by 3.2 and the run lasts 8% longer.
    /// - `camera_distortion` k1 in [-0.1, -0.02]: barrel distortion (the paper names it) of
    ///   wide lenses at the image corner; the measurement's side owns this.
    /// - `camera_perspective` 1000 mm / D in [1.25, 3.33]: a camera 300 to 800 mm above the
    ///   table, where a lab films a 40 mm ring with a normal lens; the paper names perspective
    ///   as one of the two causes of its 5% error. At 450 mm marks 25 mm above the table are
    ///   magnified by 6% about the image centre.
    /// - `none`: (0, 0).
    pub fn realistic_range(self) -> (f64, f64) {
        match self {
            EffectKind::None => (0.0, 0.0),
            EffectKind::ReynoldsDrag => (0.25, 0.75),
            EffectKind::RollingFriction => (0.001, 0.01),
            EffectKind::PivotFriction => (0.001, 0.01),
            EffectKind::Slip => (0.25, 0.6),
            EffectKind::TranslationalDrag => (0.01, 0.1),
            EffectKind::CameraDistortion => (-0.1, -0.02),
            EffectKind::CameraPerspective => (1.25, 3.33),
        }
    }
}

impl fmt::Display for EffectKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Multiplier cap of the Reynolds-dependent drag (the law is not followed to Re -> 0). Ten
/// times the start's `C_i`: with n = 1/2 the cap is reached at Re = Re_0 / 100, about 9 for the
/// paper's ring, where the flow round the ring is no longer a boundary layer (Stokes-like drag
/// varies as 1/Re and the ring is then practically at rest). The paper ring's runs never reach
/// it for n <= 0.75 (lowest Re about 50).
pub const REYNOLDS_MAX_FACTOR: f64 = 10.0;

/// Switches `kind` on in `effects` at `strength`, for a body of outer radius `r` whose run
/// starts at Reynolds number `re_start` (the reference of `reynolds_drag`: `C_i` are the
/// paper's at the start and grow as the ring slows). A baseline strength (0, except for slip)
/// switches the effect off, so the run is bit for bit the paper's model. `None` and the camera's
/// effects leave the physics alone.
pub fn apply(
    kind: EffectKind,
    strength: f64,
    r: f64,
    re_start: f64,
    effects: &mut Effects,
) -> Result<(), ParamError> {
    if !strength.is_finite() {
        return Err(ParamError {
            name: "effect strength",
            value: strength,
            reason: "must be a finite number",
        });
    }
    let non_negative = |v: f64| {
        if v < 0.0 {
            Err(ParamError {
                name: "effect strength",
                value: v,
                reason: "must not be negative for this effect",
            })
        } else {
            Ok(v)
        }
    };
    match kind {
        EffectKind::None | EffectKind::CameraDistortion | EffectKind::CameraPerspective => {}
        EffectKind::ReynoldsDrag => {
            effects.reynolds_drag = if non_negative(strength)? == 0.0 {
                None
            } else {
                Some(ReynoldsDrag {
                    re_ref: re_start.max(1e-9),
                    exponent: strength,
                    max_factor: REYNOLDS_MAX_FACTOR,
                    rim_share: 0.0,
                })
            }
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
    fn realistic_ranges_are_ordered_and_exclude_the_baseline() {
        for k in EffectKind::ALL {
            let (lo, hi) = k.realistic_range();
            assert!(lo <= hi, "{k}");
            if k.is_physical() {
                assert!(lo > 0.0, "{k}: a realistic strength must switch the effect on");
            }
        }
    }

    #[test]
    fn a_zero_strength_switches_the_effect_off() {
        for k in EffectKind::ALL.into_iter().filter(|k| k.baseline_strength() == Some(0.0)) {
            let mut e = Effects::default();
            apply(k, 0.0, 1.0, 500.0, &mut e).unwrap();
            assert!(e.is_none() && e.slip_mu.is_none(), "{k}: {e:?}");
        }
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
