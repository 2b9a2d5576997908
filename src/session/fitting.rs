//! The fit as the window runs it, and its progress in words and as a share of the whole.

use super::job::{JobContext, Progress, on_spare_cores};
use crate::analysis::fit::{FitError, FitOptions, FitProgress, FitResult, FitStage, fit};
use crate::recording::Recording;

/// The stages of a fit as shares of its progress bar (rough shares of the time on the sample).
const STAGE_SHARES: [(FitStage, f32); 5] = [
    (FitStage::Recover, 0.03),
    (FitStage::StartState, 0.07),
    (FitStage::Sweep, 0.35),
    (FitStage::Segments, 0.15),
    (FitStage::Refine, 0.40),
];

/// Where a fit is, as a share of the whole and in words.
pub fn describe_fit_progress(p: &FitProgress) -> Progress {
    let k = STAGE_SHARES.iter().position(|(s, _)| *s == p.stage).unwrap_or(0);
    let before: f32 = STAGE_SHARES[..k].iter().map(|s| s.1).sum();
    let within = if p.total > 0 { (p.done as f32 / p.total as f32).clamp(0.0, 1.0) } else { 0.0 };
    let mut text = format!("{} ({}/{})", p.stage.describe(), p.done, p.total);
    if let Some(rms) = p.rms_px {
        text.push_str(&format!(", misfit {rms:.3} px"));
    }
    Progress { fraction: before + STAGE_SHARES[k].1 * within, text }
}

/// The fit as the window runs it: default options; on its own pool of all cores but one, so
/// that the window and the integrator keep one.
pub(super) fn run_fit(
    rec: &Recording,
    ctx: &JobContext,
    own_pool: bool,
) -> Result<FitResult, FitError> {
    let progress = |p: &FitProgress| ctx.report_forward(describe_fit_progress(p));
    let opts = FitOptions::default();
    on_spare_cores(own_pool, || fit(rec, &opts, &progress, ctx.cancel_flag()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stages_fill_the_bar_in_order() {
        let at = |stage, done, total| {
            describe_fit_progress(&FitProgress { stage, done, total, rms_px: None }).fraction
        };
        let steps = [
            at(FitStage::Recover, 0, 1),
            at(FitStage::StartState, 0, 1),
            at(FitStage::Sweep, 100, 341),
            at(FitStage::Segments, 29, 30),
            at(FitStage::Refine, 30, 30),
        ];
        assert!(steps.windows(2).all(|w| w[1] > w[0]), "{steps:?}");
        assert_eq!(steps[0], 0.0);
        assert!((steps[4] - 1.0).abs() < 1e-6);
        let p = describe_fit_progress(&FitProgress {
            stage: FitStage::Refine,
            done: 3,
            total: 30,
            rms_px: Some(0.512),
        });
        assert!(
            p.text.contains("least squares (3/30)") && p.text.contains("0.512 px"),
            "{}",
            p.text
        );
    }
}
