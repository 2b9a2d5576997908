//! Analysis on top of the physics: the drag sweep, the fit of the model to a recording (and,
//! later, the diagnosis).

pub mod diagnose;
pub mod fit;
pub mod sweep;
