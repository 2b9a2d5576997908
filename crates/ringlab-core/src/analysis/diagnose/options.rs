//! What a diagnosis is asked, how it reports where it is, and how it fails.

use crate::analysis::fit::{FitError, FitOptions, FitStage};
use crate::physics::effects::EffectKind;
use crate::physics::integrator::Tolerances;
use thiserror::Error;

/// The evidence an effect must bring to be named: its BIC below the baseline's by this much
/// ("very strong" on Kass and Raftery's scale; about a 4.4 sigma drop in chi-square for one
/// parameter).
pub const DEFAULT_EVIDENCE: f64 = 10.0;

#[derive(Clone, Debug, PartialEq)]
pub struct DiagnoseOptions {
    /// The baseline's multiple-shooting fit (`analysis::fit`), where every path starts.
    pub fit: FitOptions,
    /// The effects to try (`none` is always the baseline).
    pub candidates: Vec<EffectKind>,
    /// BIC drop an effect needs over the baseline to be named.
    pub evidence: f64,
}

/// Integration tolerances of the diagnosis's rolling runs. The least squares' derivatives take
/// their runs at the steps of the run they differ from (`physics::run`'s `steps.rs`), so they
/// stay smooth at this tolerance (`tests/fit.rs`); with adaptive steps on both sides they
/// needed 1e-9 (docs/diagnosis-history.md: what each tolerance cost and changed).
pub const DIAGNOSE_TOLERANCES: Tolerances = Tolerances { rtol: 1e-6, atol: 1e-8 };

/// The tolerances of a run with slip free (at most): its switches between rolling and sliding
/// make its followed differences rougher, and at [`DIAGNOSE_TOLERANCES`] they miss the
/// accuracy the rolling ones keep (`tests/fit.rs`); a concealed slip's fit then stopped at 1.2
/// times the noise (`tests/diagnose.rs::names_slip`).
pub const SLIP_TOLERANCES: Tolerances = Tolerances { rtol: 1e-7, atol: 1e-9 };

impl Default for DiagnoseOptions {
    fn default() -> Self {
        DiagnoseOptions {
            fit: FitOptions { tolerances: DIAGNOSE_TOLERANCES, ..FitOptions::default() },
            candidates: EffectKind::ALL.into_iter().filter(|&k| k != EffectKind::None).collect(),
            evidence: DEFAULT_EVIDENCE,
        }
    }
}

/// The stages of a diagnosis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiagnoseStage {
    /// The baseline's multiple-shooting fit, at one of its own stages.
    BaselineFit(FitStage),
    /// The baseline and every candidate over the whole run.
    Candidates,
    /// Residuals, windows, signature, words.
    Explain,
}

impl DiagnoseStage {
    pub fn describe(self) -> String {
        match self {
            DiagnoseStage::BaselineFit(s) => format!("baseline fit: {}", s.describe()),
            DiagnoseStage::Candidates => "candidates over the whole run".into(),
            DiagnoseStage::Explain => "explaining".into(),
        }
    }
}

/// Where a diagnosis is: `fraction` of the whole in [0, 1] (for a bar), the stage, and a
/// line to show.
#[derive(Clone, Debug, PartialEq)]
pub struct DiagnoseProgress {
    pub stage: DiagnoseStage,
    pub fraction: f64,
    pub message: String,
    /// The pass of the diagnosis's plan under way, by its name (`None` before the plan's first
    /// pass and after its last; the message then says what runs).
    pub pass: Option<&'static str>,
}

#[derive(Debug, Error, Clone, PartialEq)]
pub enum DiagnoseError {
    #[error("the baseline fit failed: {0}")]
    Fit(#[from] FitError),
    #[error("the baseline model cannot be run over the whole recording")]
    Baseline,
    #[error("invalid diagnosis setting: {0}")]
    Options(String),
    #[error("the diagnosis was cancelled")]
    Cancelled,
    /// A diagnosis run apart (a web page's worker) that failed there: its error, as it said it.
    #[error("{0}")]
    Apart(String),
}
