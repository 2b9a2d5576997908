//! Length units of trackers' positions: pixels, or a calibrated length.

/// The unit a file's positions are in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LengthUnit {
    Px,
    /// A length: this many mm per unit.
    Length {
        mm: f64,
        name: &'static str,
    },
}

impl LengthUnit {
    pub const NAMES: &'static str = "px, um, mm, cm, m";
    pub const MM: LengthUnit = LengthUnit::Length { mm: 1.0, name: "mm" };

    /// Reads the names trackers write (`pixel`, `micron`, `µm`, `mm`, `(cm)` ...).
    pub fn parse(s: &str) -> Option<LengthUnit> {
        let s = s.trim().trim_start_matches('(').trim_end_matches(')').trim().to_lowercase();
        let length = |mm, name| Some(LengthUnit::Length { mm, name });
        match s.as_str() {
            "px" | "pixel" | "pixels" => Some(LengthUnit::Px),
            "um" | "µm" | "μm" | "micron" | "microns" | "micrometer" | "micrometre" => {
                length(1e-3, "um")
            }
            "mm" | "millimeter" | "millimetre" => length(1.0, "mm"),
            "cm" | "centimeter" | "centimetre" => length(10.0, "cm"),
            "m" | "meter" | "metre" => length(1000.0, "m"),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            LengthUnit::Px => "px",
            LengthUnit::Length { name, .. } => name,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trackers_unit_names_are_read() {
        assert_eq!(LengthUnit::parse("(pixel)"), Some(LengthUnit::Px));
        assert_eq!(LengthUnit::parse("micron").map(LengthUnit::name), Some("um"));
        assert_eq!(LengthUnit::parse(" (µm) ").map(LengthUnit::name), Some("um"));
        assert_eq!(LengthUnit::parse("m"), Some(LengthUnit::Length { mm: 1000.0, name: "m" }));
        assert_eq!(LengthUnit::parse("furlong"), None);
    }
}
