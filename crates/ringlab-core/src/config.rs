//! Case files: a body, its drag, a start state and run settings, in TOML.
//!
//! Presets live in `assets/presets/*.toml` (documented there, user-editable) and are also
//! compiled in, so the binary works from any directory. Lookup order for `--preset NAME`:
//! `$RINGLAB_PRESETS/NAME.toml`, then the source tree's `assets/presets/NAME.toml`, then
//! the compiled-in copy.
//!
//! Units: `[units] system = "model"` (the paper's: lengths in mean radii, `g` given, time
//! unit then follows) or `"mm"` (mm, s, `g = 9810 mm/s^2`). Angles are in rad, rates in rad
//! per time unit. Drag coefficients are dimensionless in both.

use crate::physics::effects::table_slope::TableSlope;
use crate::physics::integrator::Tolerances;
use crate::physics::{
    Body, Conversion, Effects, Initial, Model, ReynoldsDrag, RunOptions, Shape, SlipStart, Units,
};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use thiserror::Error;

#[derive(Debug, Error)]
pub enum ConfigError {
    #[error("cannot read {path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    #[error("{path}: {message}")]
    Parse { path: PathBuf, message: String },
    #[error("{path}: {message}")]
    Invalid { path: PathBuf, message: String },
    #[error("cannot write {path}: {source}")]
    Write { path: PathBuf, source: std::io::Error },
    #[error("unknown preset '{name}'; available: {available}")]
    UnknownPreset { name: String, available: String },
}

/// Compiled-in presets (name, TOML text).
pub const BUILTIN_PRESETS: &[(&str, &str)] = &[
    ("paper-ring", include_str!("../assets/presets/paper-ring.toml")),
    ("paper-disk-drag", include_str!("../assets/presets/paper-disk-drag.toml")),
    ("steel-ring", include_str!("../assets/presets/steel-ring.toml")),
    ("aluminium-disk", include_str!("../assets/presets/aluminium-disk.toml")),
    ("coin", include_str!("../assets/presets/coin.toml")),
    ("wedding-ring", include_str!("../assets/presets/wedding-ring.toml")),
];

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CaseFile {
    pub name: String,
    #[serde(default)]
    pub description: String,
    /// Where the numbers come from.
    #[serde(default)]
    pub source: String,
    pub units: UnitsSection,
    pub body: BodySection,
    pub drag: DragSection,
    pub initial: InitialSection,
    #[serde(default)]
    pub run: RunSection,
    #[serde(default, skip_serializing_if = "EffectsSection::is_off")]
    pub effects: EffectsSection,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct UnitsSection {
    /// "model" or "mm".
    pub system: String,
    /// Model units: the length unit (mean radius) in mm.
    pub mean_radius_mm: Option<f64>,
    /// Model units: gravity in model units.
    pub g: Option<f64>,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BodySection {
    pub shape: String,
    pub outer_radius: f64,
    pub width: f64,
    #[serde(default)]
    pub thickness: Option<f64>,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DragSection {
    pub c: [f64; 3],
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct InitialSection {
    pub theta: f64,
    #[serde(default)]
    pub theta_dot: f64,
    #[serde(default)]
    pub phi: f64,
    pub phi_dot: f64,
    #[serde(default)]
    pub psi: f64,
    #[serde(default)]
    pub psi_dot: f64,
    #[serde(default)]
    pub x: f64,
    #[serde(default)]
    pub y: f64,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct RunSection {
    pub t_end: f64,
    pub mu: f64,
    pub dt: f64,
    pub rtol: f64,
    pub atol: f64,
    pub theta_flat: f64,
}

impl Default for RunSection {
    fn default() -> Self {
        let d = RunOptions::default();
        RunSection {
            t_end: d.t_end,
            mu: d.mu,
            dt: 0.05,
            rtol: d.tol.rtol,
            atol: d.tol.atol,
            theta_flat: d.theta_flat,
        }
    }
}

/// `[effects]`: the physics beyond the paper's model in the case's own units (the CLI's
/// `--effect NAME --effect-strength X` sets the same fields from dimensionless strengths, see
/// `physics::effects::apply`).
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct EffectsSection {
    /// `[re_ref, exponent, max_factor]`: `C_i min((re_ref / Re)^exponent, max_factor)`.
    pub reynolds_drag: Option<[f64; 3]>,
    /// Rolling-resistance arm (length).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub rolling_friction: f64,
    /// Pivot-friction arm (length).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub pivot_friction: f64,
    /// Quadratic air drag on the centre of mass, `k` in `-k |v_C| v_C` (1/length).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub translational_drag: f64,
    /// Friction coefficient of the sliding contact, static and kinetic (absent: pure rolling).
    pub slip_mu: Option<f64>,
    /// With `slip_mu`: a start that needs more friction than `mu F_N` rolls on until it needs
    /// no more (as an event-driven hybrid simulator started rolling does) instead of sliding
    /// at once (`physics::SlipStart`).
    #[serde(default, skip_serializing_if = "is_false")]
    pub slip_start_held: bool,
    /// `[angle, direction]` in degrees: a table tilted from level by `angle` toward
    /// `direction` (from the table's +X axis, turning toward +Y), see `effects/table_slope.rs`.
    pub table_slope: Option<[f64; 2]>,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

fn is_false(b: &bool) -> bool {
    !*b
}

impl EffectsSection {
    /// The paper's model: nothing beyond it (a saved case then has no `[effects]`).
    pub fn is_off(&self) -> bool {
        *self == EffectsSection::default()
    }
}

/// A validated case, ready to run.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    pub name: String,
    pub description: String,
    pub units: Units,
    pub model: Model,
    pub initial: Initial,
    pub opts: RunOptions,
    /// Output spacing for samples.
    pub dt: f64,
}

impl CaseFile {
    pub fn parse(text: &str, path: &Path) -> Result<CaseFile, ConfigError> {
        toml::from_str(text)
            .map_err(|e| ConfigError::Parse { path: path.to_path_buf(), message: e.to_string() })
    }

    pub fn units(&self) -> Result<Units, String> {
        match self.units.system.as_str() {
            "mm" => {
                if self.units.mean_radius_mm.is_some() || self.units.g.is_some() {
                    return Err("[units] mean_radius_mm and g belong to system = \"model\"; mm units use g = 9810 mm/s^2".into());
                }
                Ok(Units::MM_S)
            }
            "model" => {
                let l = self
                    .units
                    .mean_radius_mm
                    .ok_or("[units] system = \"model\" needs mean_radius_mm")?;
                let g = self.units.g.ok_or("[units] system = \"model\" needs g")?;
                if !(l.is_finite() && l > 0.0) {
                    return Err(format!("[units] mean_radius_mm = {l} must be a positive number"));
                }
                if !(g.is_finite() && g > 0.0) {
                    return Err(format!("[units] g = {g} must be a positive number"));
                }
                Ok(Units::dimensionless(l, g))
            }
            other => Err(format!("[units] system = \"{other}\" is not one of \"model\", \"mm\"")),
        }
    }

    /// Validates everything and builds the case.
    pub fn build(&self) -> Result<Case, String> {
        let units = self.units()?;
        let shape = Shape::parse(&self.body.shape).ok_or_else(|| {
            format!("[body] shape = \"{}\" is not one of \"ring\", \"disk\"", self.body.shape)
        })?;
        let w = match (shape, self.body.thickness) {
            (Shape::Ring, None) => {
                return Err("[body] a ring needs thickness (wall thickness w)".into());
            }
            (Shape::Ring, Some(w)) => w,
            (Shape::Disk, w) => w.unwrap_or(self.body.outer_radius),
        };
        let body = Body::new(shape, self.body.outer_radius, self.body.width, w)
            .map_err(|e| format!("[body] {e}"))?;
        let model = Model::new(body, units.g(), self.drag.c, units.nu_air())
            .map_err(|e| format!("[drag] {e}"))?;
        let e = &self.effects;
        let effects = Effects {
            reynolds_drag: e.reynolds_drag.map(|[re_ref, exponent, max_factor]| ReynoldsDrag {
                re_ref,
                exponent,
                max_factor,
                rim_share: 0.0,
            }),
            rolling_friction: e.rolling_friction,
            pivot_friction: e.pivot_friction,
            translational_drag: e.translational_drag,
            slip_mu: e.slip_mu,
            slip_start: if e.slip_start_held { SlipStart::HeldRolling } else { SlipStart::Cone },
            table_slope: e.table_slope.map(|[angle, direction]| TableSlope {
                angle: angle.to_radians(),
                direction: direction.to_radians(),
            }),
            ..Default::default()
        };
        let model = model.with_effects(effects).map_err(|e| format!("[effects] {e}"))?;
        let i = &self.initial;
        let initial = Initial {
            phi: i.phi,
            theta: i.theta,
            psi: i.psi,
            theta_dot: i.theta_dot,
            phi_dot: i.phi_dot,
            psi_dot: i.psi_dot,
            x_c: i.x,
            y_c: i.y,
        };
        initial.validate().map_err(|e| format!("[initial] {e}"))?;
        let r = &self.run;
        let opts = RunOptions {
            t_end: r.t_end,
            tol: Tolerances { rtol: r.rtol, atol: r.atol },
            theta_flat: r.theta_flat,
            mu: r.mu,
            sample_dt: Some(r.dt),
            ..RunOptions::default()
        };
        opts.validate().map_err(|e| format!("[run] {e}"))?;
        Ok(Case {
            name: self.name.clone(),
            description: self.description.clone(),
            units,
            model,
            initial,
            opts,
            dt: r.dt,
        })
    }
}

/// Reads and validates a case file.
pub fn load_case_file(path: &Path) -> Result<CaseFile, ConfigError> {
    let text = std::fs::read_to_string(path)
        .map_err(|source| ConfigError::Io { path: path.to_path_buf(), source })?;
    let file = CaseFile::parse(&text, path)?;
    file.build().map_err(|message| ConfigError::Invalid { path: path.to_path_buf(), message })?;
    Ok(file)
}

/// What a saved case file starts with (comments; the rest is the case, as the presets have it).
const SAVED_HEADER: &str = "\
# A ringlab case (the shape of assets/presets/*.toml), saved by the window's File > Save case.
# `ringlab --config FILE` opens it in the window, `ringlab simulate --config FILE` runs it.
# Units: [units] system \"model\" (lengths in mean radii) or \"mm\" (mm, s); angles in rad.

";

impl CaseFile {
    /// The case as TOML text in the presets' shape (sections in the same order), with a
    /// header saying what it is. Reading it back gives the same case, number for number.
    pub fn to_toml(&self) -> Result<String, String> {
        let body = toml::to_string(self).map_err(|e| e.to_string())?;
        Ok(format!("{SAVED_HEADER}{body}"))
    }
}

/// Writes `file` to `path` (File > Save case). A case that does not build is refused: the
/// file would not open again.
pub fn save_case_file(path: &Path, file: &CaseFile) -> Result<(), ConfigError> {
    let invalid = |message: String| ConfigError::Invalid { path: path.to_path_buf(), message };
    file.build().map_err(|m| invalid(format!("the case is not valid, not saved: {m}")))?;
    let text = file.to_toml().map_err(invalid)?;
    std::fs::write(path, text)
        .map_err(|source| ConfigError::Write { path: path.to_path_buf(), source })
}

/// Names of all presets.
pub fn preset_names() -> Vec<&'static str> {
    BUILTIN_PRESETS.iter().map(|p| p.0).collect()
}

/// Finds a preset by name (see the module doc for the lookup order).
pub fn load_preset(name: &str) -> Result<CaseFile, ConfigError> {
    let file_name = format!("{name}.toml");
    let mut dirs: Vec<PathBuf> = Vec::new();
    if let Some(d) = std::env::var_os("RINGLAB_PRESETS") {
        dirs.push(PathBuf::from(d));
    }
    dirs.push(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/presets"));
    for d in dirs {
        let p = d.join(&file_name);
        if p.is_file() {
            return load_case_file(&p);
        }
    }
    match BUILTIN_PRESETS.iter().find(|p| p.0 == name) {
        Some((_, text)) => {
            let path = PathBuf::from(format!("<built-in preset {name}>"));
            let file = CaseFile::parse(text, &path)?;
            file.build().map_err(|message| ConfigError::Invalid { path, message })?;
            Ok(file)
        }
        None => Err(ConfigError::UnknownPreset {
            name: name.to_string(),
            available: preset_names().join(", "),
        }),
    }
}

impl Case {
    /// The same case in other units (see [`Conversion`]): lengths and positions scale by the
    /// length factor, times by the time factor, rates by its inverse; angles and the drag
    /// coefficients `C_i` are unchanged; `g` and air's viscosity come from the new units.
    pub fn in_units(&self, to: Units) -> Result<Case, String> {
        let k = Conversion::between(self.units, to);
        let b = &self.model.body;
        let body = Body::new(b.shape, b.r * k.length, b.h * k.length, b.w * k.length)
            .map_err(|e| e.to_string())?;
        let effects = self.model.effects.in_units(k.length, k.time);
        let model = Model::new(body, to.g(), self.model.c_drag, to.nu_air())
            .and_then(|m| m.with_effects(effects))
            .map_err(|e| e.to_string())?;
        let i = &self.initial;
        let initial = Initial {
            phi: i.phi,
            theta: i.theta,
            psi: i.psi,
            theta_dot: i.theta_dot * k.rate(),
            phi_dot: i.phi_dot * k.rate(),
            psi_dot: i.psi_dot * k.rate(),
            x_c: i.x_c * k.length,
            y_c: i.y_c * k.length,
        };
        let mut opts = self.opts.clone();
        opts.t_end *= k.time;
        opts.sample_dt = opts.sample_dt.map(|dt| dt * k.time);
        opts.h_max *= k.time;
        // Lengths change scale: keep the absolute tolerance relative to the body's size.
        opts.tol.atol *= k.length.min(1.0);
        Ok(Case {
            name: self.name.clone(),
            description: self.description.clone(),
            units: to,
            model,
            initial,
            opts,
            dt: self.dt * k.time,
        })
    }
}
