//! Recordings made from the model: `ringlab synth`, the tests, and the diagnosis's test data.
//!
//! Made the way `data/sample-ring.csv` was made (checked against its truth: the centroid of
//! its marks follows the truth run to 0.25 px per axis, the noise of four marks averaged):
//! frame `n` is the model at `t = n / fps` from the case's start; the marks (see
//! [`super::marks`]) are projected straight down with the table's origin at the image centre,
//! `y` downward; Gaussian noise of `noise_px` is added to each coordinate. When the run ends
//! naturally (flat or at rest) after `t_end`, frames `0 .. floor(t_end fps)` show the motion and
//! then `rest_frames` more show the final pose, still (the sample: 1824 + 60 frames).

use super::camera::Camera;
use super::marks::{MarkGeometry, MarkOrder, mark_radius};
use super::rng::Rng;
use super::{FrameMarks, Header, MARKS, Recording};
use crate::config::Case;
use crate::physics::effects::{self, EffectKind};
use crate::physics::run::RunError;
use crate::physics::{Conversion, ParamError, RunSummary, Sample, Simulation, Units};
use thiserror::Error;

/// The paper's camera scale: 135.6 px = 40.3 mm.
pub const PAPER_PX_PER_MM: f64 = 135.6 / 40.3;

#[derive(Clone, Debug, PartialEq)]
pub struct SynthOptions {
    pub fps: f64,
    pub px_per_mm: f64,
    /// Standard deviation of the Gaussian noise on each pixel coordinate.
    pub noise_px: f64,
    /// Radial lens distortion (see [`super::camera`]).
    pub lens_k1: f64,
    /// An effect beyond the baseline model and its strength (`physics::effects`).
    pub effect: Option<(EffectKind, f64)>,
    pub seed: u64,
    /// Frames of the ring lying still after a natural end.
    pub rest_frames: usize,
    pub image_width_px: f64,
    pub image_height_px: f64,
    pub mark_order: MarkOrder,
    /// Probability that a mark is missing (not tracked) in a frame.
    pub missing_fraction: f64,
}

impl Default for SynthOptions {
    fn default() -> Self {
        SynthOptions {
            fps: 300.0,
            px_per_mm: (PAPER_PX_PER_MM * 1e6).round() / 1e6,
            noise_px: 0.5,
            lens_k1: 0.0,
            effect: None,
            seed: 1,
            rest_frames: 60,
            image_width_px: 1280.0,
            image_height_px: 1024.0,
            mark_order: MarkOrder::Forward,
            missing_fraction: 0.0,
        }
    }
}

#[derive(Debug, Error, Clone, PartialEq)]
pub enum SynthError {
    #[error("invalid synth option: {0}")]
    Option(String),
    #[error("invalid effect: {0}")]
    Effect(ParamError),
    #[error("the model cannot run: {0}")]
    Run(RunError),
}

/// A synthesized recording with what it was made from.
#[derive(Clone, Debug)]
pub struct Synthesized {
    pub recording: Recording,
    /// The model at each frame (in the case's units; the rest frames repeat the last).
    pub samples: Vec<Sample>,
    pub summary: RunSummary,
    pub camera: Camera,
    /// The case's unit of length in mm.
    pub length_mm: f64,
    /// The case's unit of time in s.
    pub time_s: f64,
}

impl SynthOptions {
    pub fn validate(&self) -> Result<(), SynthError> {
        let positive = |name: &str, v: f64| {
            if v.is_finite() && v > 0.0 { Ok(()) } else { Err(SynthError::Option(format!("{name} = {v} must be a positive number"))) }
        };
        positive("fps", self.fps)?;
        positive("px_per_mm", self.px_per_mm)?;
        positive("image width", self.image_width_px)?;
        positive("image height", self.image_height_px)?;
        if !(self.noise_px.is_finite() && self.noise_px >= 0.0) {
            return Err(SynthError::Option(format!("noise_px = {} must be a number >= 0", self.noise_px)));
        }
        if !self.lens_k1.is_finite() || self.lens_k1.abs() > 0.5 {
            return Err(SynthError::Option(format!("lens k1 = {} must lie in [-0.5, 0.5]", self.lens_k1)));
        }
        if !(0.0..1.0).contains(&self.missing_fraction) {
            return Err(SynthError::Option(format!("missing fraction = {} must lie in [0, 1)", self.missing_fraction)));
        }
        if let Some((EffectKind::CameraDistortion, _)) = self.effect
            && self.lens_k1 != 0.0
        {
            return Err(SynthError::Option(
                "give the lens distortion either as lens k1 or as the camera_distortion effect, not both".into(),
            ));
        }
        Ok(())
    }

    /// The camera these options describe (the effect `camera_distortion` sets its `k1`).
    pub fn camera(&self) -> Camera {
        let k1 = match self.effect {
            Some((EffectKind::CameraDistortion, s)) => s,
            _ => self.lens_k1,
        };
        Camera { k1, ..Camera::centred(self.px_per_mm, self.image_width_px, self.image_height_px) }
    }
}

/// Runs the case and films it.
pub fn synthesize(case: &Case, opts: &SynthOptions) -> Result<Synthesized, SynthError> {
    opts.validate()?;
    let to_mm = Conversion::between(case.units, Units::MM_S);
    let (length_mm, time_s) = (to_mm.length, to_mm.time);
    let mut model = case.model.clone();
    if let Some((kind, strength)) = opts.effect {
        let start = Sample::new(&model, 0.0, &case.initial.to_state());
        effects::apply(kind, strength, model.body.r, start.reynolds, &mut model.effects).map_err(SynthError::Effect)?;
    }
    let dt = 1.0 / opts.fps / time_s;
    let run_opts = crate::physics::RunOptions { sample_dt: Some(dt), ..case.opts.clone() };
    let sim = Simulation::new(model.clone(), &case.initial, run_opts).map_err(SynthError::Run)?;
    let mut samples = Vec::new();
    let summary = sim.run(&mut |s| samples.push(*s));
    // Keep the frames on the grid before the end; then the rest frames show the end state.
    let motion_frames = ((summary.t_end / dt).floor() as usize).clamp(1, samples.len());
    samples.truncate(motion_frames);
    if summary.end_reason.is_natural() {
        samples.extend(std::iter::repeat_n(summary.final_sample, opts.rest_frames));
    }

    let camera = opts.camera();
    let geometry = MarkGeometry { radius: mark_radius(&model.body) * length_mm, order: opts.mark_order };
    let mut rng = Rng::new(opts.seed);
    let frames: Vec<FrameMarks> = samples
        .iter()
        .map(|s| {
            let a = [s.x_a * length_mm, s.y_a * length_mm];
            let marks = geometry.marks(a, s.phi(), s.theta(), s.psi());
            let mut out: FrameMarks = [None; MARKS];
            for (slot, m) in out.iter_mut().zip(marks) {
                let p = camera.to_px(m[0], m[1]);
                let noisy = [p[0] + opts.noise_px * rng.normal(), p[1] + opts.noise_px * rng.normal()];
                if opts.missing_fraction == 0.0 || rng.uniform() >= opts.missing_fraction {
                    *slot = Some(noisy);
                }
            }
            out
        })
        .collect();

    let b = &model.body;
    // Lengths to the nanometre: the unit conversion's last bits are not information.
    let mm = |v: f64| (v * length_mm * 1e6).round() / 1e6;
    let mut extra = vec![("generator".to_string(), format!("ringlab {} synth", env!("CARGO_PKG_VERSION")))];
    extra.push(("case".to_string(), case.name.clone()));
    extra.push(("seed".to_string(), opts.seed.to_string()));
    let header = Header {
        fps: opts.fps,
        px_per_mm: opts.px_per_mm,
        shape: b.shape,
        outer_radius_mm: mm(b.r),
        width_mm: mm(b.h),
        thickness_mm: (b.shape == crate::physics::Shape::Ring).then_some(mm(b.w)),
        image_width_px: Some(opts.image_width_px),
        image_height_px: Some(opts.image_height_px),
        extra,
    };
    let recording = Recording { header, first_frame: 0, frames };
    Ok(Synthesized { recording, samples, summary, camera, length_mm, time_s })
}
