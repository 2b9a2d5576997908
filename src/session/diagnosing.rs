//! The diagnosis as the window runs it (`analysis::diagnose` with its default options), and
//! the models it found as cases the simulator can adopt.

use super::job::{JobContext, Progress, on_spare_cores};
use crate::analysis::diagnose::{
    DiagnoseError, DiagnoseOptions, DiagnoseProgress, Diagnosis, diagnose,
};
use crate::config::CaseFile;
use crate::recording::Recording;

/// A diagnosis done, with the cases of its two models (or why one cannot run).
pub struct Diagnosed {
    pub result: Diagnosis,
    /// The baseline over the whole run, and the model with the effect it names (the same
    /// model as the baseline when it names none).
    pub baseline: Result<CaseFile, String>,
    pub improved: Result<CaseFile, String>,
    /// The two models' marks at every frame (a film's recording only: drawn over it).
    pub model_marks: Option<[std::sync::Arc<super::ModelMarks>; 2]>,
}

impl Diagnosed {
    /// Seconds from the first stored frame to the diagnosis's models' t = 0 (both start at
    /// the same frame).
    pub fn offset_s(&self, first_frame: u64, fps: f64) -> f64 {
        self.result.after.start_s - first_frame as f64 / fps
    }

    /// The mismatch window on the display's clock (s from the model's start), given the
    /// session's offset: recording times count from frame 0 of the camera.
    pub fn mismatch_display_s(
        &self,
        first_frame: u64,
        fps: f64,
        offset_s: f64,
    ) -> Option<(f64, f64)> {
        let m = self.result.mismatch.as_ref()?;
        let shift = first_frame as f64 / fps + offset_s;
        Some((m.start_s - shift, m.end_s - shift))
    }
}

/// The diagnosis on its job: the stages' progress as one bar that never goes back; on its own
/// pool of all cores but one, so that the window and the integrator keep one.
pub(super) fn run_diagnose(
    rec: &Recording,
    ctx: &JobContext,
    own_pool: bool,
) -> Result<Diagnosis, DiagnoseError> {
    let progress = |p: &DiagnoseProgress| {
        ctx.report_forward(Progress { fraction: p.fraction as f32, text: p.message.clone() })
    };
    let opts = DiagnoseOptions::default();
    on_spare_cores(own_pool, || diagnose(rec, &opts, &progress, ctx.cancel_flag()))
}
