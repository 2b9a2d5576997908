//! `ringlab._core`: the extension module under the Python package `ringlab` (python/ringlab),
//! over ringlab-core. Each function here is the core call the CLI makes, with the CLI's checks
//! and its JSON; the package's Python side turns the JSON into typed objects and the bytes into
//! numpy arrays. Long calls (fit, diagnose) run without the GIL and stop on Ctrl-C (`worker`).

mod case;
mod errors;
mod recording;
mod series;
mod worker;

use errors::{FitError, RecordingError, diagnose_error, fit_error};
use pyo3::exceptions::{PyKeyboardInterrupt, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use recording::PyRecording;
use ringlab_core::analysis::diagnose::{
    DiagnoseError, DiagnoseOptions, DiagnoseProgress, diagnose as core_diagnose,
};
use ringlab_core::analysis::fit::{FitOptions, FitProgress, FitStage, fit as core_fit};
use ringlab_core::physics::{EffectKind, Sample, Simulation};
use ringlab_core::recording::marks::MarkOrder;
use ringlab_core::recording::synth::{SynthOptions, synthesize};
use ringlab_core::report::{CSV_COLUMNS, RunReport, analyze};
use std::path::PathBuf;
use std::time::Instant;

fn to_json(v: &impl serde::Serialize) -> PyResult<String> {
    serde_json::to_string(v).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// One run of the model: (the summary as `simulate --json`'s JSON, the samples as the bytes of
/// a float64 array (rows, columns) in the columns of `simulate --out`, the columns).
#[pyfunction]
#[pyo3(signature = (preset=None, config=None, overrides=Vec::new(), effects=Vec::new(), slip_start=None))]
fn simulate<'py>(
    py: Python<'py>,
    preset: Option<String>,
    config: Option<PathBuf>,
    overrides: Vec<(String, f64)>,
    effects: Vec<(String, f64)>,
    slip_start: Option<String>,
) -> PyResult<(String, Bound<'py, PyBytes>, Vec<&'static str>)> {
    let mut case = case::case(preset.as_deref(), config, &overrides)?;
    let named = case::apply_effects(&mut case, &effects, slip_start.as_deref())?;
    let (report, samples) = py
        .detach(|| -> Result<_, String> {
            let start = Sample::new(&case.model, 0.0, &case.initial.to_state());
            let clock = Instant::now();
            let sim = Simulation::new(case.model.clone(), &case.initial, case.opts.clone())
                .map_err(|e| e.to_string())?;
            let mut samples = Vec::new();
            let summary = sim.run(&mut |s| samples.push(*s));
            let motion = analyze(&start, &summary);
            let seconds = clock.elapsed().as_secs_f64();
            let mut report = RunReport::new(
                &case.name,
                case.units.label(),
                case.opts.mu,
                &start,
                &summary,
                &motion,
                seconds,
            );
            report.set_effects(&case.model.effects, &named);
            Ok((report, samples))
        })
        .map_err(PyValueError::new_err)?;
    // The row of `report::write_samples_csv`, column for column.
    let mut out: Vec<u8> = Vec::with_capacity(samples.len() * CSV_COLUMNS.len() * 8);
    for s in &samples {
        let row = ringlab_core::report::sample_row(s);
        debug_assert_eq!(row.len(), CSV_COLUMNS.len());
        for v in row {
            out.extend_from_slice(&v.to_ne_bytes());
        }
    }
    Ok((to_json(&report)?, PyBytes::new(py, &out), CSV_COLUMNS.to_vec()))
}

/// A recording made from the model (`ringlab synth`), with the run's end as JSON.
#[pyfunction]
#[pyo3(signature = (preset=None, config=None, overrides=Vec::new(), noise_px=0.5, fps=300.0, px_per_mm=None, lens_k1=0.0, effect=None, effect_strength=None, effect_extras=Vec::new(), slip_start=None, seed=1, rest_frames=60, image_size=(1280.0, 1024.0), drop_marks=0.0, reverse_marks=false, camera_distance_mm=None, camera_tilt_deg=0.0, camera_in_header=false))]
#[allow(clippy::too_many_arguments)]
fn synth(
    py: Python<'_>,
    preset: Option<String>,
    config: Option<PathBuf>,
    overrides: Vec<(String, f64)>,
    noise_px: f64,
    fps: f64,
    px_per_mm: Option<f64>,
    lens_k1: f64,
    effect: Option<String>,
    effect_strength: Option<f64>,
    effect_extras: Vec<f64>,
    slip_start: Option<String>,
    seed: u64,
    rest_frames: usize,
    image_size: (f64, f64),
    drop_marks: f64,
    reverse_marks: bool,
    camera_distance_mm: Option<f64>,
    camera_tilt_deg: f64,
    camera_in_header: bool,
) -> PyResult<PyRecording> {
    let mut case = case::case(preset.as_deref(), config, &overrides)?;
    let effect = match (effect.as_deref(), effect_strength) {
        (None, None) => None,
        (None, Some(_)) => {
            return Err(PyValueError::new_err("effect_strength needs effect (a name)"));
        }
        (Some(name), strength) => match (case::effect_kind(name, "effect")?, strength) {
            (EffectKind::None, _) => None,
            (kind, None) => {
                return Err(PyValueError::new_err(format!(
                    "effect {name} needs effect_strength ({})",
                    kind.parameter()
                )));
            }
            (kind, Some(x)) => Some((kind, x)),
        },
    };
    if !effect_extras.is_empty() && effect.is_none() {
        return Err(PyValueError::new_err("effect_extras needs effect (a name)"));
    }
    let slip = effect.is_some_and(|(k, _)| k == EffectKind::Slip);
    if let Some(start) = case::slip_start(slip_start.as_deref(), slip)? {
        case.model.effects.slip_start = start;
    }
    let defaults = SynthOptions::default();
    let opts = SynthOptions {
        fps,
        px_per_mm: px_per_mm.unwrap_or(defaults.px_per_mm),
        noise_px,
        lens_k1,
        effect,
        effect_extras,
        seed,
        rest_frames,
        image_width_px: image_size.0,
        image_height_px: image_size.1,
        mark_order: if reverse_marks { MarkOrder::Reverse } else { MarkOrder::Forward },
        missing_fraction: drop_marks,
        camera_distance_mm,
        camera_tilt_deg,
        camera_in_header,
    };
    // Option errors are the caller's parameters; a model that cannot run is too (its case).
    let synth = py.detach(|| synthesize(&case, &opts)).map_err(|e| {
        PyValueError::new_err(format!("synthesizing a recording of case '{}': {e}", case.name))
    })?;
    Ok(PyRecording::new(synth.recording, format!("synth of {}", case.name), "ringlab synth"))
}

/// `ringlab fit`: the fit as `fit --json`'s JSON, with the model's marks and residuals frame
/// by frame (`series::fit_arrays`).
#[pyfunction]
#[pyo3(signature = (rec, segment_frames=60, merges=2, coarse=true, c_start=None, effect=None, effect_start=0.0, lens_k1=0.0, progress=None, threads=None))]
#[allow(clippy::too_many_arguments)]
fn fit<'py>(
    py: Python<'py>,
    rec: &PyRecording,
    segment_frames: usize,
    merges: usize,
    coarse: bool,
    c_start: Option<[f64; 3]>,
    effect: Option<String>,
    effect_start: f64,
    lens_k1: f64,
    progress: Option<Bound<'_, PyAny>>,
    threads: Option<usize>,
) -> PyResult<(String, series::Arrays<'py>)> {
    let defaults = FitOptions::default();
    let c_start = c_start.unwrap_or(defaults.c_start);
    if c_start.iter().any(|c| !(c.is_finite() && *c > 0.0)) {
        return Err(PyValueError::new_err(format!(
            "c_start = {c_start:?}: every coefficient must be a positive number"
        )));
    }
    let effect = match effect {
        None => None,
        Some(name) => {
            let kind = case::effect_kind(&name, "effect")?;
            (kind != EffectKind::None).then_some((kind, effect_start))
        }
    };
    if !lens_k1.is_finite() {
        return Err(PyValueError::new_err(format!("lens_k1 = {lens_k1}: must be a finite number")));
    }
    if !effect_start.is_finite() {
        return Err(PyValueError::new_err(format!(
            "effect_start = {effect_start}: must be a finite number"
        )));
    }
    let opts = FitOptions { segment_frames, merges, c_start, coarse, effect, lens_k1, ..defaults };
    let recording = &rec.rec;
    let result = worker::run(py, progress.as_ref(), threads, |report, cancel| {
        // The CLI's bar: the stage (and the misfit while refining), done of total.
        let on_progress = |p: &FitProgress| {
            let msg = match (p.stage, p.rms_px) {
                (FitStage::Refine, Some(rms)) => format!("{} {rms:.3} px", p.stage.describe()),
                (stage, _) => stage.describe().to_string(),
            };
            let within = if p.total > 0 { p.done as f64 / p.total as f64 } else { 0.0 };
            report((p.stage as usize as f64 + within.min(1.0)) / 5.0, msg);
        };
        core_fit(recording, &opts, &on_progress, cancel)
    })?;
    match result {
        Ok(r) => Ok((
            to_json(&ringlab_core::analysis::json::FitReport::new(&r))?,
            series::fit_arrays(py, &r, recording),
        )),
        // Cancelled only by our flag, which only Ctrl-C (raised above) sets.
        Err(ringlab_core::analysis::fit::FitError::Cancelled) => {
            Err(PyKeyboardInterrupt::new_err("the fit was cancelled"))
        }
        Err(e) => Err(fit_error(&format!("fitting {}", rec.name), &e)),
    }
}

/// `ringlab diagnose`: the diagnosis as `diagnose --json`'s JSON, the signature of its
/// mismatch as JSON, and the series its plots show (`series::diagnosis_arrays`).
#[pyfunction]
#[pyo3(signature = (rec, candidates=None, evidence=None, progress=None, threads=None))]
fn diagnose<'py>(
    py: Python<'py>,
    rec: &PyRecording,
    candidates: Option<Vec<String>>,
    evidence: Option<f64>,
    progress: Option<Bound<'_, PyAny>>,
    threads: Option<usize>,
) -> PyResult<(String, String, series::Arrays<'py>)> {
    let mut opts = DiagnoseOptions::default();
    if let Some(x) = evidence {
        if !(x.is_finite() && x >= 0.0) {
            return Err(PyValueError::new_err(format!("evidence = {x}: must be a number >= 0")));
        }
        opts.evidence = x;
    }
    if let Some(names) = candidates {
        // As `--candidates`: names checked, `none` and repeats dropped.
        let mut list = Vec::new();
        for name in names.iter().map(|s| s.trim()).filter(|s| !s.is_empty()) {
            let kind = case::effect_kind(name, "candidates:")?;
            if kind != EffectKind::None && !list.contains(&kind) {
                list.push(kind);
            }
        }
        opts.candidates = list;
    }
    let recording = &rec.rec;
    let result = worker::run(py, progress.as_ref(), threads, |report, cancel| {
        let on_progress =
            |p: &DiagnoseProgress| report(p.fraction.clamp(0.0, 1.0), p.message.clone());
        core_diagnose(recording, &opts, &on_progress, cancel)
    })?;
    match result {
        Ok(d) => Ok((
            to_json(&ringlab_core::analysis::json::DiagnoseJson::new(&d))?,
            to_json(&d.signature)?,
            series::diagnosis_arrays(py, &d),
        )),
        Err(DiagnoseError::Cancelled) => {
            Err(PyKeyboardInterrupt::new_err("the diagnosis was cancelled"))
        }
        Err(e) => Err(diagnose_error(&format!("diagnosing {}", rec.name), &e)),
    }
}

/// The presets' names.
#[pyfunction]
fn presets() -> Vec<&'static str> {
    ringlab_core::config::preset_names()
}

/// The effects beyond the paper's model: (name, what its strength is, a camera's or not).
#[pyfunction]
fn effects() -> Vec<(&'static str, &'static str, bool)> {
    EffectKind::ALL.iter().map(|k| (k.name(), k.parameter(), k.is_camera())).collect()
}

#[pymodule(name = "_core")]
fn core_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("RecordingError", py.get_type::<RecordingError>())?;
    m.add("FitError", py.get_type::<FitError>())?;
    m.add_class::<PyRecording>()?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(synth, m)?)?;
    m.add_function(wrap_pyfunction!(fit, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose, m)?)?;
    m.add_function(wrap_pyfunction!(presets, m)?)?;
    m.add_function(wrap_pyfunction!(effects, m)?)?;
    m.add("DEFAULT_EVIDENCE", ringlab_core::analysis::diagnose::DEFAULT_EVIDENCE)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
