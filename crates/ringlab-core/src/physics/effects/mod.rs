//! The effects beyond the paper's model, one file each, listed once in [`list!`] below.
//!
//! An effect's file holds everything the simulator, the fit, the diagnosis, the explanation,
//! `synth`, `ringlab effects` and the window know of it: its [`Descriptor`] (name, strength and
//! realistic range, its free numbers beyond the strength, where the diagnosis scans for it, its
//! words) and, for a physical effect, its terms in the equations of motion ([`Terms`]: a force
//! at the centre of mass, a torque per unit normal force, or both) and its parameters in
//! [`Effects`]. A camera effect maps its numbers onto the camera ([`CameraNumbers`]). The
//! sliding contact (`slip`) is a contact model of its own (`physics/slip.rs`, `run/switch.rs`);
//! its file holds its descriptor and its parameters.
//!
//! Why one dimensionless strength per effect: `synth --effect NAME --effect-strength X`,
//! `simulate`, the window and the diagnosis then mean the same thing by it.
//!
//! A new effect is one new file and one line in [`list!`]; every `match` over [`EffectKind`]
//! is exhaustive, so the compiler names what a new kind lacks.

use super::body::ParamError;
use nalgebra::Vector3;
use std::fmt;

/// The effects, each `Variant => module: field type`: the variant of [`EffectKind`], its file,
/// and its parameters' field in [`Effects`] (named as its module). The order is the order of
/// [`EffectKind::ALL`] (the diagnosis's candidates, `ringlab effects`), and new effects go last
/// (a concealed recording's random numbers are seeded by the variant's index).
macro_rules! list {
    ($($variant:ident => $module:ident : $params:ty),* $(,)?) => {
        $(pub mod $module;)*

        /// Everything the diagnosis can name.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
        pub enum EffectKind { $($variant),* }

        impl EffectKind {
            pub const ALL: [EffectKind; [$(stringify!($variant)),*].len()] =
                [$(EffectKind::$variant),*];

            /// Everything ringlab knows of the effect.
            pub fn descriptor(self) -> &'static Descriptor {
                match self { $(EffectKind::$variant => &$module::DESCRIPTOR),* }
            }
        }

        /// Physics beyond the paper's model: each effect's parameters, all off by default
        /// (lengths in the model's units). Each field is described in its effect's file.
        #[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
        pub struct Effects {
            $(pub $module: $params,)*
            /// The sliding contact's parameters (`slip.rs` says what each is): a contact model
            /// of its own, which the run switches to, not a term of the rolling equations.
            pub slip_mu: Option<f64>,
            pub slip_start: slip::SlipStart,
            pub slip_start_velocity: [f64; 2],
        }

        impl Effects {
            /// Whether the rolling right-hand side needs its cold path: forces and torques
            /// that change the contact force.
            #[inline]
            pub fn has_contact_terms(&self) -> bool {
                false $(|| <$module::Effect as Terms>::active(&self.$module))*
            }

            /// No effect at all in the rolling right-hand side (the sliding contact is handled
            /// by the run, not here).
            pub fn is_none(&self) -> bool {
                !self.has_contact_terms() $(&& !<$module::Effect as Terms>::scales_drag(&self.$module))*
            }

            /// The force per unit mass on the centre of mass of every effect (frame components).
            #[inline]
            pub fn force_at_centre(&self, at: &At) -> Vector3<f64> {
                let mut f = Vector3::zeros();
                $(if <$module::Effect as Terms>::active(&self.$module) {
                    if let Some(x) = <$module::Effect as Terms>::force_at_centre(&self.$module, at) {
                        f += x;
                    }
                })*
                f
            }

            /// `u`: the torque of every effect per unit normal force (frame components).
            #[inline]
            pub fn torque_per_normal_force(&self, at: &At) -> Vector3<f64> {
                let mut u = Vector3::zeros();
                $(if <$module::Effect as Terms>::active(&self.$module) {
                    if let Some(x) = <$module::Effect as Terms>::torque_against(&self.$module, at) {
                        u -= x;
                    }
                })*
                u
            }

            /// The same effects in other units: lengths `length` times, times `time` times the
            /// old.
            pub fn in_units(&self, length: f64, time: f64) -> Effects {
                Effects {
                    $($module: <$module::Effect as Terms>::in_units(&self.$module, length, time),)*
                    slip_start_velocity: self.slip_start_velocity.map(|v| v * length / time),
                    ..*self
                }
            }

            pub fn validate(&self) -> Result<(), ParamError> {
                $(<$module::Effect as Terms>::validate(&self.$module)?;)*
                slip::validate_contact(self)
            }
        }
    };
}

list! {
    None => none: (),
    ReynoldsDrag => reynolds_drag: Option<reynolds_drag::ReynoldsDrag>,
    RollingFriction => rolling_friction: f64,
    PivotFriction => pivot_friction: f64,
    Slip => slip: (),
    TranslationalDrag => translational_drag: f64,
    CameraDistortion => camera_distortion: (),
    CameraPerspective => camera_perspective: (),
    TableSlope => table_slope: Option<table_slope::TableSlope>,
}

/// Where the terms are evaluated: the state's rates and the table's directions in the Resal
/// frame, and the model's constants.
pub struct At<'a> {
    /// omega.
    pub w: &'a Vector3<f64>,
    /// The table's normal, `(0, sin(theta), cos(theta))`.
    pub z: &'a Vector3<f64>,
    /// The velocity of the centre of mass.
    pub v_c: &'a Vector3<f64>,
    /// `(sin(theta), cos(theta))` and `(sin(phi), cos(phi))`.
    pub theta: (f64, f64),
    pub heading: (f64, f64),
    /// Gravity.
    pub g: f64,
    /// The rate below which friction directions are smoothed (`losses::FRICTION_SMOOTHING`).
    pub eps: f64,
}

/// An effect's terms in the equations of motion (`losses.rs` assembles them; `slip.rs` adds
/// them to the sliding contact). Every method but `active` and `validate` has a default of
/// nothing, so an effect says only what it does.
pub trait Terms {
    type Params: Copy;
    /// Its parameters in other units, lengths `length` times, times `time` times the old.
    fn in_units(p: &Self::Params, _length: f64, _time: f64) -> Self::Params {
        *p
    }
    /// Whether its parameters switch on a force or torque of the cold path.
    fn active(_p: &Self::Params) -> bool {
        false
    }
    /// Whether it rescales eq. 5's drag (the hot path: `Model::drag_coefficients`).
    fn scales_drag(_p: &Self::Params) -> bool {
        false
    }
    /// A force per unit mass at the centre of mass.
    fn force_at_centre(_p: &Self::Params, _at: &At) -> Option<Vector3<f64>> {
        None
    }
    /// A torque per unit normal force, given as what is subtracted (the friction it opposes).
    fn torque_against(_p: &Self::Params, _at: &At) -> Option<Vector3<f64>> {
        None
    }
    fn validate(_p: &Self::Params) -> Result<(), ParamError> {
        Ok(())
    }
}

/// Whether an effect is in the physics, in the camera, or nowhere (`none`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    Nothing,
    Physical,
    Camera,
}

/// The camera's numbers an effect can set (`recording::Camera` reads and writes them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraNumbers {
    /// The table's scale (px per mm).
    pub px_per_mm: f64,
    /// Radial distortion coefficient (0: none).
    pub k1: f64,
    /// The pinhole's distance from the table (mm); None: orthographic.
    pub distance_mm: Option<f64>,
    /// The optical axis's angle from the table's normal (rad).
    pub tilt_rad: f64,
    /// Whether `px_per_mm` is the tracker's estimate through a near camera, which a camera
    /// effect may correct (read only: no effect sets it).
    pub scale_free: bool,
}

/// What an effect's numbers are applied to: the body's outer radius, the Reynolds numbers at
/// the run's start (of the centre's speed and of the rim's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ApplyAt {
    pub r: f64,
    pub re_centre: f64,
    pub re_rim: f64,
}

impl ApplyAt {
    /// For a run of a body of outer radius `r` starting at Reynolds number `re_start` (both
    /// speeds the same: the paper's law).
    pub fn new(r: f64, re_start: f64) -> ApplyAt {
        ApplyAt { r, re_centre: re_start, re_rim: re_start }
    }
}

/// How a fit steps a number for its derivative (internal coordinates).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Step {
    /// A fixed step.
    Fixed(f64),
    /// A step into the number's box from whichever bound is nearer.
    IntoBox(f64),
}

/// A number an effect's fit adds beyond its strength.
pub struct Extra {
    /// In the fit's words ("camera tilt (deg)").
    pub name: &'static str,
    /// Its key among a JSON report's fitted parameters (its sigma's: `_sigma` added); None
    /// where the report gives it in other words.
    pub json: Option<&'static str>,
    /// Where a fit starts it.
    pub start: f64,
    /// Values the diagnosis's scan tries beside each trial strength (empty: the start only).
    pub scan: &'static [f64],
    /// Where a concealed recording draws it (uniformly; where the ends are equal, it is not
    /// drawn and the recording keeps its own).
    pub realistic: (f64, f64),
    /// Outside, the model is not built (a step there is refused).
    pub bounds: (f64, f64),
    /// Whether a least-squares step that would leave `bounds` stops at the bound instead.
    pub projected: bool,
    pub step: Step,
    /// Its value in a model and camera (where a fit starts from them).
    pub read: fn(&Effects, &CameraNumbers) -> f64,
    /// Sets it, after the strength; false where the value is outside the effect's domain.
    pub write: fn(f64, &ApplyAt, &mut Effects, &mut CameraNumbers) -> bool,
    /// Whether the model (or the camera) holds it at zero (a box of one point: its runs
    /// ignore it).
    pub held_at_zero: fn(&Effects, &CameraNumbers) -> bool,
}

/// What the explanation knows when it puts an effect in words.
pub struct Words<'a> {
    /// The fitted strength (NaN where unknown) and the extra numbers with their sigmas, in the
    /// descriptor's order (empty where they were not fitted).
    pub strength: f64,
    pub strength_sigma: f64,
    pub extras: &'a [(f64, f64)],
    /// "X% of the misfit lies in the last third." and the motion's end, both as sentences
    /// with a leading space, or empty.
    pub late: &'a str,
    pub end: &'a str,
    /// The share of the baseline's squared residual along the radius from the image centre,
    /// and of the correction.
    pub radial_share: f64,
    pub change_radial_share: f64,
    /// The fitted outer radius (mm).
    pub r_mm: f64,
    /// The improved model's slides (s), whether its contact starts held rolling, where its fit
    /// begins (s) and its slip velocity there (mm/s) where it slides from there.
    pub slides_s: &'a [(f64, f64)],
    pub held_rolling: bool,
    pub start_s: f64,
    pub slip_start_mm_s: Option<[f64; 2]>,
}

/// Everything ringlab knows of an effect but its terms: what the simulator, the fit, the
/// diagnosis, the explanation, `synth`, `ringlab effects` and the window read.
pub struct Descriptor {
    pub name: &'static str,
    /// What the strength is, in words.
    pub parameter: &'static str,
    /// What the effect is, in a lab's words.
    pub what: &'static str,
    pub role: Role,
    /// Strengths where the effect is physically plausible and visibly changes the paper ring's
    /// run (the effect's file says why); for tests and the diagnosis to draw from.
    pub realistic: (f64, f64),
    /// The strength that leaves the model as the paper has it (None: no strength does, as for
    /// slip, whose pure rolling is the limit of a large `mu`).
    pub baseline: Option<f64>,
    /// Sets the physics at `strength` (a baseline strength switches the effect off, so the run
    /// is bit for bit the paper's).
    pub apply: fn(f64, &ApplyAt, &mut Effects) -> Result<(), ParamError>,
    /// Sets the camera at `strength`; false outside the camera's domain.
    pub camera: fn(f64, &mut CameraNumbers) -> bool,
    /// The strength a fit starts from in a model and camera.
    pub read: fn(&Effects, &CameraNumbers) -> f64,
    /// The numbers a fit adds beyond the strength.
    pub extras: &'static [Extra],
    /// The strengths the diagnosis scans first (`realistic`, the Painleve limit `mu_max`).
    pub scan: fn((f64, f64), f64) -> Vec<f64>,
    /// Where the diagnosis looks for the strength (`realistic`, `mu_max`).
    pub search: fn((f64, f64), f64) -> (f64, f64),
    /// More strengths the diagnosis starts from beside the scan's pick, where the scan cannot
    /// see the effect (`realistic`, `mu_max`, whether the run begins held rolling).
    pub blind: fn((f64, f64), f64, bool) -> Vec<f64>,
    /// Why the mismatch's signature points to the effect, in words.
    pub words: fn(&Words) -> String,
    /// What the diagnosis's plan needs to know of it beyond its role.
    pub plan: InPlan,
}

/// What the diagnosis's plan (`analysis/diagnose/plan.rs`) knows of an effect beyond its
/// [`Role`]: no pass of the plan names an effect, it asks these.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InPlan {
    /// Its runs cost the most of any (a sliding contact's switches are found and run anew at
    /// each): fitted first among the candidates, paired and added to another's solution only
    /// where it improved alone, not scanned from the baseline's solution, given up through a
    /// camera where its path stopped, and fitted through a leading camera by a pass of its own
    /// (through the wrong camera it cannot improve alone).
    pub costly: bool,
    /// Its run can begin in two ways (`SlipStart`): its first stage is fitted both ways and
    /// goes on with the better, and a pair with it keeps the way its own fit chose.
    pub two_starts: bool,
    /// It stands in for the camera a header can give (its distance): where the header gives
    /// it, every model uses that camera, and this effect is no suspect unless that camera is
    /// a tracker's fit from the ring (`scale_free`), which it then starts from.
    pub header_camera: bool,
    /// The extra (an index into `extras`) that shapes the effect's law away from the paper's:
    /// where it fitted alone away from its start, a pair it leads is also walked with the
    /// other effect leading (alone, that shape can imitate part of another effect).
    pub shape: Option<usize>,
}

/// An effect the plan treats as any other.
pub const USUAL_IN_PLAN: InPlan =
    InPlan { costly: false, two_starts: false, header_camera: false, shape: None };

impl EffectKind {
    /// The paper's model alone: the kind with no role (the baseline of every comparison).
    pub const BASELINE: EffectKind = EffectKind::None;

    /// Whether it is the paper's model alone ([`EffectKind::BASELINE`]).
    pub fn is_baseline(self) -> bool {
        self.descriptor().role == Role::Nothing
    }

    /// What the diagnosis's plan knows of it ([`InPlan`]).
    pub fn in_plan(self) -> InPlan {
        self.descriptor().plan
    }

    pub fn name(self) -> &'static str {
        self.descriptor().name
    }

    pub fn from_name(s: &str) -> Option<EffectKind> {
        EffectKind::ALL.into_iter().find(|k| k.name() == s.trim())
    }

    /// What the strength is, in words.
    pub fn parameter(self) -> &'static str {
        self.descriptor().parameter
    }

    /// Whether the effect is in the physics (`Effects`) rather than the camera.
    pub fn is_physical(self) -> bool {
        self.descriptor().role == Role::Physical
    }

    /// Whether the effect belongs to the camera (the measurement) rather than the motion.
    pub fn is_camera(self) -> bool {
        self.descriptor().role == Role::Camera
    }

    /// The free numbers a fit of the effect adds: its strength and its extras.
    pub fn free_count(self) -> usize {
        match self.descriptor().role {
            Role::Nothing => 0,
            Role::Physical | Role::Camera => 1 + self.descriptor().extras.len(),
        }
    }

    /// The strength that leaves the physics as the paper's model has it.
    pub fn baseline_strength(self) -> Option<f64> {
        self.descriptor().baseline
    }

    /// See [`Descriptor::realistic`].
    pub fn realistic_range(self) -> (f64, f64) {
        self.descriptor().realistic
    }
}

impl fmt::Display for EffectKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Switches `kind` on in `effects` at `strength`, for a body of outer radius `r` whose run
/// starts at Reynolds number `re_start`. A baseline strength switches the effect off, so the
/// run is bit for bit the paper's model. `None` and the camera's effects leave the physics alone.
pub fn apply(
    kind: EffectKind,
    strength: f64,
    r: f64,
    re_start: f64,
    effects: &mut Effects,
) -> Result<(), ParamError> {
    apply_at(kind, strength, &ApplyAt::new(r, re_start), effects)
}

/// [`apply`] at `at`.
pub fn apply_at(
    kind: EffectKind,
    strength: f64,
    at: &ApplyAt,
    effects: &mut Effects,
) -> Result<(), ParamError> {
    if !strength.is_finite() {
        return Err(ParamError {
            name: "effect strength",
            value: strength,
            reason: "must be a finite number",
        });
    }
    (kind.descriptor().apply)(strength, at, effects)?;
    effects.validate()
}

/// Switches `kind` on at `strength` with its first `extras.len()` extra numbers (the rest as
/// the model and camera have them): the physics in `effects`, the camera's numbers in `camera`.
pub fn apply_with_extras(
    kind: EffectKind,
    strength: f64,
    extras: &[f64],
    at: &ApplyAt,
    effects: &mut Effects,
    camera: &mut CameraNumbers,
) -> Result<(), ParamError> {
    let d = kind.descriptor();
    match d.role {
        Role::Physical => apply_at(kind, strength, at, effects)?,
        Role::Camera => {
            if !strength.is_finite() || !(d.camera)(strength, camera) {
                return Err(ParamError {
                    name: "effect strength",
                    value: strength,
                    reason: "is outside the camera's domain",
                });
            }
        }
        Role::Nothing => {}
    }
    for (x, &v) in d.extras.iter().zip(extras) {
        if !(x.bounds.0..=x.bounds.1).contains(&v) || !(x.write)(v, at, effects, camera) {
            return Err(ParamError { name: x.name, value: v, reason: "is outside its bounds" });
        }
    }
    effects.validate()
}

/// `v` where it is not negative.
pub(crate) fn non_negative(v: f64) -> Result<f64, ParamError> {
    if v < 0.0 {
        Err(ParamError {
            name: "effect strength",
            value: v,
            reason: "must not be negative for this effect",
        })
    } else {
        Ok(v)
    }
}

/// Nothing to apply (the camera's effects, `none`).
pub(crate) fn no_physics(_: f64, _: &ApplyAt, _: &mut Effects) -> Result<(), ParamError> {
    Ok(())
}

/// No camera to set (the physical effects, `none`).
pub(crate) fn no_camera(_: f64, _: &mut CameraNumbers) -> bool {
    true
}

/// Starts at zero.
pub(crate) fn from_zero(_: &Effects, _: &CameraNumbers) -> f64 {
    0.0
}

/// Never held.
pub(crate) fn never_held(_: &Effects, _: &CameraNumbers) -> bool {
    false
}

/// Nine log-spaced values from `a` to `b`.
pub(crate) fn log_spaced(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n).map(|i| a * (b / a).powf(i as f64 / (n - 1) as f64)).collect()
}

/// The usual scan: nine log-spaced strengths from half the realistic range's low end to twice
/// its high end. Not zero: the baseline's drag and states absorb what they can of an effect,
/// so at them no effect always looks best.
pub(crate) fn usual_scan((lo, hi): (f64, f64), _mu_max: f64) -> Vec<f64> {
    log_spaced(0.5 * lo, 2.0 * hi, 9)
}

/// The usual search: from zero to four times the realistic range's far end. Beyond, the
/// physics is no longer the effect's and the runs crawl.
pub(crate) fn usual_search((_, hi): (f64, f64), _mu_max: f64) -> (f64, f64) {
    (0.0, 4.0 * hi)
}

/// No more starts than the scan's.
pub(crate) fn no_blind(_: (f64, f64), _: f64, _: bool) -> Vec<f64> {
    Vec::new()
}

/// Three significant digits, plain notation where readable.
pub fn sig(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let mag = v.abs().log10().floor() as i32;
    if (-4..6).contains(&mag) {
        format!("{:.*}", (2 - mag).max(0) as usize, v)
    } else {
        format!("{v:.2e}")
    }
}

/// A value and its sigma in words.
pub fn pm(v: f64, s: f64) -> String {
    if s.is_finite() {
        format!("{} +- {}", sig(v), sig(s))
    } else {
        format!("{} (uncertainty unknown)", sig(v))
    }
}

/// A length in mm, three significant digits.
pub(crate) fn mm(v: f64) -> String {
    format!("{} mm", sig(v))
}

/// No words beyond the signature's own.
pub(crate) fn no_words(_: &Words) -> String {
    String::new()
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

    #[test]
    fn extras_start_inside_their_bounds() {
        for k in EffectKind::ALL {
            for x in k.descriptor().extras {
                assert!((x.bounds.0..=x.bounds.1).contains(&x.start), "{k}: {}", x.name);
            }
        }
    }
}
