//! The Resal frame `(e1, e2, e3)` of `PHYSICS.md` (it does not spin with `psi`), expressed in
//! table coordinates `(X, Y, Z)`, `Z` up.

use nalgebra::{Matrix3, Vector3};

/// Table-frame directions of `e1, e2, e3` for the angles `phi` (about `Z`) and `theta`
/// (about the line of nodes `e1`).
#[derive(Clone, Copy, Debug)]
pub struct ResalFrame {
    pub e1: Vector3<f64>,
    pub e2: Vector3<f64>,
    pub e3: Vector3<f64>,
}

impl ResalFrame {
    pub fn new(phi: f64, theta: f64) -> ResalFrame {
        let (sp, cp) = phi.sin_cos();
        let (st, ct) = theta.sin_cos();
        // E2' = (-sin phi, cos phi, 0): the horizontal direction normal to e1.
        let e2h = Vector3::new(-sp, cp, 0.0);
        let z = Vector3::z();
        ResalFrame { e1: Vector3::new(cp, sp, 0.0), e2: ct * e2h + st * z, e3: -st * e2h + ct * z }
    }

    /// The rotation taking frame components to table components (columns `e1, e2, e3`).
    pub fn world_from_frame(&self) -> Matrix3<f64> {
        Matrix3::from_columns(&[self.e1, self.e2, self.e3])
    }

    /// Table components of a vector given in frame components.
    pub fn to_world(&self, v: &Vector3<f64>) -> Vector3<f64> {
        self.e1 * v.x + self.e2 * v.y + self.e3 * v.z
    }
}

/// The table normal `Z` in frame components: `(0, sin(theta), cos(theta))`.
pub fn up_in_frame(theta: f64) -> Vector3<f64> {
    let (st, ct) = theta.sin_cos();
    Vector3::new(0.0, st, ct)
}

/// The lateral direction of `F_f`, `cos(theta) e2 - sin(theta) e3`, in frame components: the
/// horizontal unit vector normal to the rolling direction `e1`.
pub fn lateral_in_frame(theta: f64) -> Vector3<f64> {
    let (st, ct) = theta.sin_cos();
    Vector3::new(0.0, ct, -st)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_is_orthonormal_and_right_handed() {
        let f = ResalFrame::new(-0.38, 0.55);
        let m = f.world_from_frame();
        assert!((m.transpose() * m - Matrix3::identity()).norm() < 1e-15);
        assert!((m.determinant() - 1.0).abs() < 1e-15);
        assert!(f.e1.z.abs() < 1e-16, "e1 lies in the table");
        let z_in_frame = up_in_frame(0.55);
        assert!((f.to_world(&z_in_frame) - Vector3::z()).norm() < 1e-15);
        assert!(f.to_world(&lateral_in_frame(0.55)).z.abs() < 1e-15);
    }
}
