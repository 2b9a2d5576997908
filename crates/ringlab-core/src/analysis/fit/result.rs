//! What a fit found, and the fitted model run again.

use super::last_runs::LastRuns;
use super::params::{Free, ModelSpec, StartReynolds};
use super::shooting::{NEVER_CANCELLED, Shooting};
use crate::physics::effects::EffectKind;
use crate::physics::run::RunError;
use crate::physics::{Initial, Model, RunOptions, RunSummary, Sample, Simulation, StateVec, Units};
use crate::recording::glitches::Glitch;
use crate::recording::marks::MarkGeometry;
use crate::recording::{Camera, FrameMarks};
use std::ops::Range;
use std::sync::atomic::AtomicBool;

/// What a fit found.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct FitResult {
    pub c: [f64; 3],
    /// One standard deviation (infinite where the data do not constrain it).
    pub c_sigma: [f64; 3],
    /// A fitted effect: kind, strength and its sigma.
    pub effect: Option<(EffectKind, f64, f64)>,
    /// The start state at the first inner turning point (model units).
    pub start: Initial,
    /// Its time (model units, frame `i` at `i dt`) and fractional frame index.
    pub start_t: f64,
    pub start_frame: f64,
    /// RMS of model minus recording over every tracked mark coordinate fitted (px).
    pub rms_px: f64,
    pub residual_count: usize,
    pub parameter_count: usize,
    /// Frames in the recording.
    pub frames: usize,
    /// Frames fitted: from the start to the still end (the still frames show only the pose
    /// in which the ring landed, which the model's flat limit gives to a frame at best).
    pub frames_fitted: usize,
    /// The pixel noise per coordinate from the marks' tracks alone (`recording::noise`).
    pub noise_px: Option<f64>,
    /// The tracker's glitches left out of the fit.
    pub glitches: Vec<Glitch>,
    pub segments: Vec<Range<usize>>,
    pub segment_states: Vec<StateVec>,
    pub coarse_c: Option<[f64; 3]>,
    pub iterations: usize,
    /// The fitted model and camera (model units).
    pub model: Model,
    pub camera: Camera,
    pub units: Units,
    /// Model time per frame.
    pub dt: f64,
    /// The marks' circle in model units.
    pub geometry: MarkGeometry,
    /// Reynolds number at the start (the reference of `reynolds_drag`).
    pub re_start: StartReynolds,
    /// The integration settings of the fit's runs.
    pub run: RunOptions,
    pub compute_seconds: f64,
}

impl FitResult {
    /// The fit's multiple-shooting problem at its final segments, with the drag free (the
    /// fitted model as the base): for refits that start where this fit ended (the diagnosis),
    /// stopped by `cancel`.
    pub fn shooting<'a>(&self, observed: &'a [FrameMarks], cancel: &'a AtomicBool) -> Shooting<'a> {
        let free = (0..3).map(Free::Drag).collect();
        Shooting {
            observed,
            segments: self.segments.clone(),
            dt: self.dt,
            spec: ModelSpec {
                base: self.model.clone(),
                camera: self.camera,
                free,
                re_start: self.re_start,
                strength_ranges: Vec::new(),
            },
            run: self.run.clone(),
            geometry: self.geometry,
            length_mm: self.units.length_mm,
            budget: None,
            last_runs: LastRuns::default(),
            cancel,
        }
    }

    /// The fitted model's four marks in pixels at every frame its segments cover (each
    /// segment from its fitted state), `None` elsewhere: what is drawn over the film.
    pub fn predicted_marks(&self, observed: &[FrameMarks]) -> Vec<Option<[[f64; 2]; 4]>> {
        let mut out = vec![None; observed.len()];
        let shooting = self.shooting(observed, &NEVER_CANCELLED);
        for (s, range) in self.segments.iter().enumerate() {
            let Some(state) = self.segment_states.get(s) else { continue };
            if let Some(marks) = shooting.predict(&self.model, &self.camera, s, state) {
                for (i, m) in range.clone().zip(marks) {
                    if let Some(slot) = out.get_mut(i) {
                        *slot = Some(m);
                    }
                }
            }
        }
        out
    }

    /// The fitted model run from the fitted start to its end, sampled at the recording's
    /// frames (`t = start_t + k dt`): the model's path to show beside the recording's (same
    /// table coordinates, model units; the recording's are in mm).
    pub fn model_run(&self) -> Result<(RunSummary, Vec<Sample>), RunError> {
        let opts = RunOptions { sample_dt: Some(self.dt), ..RunOptions::default() };
        let sim =
            Simulation::from_state(self.model.clone(), self.start_t, self.start.to_state(), opts)?;
        let mut samples = Vec::new();
        let summary = sim.run(&mut |s| samples.push(*s));
        Ok((summary, samples))
    }
}
