//! The rolling body: a thin-walled ring (tube) or a solid disk, mass 1.
//!
//! Geometry and inertia follow `PHYSICS.md`: outer radius `R`, width `h` along the
//! symmetry axis `e2`, wall thickness `w` (a disk is `w = R`).

use nalgebra::{Matrix3, Vector3};
use std::fmt;

/// Which inertia formula applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Shape {
    /// Thin-walled tube: `I2 = (R^2 + Ri^2)/2`, `I1 = I3 = (R^2 + Ri^2)/4 + h^2/12`.
    Ring,
    /// Solid cylinder: `I2 = R^2/2`, `I1 = I3 = R^2/4 + h^2/12`.
    Disk,
}

impl Shape {
    pub fn name(self) -> &'static str {
        match self {
            Shape::Ring => "ring",
            Shape::Disk => "disk",
        }
    }

    pub fn parse(s: &str) -> Option<Shape> {
        match s.trim().to_ascii_lowercase().as_str() {
            "ring" => Some(Shape::Ring),
            "disk" | "disc" => Some(Shape::Disk),
            _ => None,
        }
    }
}

impl fmt::Display for Shape {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A parameter that failed validation, with the reason in words.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamError {
    pub name: &'static str,
    pub value: f64,
    pub reason: &'static str,
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "invalid {} = {}: {}", self.name, self.value, self.reason)
    }
}

impl std::error::Error for ParamError {}

pub(crate) fn check_finite(name: &'static str, value: f64) -> Result<f64, ParamError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ParamError { name, value, reason: "must be a finite number" })
    }
}

pub(crate) fn check_positive(name: &'static str, value: f64) -> Result<f64, ParamError> {
    check_finite(name, value)?;
    if value > 0.0 {
        Ok(value)
    } else {
        Err(ParamError { name, value, reason: "must be greater than zero" })
    }
}

pub(crate) fn check_non_negative(name: &'static str, value: f64) -> Result<f64, ParamError> {
    check_finite(name, value)?;
    if value >= 0.0 {
        Ok(value)
    } else {
        Err(ParamError { name, value, reason: "must not be negative" })
    }
}

/// A validated body with its inertia and the constant matrix `J` of eq. 4 (and its inverse).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Body {
    pub shape: Shape,
    /// Outer radius `R`.
    pub r: f64,
    /// Width `h` (extent along the symmetry axis).
    pub h: f64,
    /// Wall thickness `w` (`w = R` for a disk).
    pub w: f64,
    /// Principal moments about the centre of mass: `(I1, I2, I3)`, with `I1 = I3`.
    pub inertia: Vector3<f64>,
    /// `J = I + m [[h^2/4 + R^2, 0, 0], [0, R^2, -hR/2], [0, -hR/2, h^2/4]]` (eq. 4).
    pub j: Matrix3<f64>,
    pub j_inv: Matrix3<f64>,
}

impl Body {
    /// Builds a body; a disk ignores `w` and uses `w = R`.
    /// Validates `R > 0`, `h > 0`, `0 < w <= R`, all finite.
    pub fn new(shape: Shape, r: f64, h: f64, w: f64) -> Result<Body, ParamError> {
        let r = check_positive("outer radius R", r)?;
        let h = check_positive("width h", h)?;
        let w = match shape {
            Shape::Disk => r,
            Shape::Ring => {
                let w = check_positive("wall thickness w", w)?;
                if w > r {
                    return Err(ParamError {
                        name: "wall thickness w",
                        value: w,
                        reason: "must not exceed the outer radius R",
                    });
                }
                w
            }
        };
        let (i1, i2) = match shape {
            Shape::Ring => {
                let ri = r - w;
                let s = r * r + ri * ri;
                (s / 4.0 + h * h / 12.0, s / 2.0)
            }
            Shape::Disk => (r * r / 4.0 + h * h / 12.0, r * r / 2.0),
        };
        let inertia = Vector3::new(i1, i2, i1);
        let j = Matrix3::from_diagonal(&inertia)
            + Matrix3::new(
                h * h / 4.0 + r * r,
                0.0,
                0.0,
                0.0,
                r * r,
                -h * r / 2.0,
                0.0,
                -h * r / 2.0,
                h * h / 4.0,
            );
        // J is symmetric positive definite for any valid geometry (I is, and the added
        // term is m(|r_G|^2 1 - r_G r_G^T), positive semi-definite).
        let j_inv = j.try_inverse().ok_or(ParamError {
            name: "geometry",
            value: r,
            reason: "gives a singular inertia matrix",
        })?;
        Ok(Body { shape, r, h, w, inertia, j, j_inv })
    }

    /// The paper's ring (`PHYSICS.md`, dimensionless): `R = 1.025, h = 0.88, w = 0.05`.
    pub fn paper_ring() -> Body {
        Body::new(Shape::Ring, 1.025, 0.88, 0.05).expect("the paper's ring is valid")
    }

    /// Mean radius `R - w/2`: the paper's unit of length.
    pub fn mean_radius(&self) -> f64 {
        self.r - self.w / 2.0
    }

    /// Inner radius `R - w` (0 for a disk).
    pub fn inner_radius(&self) -> f64 {
        self.r - self.w
    }

    /// `r_G = C - P = (0, h/2, R)` in the Resal frame.
    pub fn r_g(&self) -> Vector3<f64> {
        Vector3::new(0.0, self.h / 2.0, self.r)
    }

    /// Below this tilt gravity pushes the ring back upright (`R sin(theta) < (h/2) cos(theta)`).
    pub fn critical_theta(&self) -> f64 {
        (self.h / (2.0 * self.r)).atan()
    }

    /// The same body scaled in length by `k` (for unit conversion).
    pub fn scaled(&self, k: f64) -> Result<Body, ParamError> {
        Body::new(self.shape, self.r * k, self.h * k, self.w * k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ring_inertia_matches_physics_md() {
        let b = Body::paper_ring();
        let ri: f64 = 0.975;
        let s = 1.025f64.powi(2) + ri * ri;
        assert!((b.inertia.y - s / 2.0).abs() < 1e-15);
        assert!((b.inertia.x - (s / 4.0 + 0.88f64.powi(2) / 12.0)).abs() < 1e-15);
        assert!((b.j * b.j_inv - Matrix3::identity()).norm() < 1e-13);
        assert!((b.mean_radius() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn disk_is_ring_with_full_wall() {
        let d = Body::new(Shape::Disk, 1.0, 0.2, 123.0).unwrap();
        let r = Body::new(Shape::Ring, 1.0, 0.2, 1.0).unwrap();
        assert_eq!(d.w, 1.0);
        assert!((d.inertia - r.inertia).norm() < 1e-15);
    }

    #[test]
    fn rejects_bad_geometry() {
        assert_eq!(Body::new(Shape::Ring, 1.0, 0.5, 1.5).unwrap_err().name, "wall thickness w");
        assert_eq!(Body::new(Shape::Ring, 1.0, 0.5, 0.0).unwrap_err().name, "wall thickness w");
        assert_eq!(Body::new(Shape::Ring, -1.0, 0.5, 0.1).unwrap_err().name, "outer radius R");
        assert_eq!(Body::new(Shape::Disk, 1.0, 0.0, 0.1).unwrap_err().name, "width h");
        assert_eq!(Body::new(Shape::Disk, f64::NAN, 1.0, 0.1).unwrap_err().name, "outer radius R");
        assert_eq!(Body::new(Shape::Ring, 1.0, f64::INFINITY, 0.1).unwrap_err().name, "width h");
    }
}
