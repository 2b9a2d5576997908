//! Recordings made from the model: `ringlab synth`, the tests, and the diagnosis's test data.
//!
//! Made the way `data/sample-ring.csv` was made (checked against its truth: the centroid of
//! its marks follows the truth run to 0.25 px per axis, the noise of four marks averaged):
//! frame `n` is the model at `t = n / fps` from the case's start; the marks (see
//! [`super::marks`]) are projected straight down with the table's origin at the image centre,
//! `y` downward; Gaussian noise of `noise_px` is added to each coordinate. A camera distance or
//! tilt films through that camera instead ([`super::camera`]: the marks' heights above the table
//! magnified); the header names it only with `camera_in_header`, so that by default a diagnosis
//! has to find it, as it would a lab's unmeasured camera. When the run ends
//! naturally (flat or at rest) after `t_end`, frames `0 .. floor(t_end fps)` show the motion and
//! then `rest_frames` more show the final pose, still (the sample: 1824 + 60 frames).

use super::camera::Camera;
use super::marks::{MarkGeometry, MarkOrder};
use super::read::MAX_TILT_DEG;
use super::rng::Rng;
use super::{FrameMarks, Header, MARKS, Recording};
use crate::config::Case;
use crate::physics::effects::{self, EffectKind};
use crate::physics::run::RunError;
use crate::physics::{Conversion, Model, ParamError, RunSummary, Sample, Simulation, Units};
use thiserror::Error;

/// The paper's camera scale: 135.6 px = 40.3 mm.
pub const PAPER_PX_PER_MM: f64 = 135.6 / 40.3;
/// The closest camera `synth` films with, in outer radii of the body.
pub const MIN_CAMERA_DISTANCE_RADII: f64 = 5.0;

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
    /// The effect's first extra numbers (`Descriptor::extras`, in order; the rest as the case
    /// and the camera options have them).
    pub effect_extras: Vec<f64>,
    pub seed: u64,
    /// Frames of the ring lying still after a natural end.
    pub rest_frames: usize,
    pub image_width_px: f64,
    pub image_height_px: f64,
    pub mark_order: MarkOrder,
    /// Probability that a mark is missing (not tracked) in a frame.
    pub missing_fraction: f64,
    /// A pinhole camera this far from the table (mm, along its axis); None: orthographic.
    pub camera_distance_mm: Option<f64>,
    /// The camera's tilt (degrees; positive: the camera towards the table's `-Y`, the image's bottom).
    pub camera_tilt_deg: f64,
    /// Whether the header gives the camera's distance and tilt (the format's optional keys).
    pub camera_in_header: bool,
}

impl Default for SynthOptions {
    fn default() -> Self {
        SynthOptions {
            fps: 300.0,
            px_per_mm: (PAPER_PX_PER_MM * 1e6).round() / 1e6,
            noise_px: 0.5,
            lens_k1: 0.0,
            effect: None,
            effect_extras: Vec::new(),
            seed: 1,
            rest_frames: 60,
            image_width_px: 1280.0,
            image_height_px: 1024.0,
            mark_order: MarkOrder::Forward,
            missing_fraction: 0.0,
            camera_distance_mm: None,
            camera_tilt_deg: 0.0,
            camera_in_header: false,
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
    #[error("the camera cannot film the run: {0}")]
    Camera(String),
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
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(SynthError::Option(format!("{name} = {v} must be a positive number")))
            }
        };
        positive("fps", self.fps)?;
        positive("px_per_mm", self.px_per_mm)?;
        positive("image width", self.image_width_px)?;
        positive("image height", self.image_height_px)?;
        if !(self.noise_px.is_finite() && self.noise_px >= 0.0) {
            return Err(SynthError::Option(format!(
                "noise_px = {} must be a number >= 0",
                self.noise_px
            )));
        }
        if !self.lens_k1.is_finite() || self.lens_k1.abs() > 0.5 {
            return Err(SynthError::Option(format!(
                "lens k1 = {} must lie in [-0.5, 0.5]",
                self.lens_k1
            )));
        }
        if let Some(d) = self.camera_distance_mm
            && !(d.is_finite() && d > 0.0)
        {
            return Err(SynthError::Option(format!(
                "camera distance = {d} mm must be a positive number"
            )));
        }
        if !(self.camera_tilt_deg.abs() < MAX_TILT_DEG) {
            let t = self.camera_tilt_deg;
            return Err(SynthError::Option(format!(
                "camera tilt = {t} degrees must lie between -{MAX_TILT_DEG} and {MAX_TILT_DEG}"
            )));
        }
        if !(0.0..1.0).contains(&self.missing_fraction) {
            return Err(SynthError::Option(format!(
                "missing fraction = {} must lie in [0, 1)",
                self.missing_fraction
            )));
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

    /// The camera these options describe (a camera effect sets its numbers on it: the effect
    /// `camera_distortion` its `k1`, `camera_perspective` its distance).
    pub fn camera(&self) -> Camera {
        let mut camera = Camera {
            k1: self.lens_k1,
            distance_mm: self.camera_distance_mm,
            tilt_rad: self.camera_tilt_deg.to_radians(),
            ..Camera::centred(self.px_per_mm, self.image_width_px, self.image_height_px)
        };
        if let Some((kind, s)) = self.effect
            && kind.is_camera()
            && s != 0.0
        {
            let mut numbers = camera.numbers();
            let (at, mut effects) = (effects::ApplyAt::new(1.0, 1.0), Default::default());
            if effects::apply_with_extras(
                kind,
                s,
                &self.effect_extras,
                &at,
                &mut effects,
                &mut numbers,
            )
            .is_ok()
            {
                camera.set_numbers(&numbers);
            }
        }
        camera
    }
}

/// Runs the case and films it.
pub fn synthesize(case: &Case, opts: &SynthOptions) -> Result<Synthesized, SynthError> {
    opts.validate()?;
    let to_mm = Conversion::between(case.units, Units::MM_S);
    let (length_mm, time_s) = (to_mm.length, to_mm.time);
    // Closer than a few radii the ring would fill the picture (and could reach the lens).
    if let Some(d) = opts.camera_distance_mm
        && d <= MIN_CAMERA_DISTANCE_RADII * case.model.body.r * length_mm
    {
        let r = case.model.body.r * length_mm;
        return Err(SynthError::Option(format!(
            "camera distance = {d} mm must exceed {MIN_CAMERA_DISTANCE_RADII} times the body's outer radius ({r:.3} mm)"
        )));
    }
    let mut model = case.model.clone();
    if let Some((kind, strength)) = opts.effect {
        let start = Sample::new(&model, 0.0, &case.initial.to_state());
        if kind.is_physical() {
            let at = effects::ApplyAt::new(model.body.r, start.reynolds);
            let mut numbers = opts.camera().numbers();
            effects::apply_with_extras(
                kind,
                strength,
                &opts.effect_extras,
                &at,
                &mut model.effects,
                &mut numbers,
            )
            .map_err(SynthError::Effect)?;
        }
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

    let recording = film(case, &model, &samples, opts)?;
    let camera = opts.camera();
    Ok(Synthesized { recording, samples, summary, camera, length_mm, time_s })
}

/// Films `samples` of a run of `model` (the case's, with the effects it ran with) as `opts`
/// say: the marks through the camera with the pixel noise, and the header. [`synthesize`] runs
/// the model first; a test can film a motion made another way.
pub fn film(
    case: &Case,
    model: &Model,
    samples: &[Sample],
    opts: &SynthOptions,
) -> Result<Recording, SynthError> {
    let length_mm = Conversion::between(case.units, Units::MM_S).length;
    let camera = opts.camera();
    let geometry = MarkGeometry::of_body(&model.body, opts.mark_order).scaled(length_mm);
    let mut rng = Rng::new(opts.seed);
    let mut frames: Vec<FrameMarks> = Vec::with_capacity(samples.len());
    for (n, s) in samples.iter().enumerate() {
        let a = [s.x_a * length_mm, s.y_a * length_mm];
        let pixels = if camera.sees_height() {
            geometry.marks3(a, s.phi(), s.theta(), s.psi()).map(|m| camera.to_px3(m[0], m[1], m[2]))
        } else {
            geometry.marks(a, s.phi(), s.theta(), s.psi()).map(|m| camera.to_px(m[0], m[1]))
        };
        if pixels.iter().flatten().any(|v| !v.is_finite()) {
            return Err(SynthError::Camera(format!(
                "at frame {n} a mark is at or behind the camera's centre plane"
            )));
        }
        let mut out: FrameMarks = [None; MARKS];
        for (slot, p) in out.iter_mut().zip(pixels) {
            let noisy = [p[0] + opts.noise_px * rng.normal(), p[1] + opts.noise_px * rng.normal()];
            if opts.missing_fraction == 0.0 || rng.uniform() >= opts.missing_fraction {
                *slot = Some(noisy);
            }
        }
        frames.push(out);
    }

    let b = &model.body;
    // Lengths to the nanometre: the unit conversion's last bits are not information.
    let mm = |v: f64| (v * length_mm * 1e6).round() / 1e6;
    let mut extra =
        vec![("generator".to_string(), format!("ringlab {} synth", env!("CARGO_PKG_VERSION")))];
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
        camera_distance_mm: opts.camera_distance_mm.filter(|_| opts.camera_in_header),
        camera_tilt_deg: opts.camera_in_header.then_some(opts.camera_tilt_deg),
        extra,
    };
    Ok(Recording { header, first_frame: 0, frames })
}
