//! Diagnosis (draft doc).

pub mod candidates;
pub mod concealed;
pub mod departure;
pub mod explain;
mod options;
pub mod residual;
mod result;
mod run;
pub mod signature;
pub mod whole;

pub use options::{DEFAULT_EVIDENCE, DiagnoseError, DiagnoseOptions, DiagnoseProgress, DiagnoseStage};
pub use result::{Candidate, Diagnosis, MismatchWindow, ModelFit, ResidualSeries, Signature, Trace};
pub use run::{bic, diagnose};
