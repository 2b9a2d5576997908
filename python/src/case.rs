//! The case a run or a synthesized recording starts from: a preset or a case file, with the
//! CLI's overrides (`--c1 .. --atol`) and effects (`--effect NAME --effect-strength X`) as
//! keyword arguments.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use ringlab_core::config::{Case, CaseFile, load_case_file, load_preset};
use ringlab_core::physics::effects::apply;
use ringlab_core::physics::slip::painleve_mu_limit;
use ringlab_core::physics::{EffectKind, Sample, SlipStart};
use std::path::PathBuf;

/// The overrides, by the names of `simulate`'s keyword arguments (the CLI's flags).
pub const OVERRIDES: [&str; 13] = [
    "c1",
    "c2",
    "c3",
    "theta0",
    "thetadot0",
    "phidot0",
    "psidot0",
    "phi0",
    "mu",
    "t_end",
    "dt",
    "rtol",
    "atol",
];

fn known_effects() -> String {
    EffectKind::ALL.iter().map(|k| k.name()).collect::<Vec<_>>().join(", ")
}

/// An effect by name, or a `ValueError` listing the names.
pub fn effect_kind(name: &str, what: &str) -> PyResult<EffectKind> {
    EffectKind::from_name(name).ok_or_else(|| {
        PyValueError::new_err(format!("{what} '{name}' is not one of {}", known_effects()))
    })
}

/// `slip_start`: "cone" or "held", only with slip.
pub fn slip_start(name: Option<&str>, slip: bool) -> PyResult<Option<SlipStart>> {
    match name {
        None => Ok(None),
        Some(_) if !slip => Err(PyValueError::new_err(
            "slip_start needs the effect slip (it says how sliding begins)",
        )),
        Some("cone") => Ok(Some(SlipStart::Cone)),
        Some("held") => Ok(Some(SlipStart::HeldRolling)),
        Some(other) => {
            Err(PyValueError::new_err(format!("slip_start = '{other}': not 'cone' or 'held'")))
        }
    }
}

/// The case file with the overrides applied (not yet validated as a whole).
fn case_file(
    preset: Option<&str>,
    config: Option<PathBuf>,
    overrides: &[(String, f64)],
) -> PyResult<CaseFile> {
    let mut f = match (preset, config) {
        (Some(_), Some(_)) => {
            return Err(PyValueError::new_err("give either preset or config, not both"));
        }
        (_, Some(path)) => load_case_file(&path),
        (Some(name), None) => load_preset(name),
        (None, None) => load_preset("paper-ring"),
    }
    .map_err(|e| PyValueError::new_err(e.to_string()))?;
    for (name, v) in overrides {
        if !v.is_finite() {
            return Err(PyValueError::new_err(format!("{name} = {v}: must be a finite number")));
        }
        let slot = match name.as_str() {
            "c1" => &mut f.drag.c[0],
            "c2" => &mut f.drag.c[1],
            "c3" => &mut f.drag.c[2],
            "theta0" => &mut f.initial.theta,
            "thetadot0" => &mut f.initial.theta_dot,
            "phidot0" => &mut f.initial.phi_dot,
            "psidot0" => &mut f.initial.psi_dot,
            "phi0" => &mut f.initial.phi,
            "mu" => &mut f.run.mu,
            "t_end" => &mut f.run.t_end,
            "dt" => &mut f.run.dt,
            "rtol" => &mut f.run.rtol,
            "atol" => &mut f.run.atol,
            other => {
                return Err(PyValueError::new_err(format!(
                    "unknown override '{other}': one of {}",
                    OVERRIDES.join(", ")
                )));
            }
        };
        *slot = *v;
    }
    Ok(f)
}

/// The validated case.
pub fn case(
    preset: Option<&str>,
    config: Option<PathBuf>,
    overrides: &[(String, f64)],
) -> PyResult<Case> {
    let f = case_file(preset, config, overrides)?;
    f.build().map_err(|m| {
        PyValueError::new_err(format!("case '{}' with the given overrides: {m}", f.name))
    })
}

/// Switches the physical effects on in `case`, as `simulate --effect` does (a camera's effect
/// is refused: it belongs to a recording, give it to `synth`); returns them as given.
pub fn apply_effects(
    case: &mut Case,
    effects: &[(String, f64)],
    slip_start_name: Option<&str>,
) -> PyResult<Vec<(EffectKind, f64)>> {
    let mut named: Vec<(EffectKind, f64)> = Vec::new();
    for (name, x) in effects {
        let kind = effect_kind(name, "effect")?;
        if named.iter().any(|(k, _)| *k == kind) {
            return Err(PyValueError::new_err(format!("effect {kind} is given twice")));
        }
        if !x.is_finite() {
            return Err(PyValueError::new_err(format!(
                "strength {x} for {kind}: must be a finite number"
            )));
        }
        if kind != EffectKind::None {
            named.push((kind, *x));
        }
    }
    let slip = named.iter().any(|(k, _)| *k == EffectKind::Slip);
    if let Some(start) = slip_start(slip_start_name, slip)? {
        case.model.effects.slip_start = start;
    }
    let start = Sample::new(&case.model, 0.0, &case.initial.to_state());
    for &(kind, x) in &named {
        if kind.is_camera() {
            return Err(PyValueError::new_err(format!(
                "effect {kind} changes the camera, not the motion: give it to ringlab.synth"
            )));
        }
        let mut e = case.model.effects;
        apply(kind, x, case.model.body.r, start.reynolds, &mut e).map_err(|err| {
            PyValueError::new_err(format!("strength {x} for {kind} ({}): {err}", kind.parameter()))
        })?;
        let mut model = case.model.clone();
        model.effects = e;
        if let Err(err) = model.check_effects() {
            if kind == EffectKind::Slip {
                return Err(PyValueError::new_err(format!(
                    "strength {x} for slip: {err}; for this body mu must stay below {:.3}",
                    painleve_mu_limit(&model)
                )));
            }
            return Err(PyValueError::new_err(format!("strength {x} for {kind}: {err}")));
        }
        case.model = model;
    }
    Ok(named)
}
