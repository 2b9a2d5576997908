//! Units. The model is unit-agnostic: lengths, times and `g` only need to agree. Two systems
//! are in use: physical (mm, s, `g = 9810 mm/s^2`) and the paper's dimensionless units
//! (length = the mean radius `R - w/2`, time chosen so that `R phi'_0^2 = 20.2 g`).
//! The drag coefficients `C_i` are dimensionless in both (eq. 5: `tau = -C |w| w` has the units
//! of `w^2`), so they never change.

/// `g` in mm/s^2 (`PHYSICS.md`: 9.81 m/s^2).
pub const G_MM_PER_S2: f64 = 9810.0;
/// Kinematic viscosity of air at about 20 degrees C, in mm^2/s (1.51e-5 m^2/s).
pub const NU_AIR_MM2_PER_S: f64 = 15.1;

/// What one unit of length and one unit of time of a model are, in mm and s.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Units {
    pub length_mm: f64,
    pub time_s: f64,
}

impl Units {
    /// Physical units: mm and s.
    pub const MM_S: Units = Units { length_mm: 1.0, time_s: 1.0 };

    /// The paper's dimensionless units for a body of mean radius `mean_radius_mm`, where
    /// gravity is `g_model`: the time unit is then `sqrt(g_model L / g)`.
    pub fn dimensionless(mean_radius_mm: f64, g_model: f64) -> Units {
        Units { length_mm: mean_radius_mm, time_s: (g_model * mean_radius_mm / G_MM_PER_S2).sqrt() }
    }

    /// Gravity in these units.
    pub fn g(&self) -> f64 {
        G_MM_PER_S2 * self.time_s * self.time_s / self.length_mm
    }

    /// Air's kinematic viscosity in these units (for the Reynolds number).
    pub fn nu_air(&self) -> f64 {
        NU_AIR_MM2_PER_S * self.time_s / (self.length_mm * self.length_mm)
    }

    pub fn is_physical(&self) -> bool {
        self.length_mm == 1.0 && self.time_s == 1.0
    }

    pub fn label(&self) -> &'static str {
        if self.is_physical() { "mm, s" } else { "model units" }
    }
}

/// How quantities of each dimension scale from one unit system to another: multiply a value
/// in `from` by the factor to get it in `to`. This is the one conversion function; everything
/// that converts (presets, recordings, the fit) goes through it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conversion {
    /// Factor for lengths.
    pub length: f64,
    /// Factor for times.
    pub time: f64,
}

impl Conversion {
    pub fn between(from: Units, to: Units) -> Conversion {
        Conversion { length: from.length_mm / to.length_mm, time: from.time_s / to.time_s }
    }
    /// Factor for rates (angular velocities): 1/time.
    pub fn rate(&self) -> f64 {
        1.0 / self.time
    }
    /// Factor for speeds: length/time.
    pub fn speed(&self) -> f64 {
        self.length / self.time
    }
    /// Factor for forces per unit mass (accelerations): length/time^2.
    pub fn acceleration(&self) -> f64 {
        self.length / (self.time * self.time)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_units_match_truth_file() {
        // sample-ring.truth.json: mean radius 20.16 mm, g = 1.025 * 4.5^2 / 20.2, T0 = 0.0459525 s.
        let g = 1.025 * 4.5 * 4.5 / 20.2;
        let u = Units::dimensionless(20.16, g);
        assert!((u.time_s - 0.045952540019411604).abs() < 1e-9);
        assert!((u.g() - g).abs() < 1e-12);
        let c = Conversion::between(u, Units::MM_S);
        assert!((c.length - 20.16).abs() < 1e-12);
        let back = Conversion::between(Units::MM_S, u);
        assert!((c.rate() * back.rate() - 1.0).abs() < 1e-14);
    }
}
