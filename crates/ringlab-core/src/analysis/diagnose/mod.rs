//! The diagnosis: when the paper's model and a recording differ, where they part, what
//! physics (or what of the camera) was left out, the model with it, and how much better it
//! fits. The suspects are the paper's own (section III): drag coefficients that grow as `Re`
//! falls (its simulated final spiral lives too long), slippage at the cusps (its drift),
//! rolling and pivot friction, air drag on the travel, the camera's distortion; errors in
//! the start state are no suspect here, because every model's start state is fitted.
//!
//! **The misfit: one prediction of the whole run.** Multiple shooting, the fit's misfit
//! (`analysis::fit`), re-anchors every segment to the data, and a missing effect goes into the
//! segments' start states: on the paper's ring with 0.5 px of noise, Reynolds-dependent drag
//! (n = 0.25) leaves a 60-frame multiple-shooting fit at 0.51 px and rolling friction at the
//! bottom of its realistic range (k/R = 0.001) at 0.50 px, both indistinguishable from the
//! noise, while one prediction from the start over the whole run misses by 7.8 and 5.7 px.
//! A re-anchored misfit would hide the effect, and the improvement with it. So every model
//! here, the baseline and each candidate alike, is scored by single shooting: its drag, its
//! effect's strength and the 8 numbers of the start state at the first inner turning point are
//! fitted so that one run of the model matches every tracked mark coordinate (pixels) from that
//! turning point to the still end; the misfit is the RMS of model minus recording over all of
//! them. The same residuals, the same start, any model: "before" and "after" are this one
//! misfit, and so are the candidates' scores.
//!
//! **Reaching it.** Single shooting over thousands of frames is steep and full of side valleys
//! (a small change in drag shifts every later cycloid), so no fit starts there. The baseline
//! walks from its multiple-shooting fit down a path: segments merged pairwise and refitted
//! until one is left ([`whole`]). Each candidate walks the same path from the same segments,
//! its strength starting from the best of a scan over its realistic range ([`candidates`]). A
//! candidate that at zero strength is the baseline can never end worse, so one whose stage
//! fits four times worse than the baseline's with as many segments has left the valley and
//! stops there, and one that ends worse is refitted from the baseline's solution; and the
//! baseline is refitted from the best candidate's drag and start, so that "before" is the
//! baseline at its best.
//!
//! **The criterion: BIC** `N ln(RSS/N) + k ln N`, `N` the mark coordinates, `k` the free
//! numbers (3 drag + 8 start, +1 for an effect). With the right model the residuals are the
//! recording's white pixel noise, where BIC is what it claims to be; an effect is named when
//! its BIC is at least [`DEFAULT_EVIDENCE`] (10, "very strong") below the baseline's and it
//! explains at least half of the baseline's misfit beyond the noise ([`MIN_EXPLAINED`]: far
//! from the noise the residuals are not white, and BIC rewards any parameter that bends the
//! path a little), else `none`. On recordings without an effect the nested candidates end at the baseline's misfit
//! and their BIC at `+ln N` (about 9.7 for 2,000 frames): no false alarm unless the noise
//! itself lowers the misfit by more than 10 + ln N noise variances.
//!
//! **Where.** Fitted to the whole run, a model that lacks something spreads its error over the
//! whole run. So the location is found apart from the score ([`departure`]): the baseline is
//! fitted to a stretch from the start that doubles while the fit stays within the noise, and
//! bisected where it stops; the mismatch runs from there to the last window where the
//! prediction of that fit departs. "Within the noise" is a window test against the noise
//! estimated from the marks alone ([`residual`]).
//!
//! **Why.** [`signature`] measures what tells the effects apart (where the baseline departs,
//! the misfit by thirds of the run, when each model's motion ends, how much of the residual
//! points radially from the image centre, where the improved model slides) and [`explain`]
//! puts it in words with the fitted parameter and its uncertainty.
//!
//! **Proof.** [`concealed`] makes recordings with a random effect, strength, start state and
//! drag through `synth`; `ringlab diagnose-bench` runs the diagnosis on them (the table in
//! `docs/diagnosis.md`).
//!
//! For a window: [`diagnose`] on a worker thread, with a progress callback
//! ([`DiagnoseProgress`]: a fraction for a bar and a line to show) and a cancel flag; the
//! [`Diagnosis`] is plain data with everything the report shows: the residual series, the
//! mismatch windows, the trace of point A under both models, the ranked candidates, and the
//! improved model with its start state, ready for a simulator to adopt.

mod again;
pub mod candidates;
pub mod concealed;
pub mod departure;
pub mod explain;
mod in_order;
pub mod noise_correlation;
mod options;
mod progress;
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
    Candidate, Diagnosis, Finding, MismatchWindow, ModelFit, PairCandidate, Partial,
    ResidualSeries, Signature, Trace,
};
pub use rules::{
    CONSISTENT_RATIO, MIN_EXCESS_CUT, MIN_EXPLAINED, bic, excess_px, explained_share, explains,
};
pub use run::diagnose;
