//! The diagnosis: when the paper's model and a recording differ, where they part, what
//! physics (or what of the camera) was left out, the model with it, and how much better it
//! fits. The suspects are the effects of `physics::effects`, one file each.
//!
//! Every model, the baseline and each candidate alike, is scored by one prediction of the
//! whole run (single shooting) over every tracked mark coordinate: multiple shooting
//! re-anchors each segment to the data, and a missing effect would hide in the segments' start
//! states. Single shooting over thousands of frames is full of side valleys, so every model is
//! reached by a path from the multiple-shooting fit, its segments merged pairwise until one is
//! left ([`whole`], [`candidates`]). The criterion is BIC, and an effect is named only where it
//! also explains most of the misfit beyond the noise ([`rules`]); where one effect is not
//! enough, pairs ([`select`]). The passes that fit the candidates again and the larger models
//! are one list, the plan (`plan.rs`), run by one loop. Where the baseline departs is found
//! apart from the score
//! ([`departure`]); what tells the effects apart is measured ([`signature`]) and put in words
//! with each effect's own ([`explain`]).
//!
//! [`diagnose`] reads as its stages (`run.rs`). It runs off the UI thread with a progress
//! callback and a cancel flag; the [`Diagnosis`] is plain data with everything a report or a
//! window shows. [`concealed`] makes the recordings of `ringlab diagnose-bench`. The method,
//! its rules and the figures behind them: `docs/diagnosis.md`.

mod again;
pub mod candidates;
pub mod concealed;
pub mod departure;
pub mod explain;
mod in_order;
pub mod noise_correlation;
mod options;
mod pairs;
mod plan;
mod progress;
mod ranking;
pub mod residual;
mod result;
mod rules;
mod run;
mod seen_camera;
mod select;
pub mod signature;
pub mod whole;

pub use options::{
    DEFAULT_EVIDENCE, DIAGNOSE_TOLERANCES, DiagnoseError, DiagnoseOptions, DiagnoseProgress,
    DiagnoseStage, SLIP_TOLERANCES,
};
pub use result::{
    Candidate, Diagnosis, Finding, MismatchWindow, ModelFit, NamedShare, PairCandidate, Partial,
    ResidualSeries, Signature, Trace,
};
pub use rules::{
    CONSISTENT_RATIO, MIN_EXCESS_CUT, MIN_EXPLAINED, bic, excess_px, explained_share, explains,
};
pub use run::diagnose;
