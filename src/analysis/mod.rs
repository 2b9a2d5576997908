//! Analysis on top of the physics: the drag sweep (and, later, fitting and diagnosis).

pub mod sweep;
