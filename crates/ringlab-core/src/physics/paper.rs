//! The paper's case (`PHYSICS.md`), in its dimensionless units.

use super::body::Body;
use super::model::{Initial, Model};
use super::units::Units;

/// Drag of the paper's ring (Fig. 4a).
pub const C_RING: [f64; 3] = [0.03, 0.063, 0.085];
/// Disk-like drag on the same body (Fig. 4b).
pub const C_DISK_LIKE: [f64; 3] = [0.2, 0.063, 0.2];
/// Mean radius of the experiment's ring in mm (`R - w/2` with R = 20.66, w = 1).
pub const MEAN_RADIUS_MM: f64 = 20.16;

/// `g` such that `R phi'_0^2 = 20.2 g` with `R = 1.025`, `phi'_0 = 4.5`.
pub fn g() -> f64 {
    1.025 * 4.5 * 4.5 / 20.2
}

/// The paper's unit system: lengths in mean radii, time such that `g` is [`g()`].
pub fn units() -> Units {
    Units::dimensionless(MEAN_RADIUS_MM, g())
}

/// The paper's ring with drag coefficients `c`.
pub fn ring_model(c: [f64; 3]) -> Model {
    Model::new(Body::paper_ring(), g(), c, units().nu_air()).expect("the paper's case is valid")
}

/// The paper's start at the first inner turning point.
pub fn initial() -> Initial {
    Initial::paper()
}
