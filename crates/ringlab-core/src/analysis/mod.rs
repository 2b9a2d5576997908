//! Analysis on top of the physics: the drag sweep, the fit of the model to a recording, and
//! the diagnosis of what the model left out of it.

pub mod diagnose;
pub mod fit;
pub mod json;
pub mod sweep;
