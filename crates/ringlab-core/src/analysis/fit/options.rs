//! What a fit is asked (options), how far it is (progress), how it fails (errors).

use super::lm::LmError;
use crate::analysis::sweep::Axis;
use crate::physics::ParamError;
use crate::physics::effects::EffectKind;
use crate::physics::integrator::Tolerances;
use crate::recording::recover::RecoverError;
use thiserror::Error;

/// The flat limit of the fit's runs, closer to flat than a plain run's (`pi/2 - 0.02`): a
/// model that is still off may otherwise end on a `theta` maximum before the recording's ring
/// comes to rest, and whether a maximum crosses the limit is all or nothing.
pub const FIT_THETA_FLAT: f64 = std::f64::consts::FRAC_PI_2 - 0.005;

#[derive(Clone, Debug, PartialEq)]
pub struct FitOptions {
    /// Frames per shooting segment at first.
    pub segment_frames: usize,
    /// How many times the segments may be doubled in length after the first fit (each time
    /// only while the misfit stays as the noise allows).
    pub merges: usize,
    /// Drag to start from (and to use for the start state).
    pub c_start: [f64; 3],
    /// Run the coarse grid (else start the least squares from `c_start`).
    pub coarse: bool,
    pub coarse_axes: [Axis; 3],
    /// An effect whose strength is fitted too, with its starting strength.
    pub effect: Option<(EffectKind, f64)>,
    /// The camera's radial distortion, when known (`camera_distortion` fits it instead).
    pub lens_k1: f64,
    /// A pinhole camera's distance (mm) and tilt (degrees), when known, over the header's.
    pub camera_distance_mm: Option<f64>,
    pub camera_tilt_deg: Option<f64>,
    pub tolerances: Tolerances,
    pub max_iterations: usize,
    /// Leave the tracker's glitches out (`recording::glitches`); off where the caller has
    /// already done so.
    pub leave_out_glitches: bool,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            segment_frames: 60,
            merges: 2,
            c_start: crate::physics::paper::C_RING,
            coarse: true,
            coarse_axes: [Axis { lo: 0.005, hi: 0.5, n: 6, log: true }; 3],
            effect: None,
            lens_k1: 0.0,
            camera_distance_mm: None,
            camera_tilt_deg: None,
            tolerances: Tolerances { rtol: 1e-10, atol: 1e-12 },
            max_iterations: 30,
            leave_out_glitches: true,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FitStage {
    Recover,
    StartState,
    Sweep,
    Segments,
    Refine,
}

impl FitStage {
    pub fn describe(self) -> &'static str {
        match self {
            FitStage::Recover => "recovering the motion",
            FitStage::StartState => "start state",
            FitStage::Sweep => "coarse drag grid",
            FitStage::Segments => "segment states",
            FitStage::Refine => "least squares",
        }
    }
}

/// Where a fit is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitProgress {
    pub stage: FitStage,
    pub done: usize,
    pub total: usize,
    /// The misfit so far (px), where known.
    pub rms_px: Option<f64>,
}

#[derive(Debug, Error, Clone, PartialEq)]
pub enum FitError {
    #[error(transparent)]
    Recover(#[from] RecoverError),
    #[error("invalid fit setting: {0}")]
    Options(String),
    #[error("the model cannot be built: {0}")]
    Model(ParamError),
    #[error(
        "too few frames after the start (frame {start}) to fit: {frames}, one segment at least"
    )]
    TooFewFrames { start: usize, frames: usize },
    #[error("the start state cannot be reconstructed at frame {0} (marks missing around it?)")]
    NoStartState(usize),
    #[error("the model cannot be evaluated at the starting parameters")]
    BadStart,
    #[error("the fit was cancelled")]
    Cancelled,
    /// A fit run apart (a web page's worker) that failed there: its error, as it said it.
    #[error("{0}")]
    Apart(String),
}

impl From<LmError> for FitError {
    fn from(e: LmError) -> Self {
        match e {
            LmError::Cancelled => FitError::Cancelled,
            LmError::BadStart => FitError::BadStart,
        }
    }
}
