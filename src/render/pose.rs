//! From the physics state to the picture: `world_from_ring` and the points the scene marks.

use crate::physics::{Body, Sample};
use glam::{DMat3, DVec3, Mat4, Vec2, Vec3};

/// The rigid motion taking the ring's own coordinates (axis along +Y, see [`super::mesh`]) to
/// the table's: the Resal frame `(e1, e2, e3)` of `phi` and `theta` (PHYSICS.md) as columns,
/// turned by the spin `psi` about `e2`, placed at the centre of mass `c`.
pub fn world_from_ring(phi: f64, theta: f64, psi: f64, c: DVec3) -> Mat4 {
    let (sp, cp) = phi.sin_cos();
    let (st, ct) = theta.sin_cos();
    let e1 = DVec3::new(cp, sp, 0.0);
    let e2h = DVec3::new(-sp, cp, 0.0);
    let e2 = ct * e2h + st * DVec3::Z;
    let e3 = -st * e2h + ct * DVec3::Z;
    let world_from_frame = DMat3::from_cols(e1, e2, e3);
    let r = world_from_frame * DMat3::from_rotation_y(psi);
    Mat4::from_cols(
        r.x_axis.as_vec3().extend(0.0),
        r.y_axis.as_vec3().extend(0.0),
        r.z_axis.as_vec3().extend(0.0),
        c.as_vec3().extend(1.0),
    )
}

/// Where a body is at one state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyPose {
    pub world_from_ring: Mat4,
    /// The contact point P on the table.
    pub contact: Vec2,
    /// Point A, the centre of the top edge.
    pub point_a: Vec3,
    /// The centre of mass C.
    pub center: Vec3,
}

impl BodyPose {
    pub fn new(s: &Sample, body: &Body) -> BodyPose {
        let c = DVec3::new(s.x_c(), s.y_c(), s.z_c);
        let world_from_ring = world_from_ring(s.phi(), s.theta(), s.psi(), c);
        let a = world_from_ring.transform_point3(Vec3::new(0.0, 0.5 * body.h as f32, 0.0));
        BodyPose {
            world_from_ring,
            contact: Vec2::new(s.x_p as f32, s.y_p as f32),
            point_a: a,
            center: c.as_vec3(),
        }
    }
}

impl BodyPose {
    /// A body rolling on the table with point A over `a` (table) and Euler angles `phi, theta,
    /// psi`: where a recording puts its ring (no state vector, no dynamics).
    pub fn on_table(phi: f64, theta: f64, psi: f64, a: [f64; 2], body: &Body) -> BodyPose {
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        let half = 0.5 * body.h;
        // C = A - (h/2) e2; P = C - (h/2) e2 - R e3 lies on the table (as in `Sample`).
        let c = DVec3::new(a[0] + half * ct * sp, a[1] - half * ct * cp, half * st + body.r * ct);
        let lever = body.r * st - half * ct;
        let world_from_ring = world_from_ring(phi, theta, psi, c);
        let point_a = world_from_ring.transform_point3(Vec3::new(0.0, half as f32, 0.0));
        BodyPose {
            world_from_ring,
            contact: Vec2::new((c.x - lever * sp) as f32, (c.y + lever * cp) as f32),
            point_a,
            center: c.as_vec3(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::paper;

    #[test]
    fn contact_point_touches_the_table_and_a_is_the_top_edge_centre() {
        let model = paper::ring_model(paper::C_RING);
        let (summary, samples) = crate::physics::simulate(
            model.clone(),
            &paper::initial(),
            crate::physics::RunOptions { sample_dt: Some(0.7), t_end: 30.0, ..Default::default() },
        )
        .expect("runs");
        assert!(summary.t_end > 29.0);
        let b = &model.body;
        for s in &samples {
            let pose = BodyPose::new(s, b);
            // P = C - (h/2) e2 - R e3: (0, -h/2, -R) in the frame, which does not spin with psi.
            let c = DVec3::new(s.x_c(), s.y_c(), s.z_c);
            let frame = world_from_ring(s.phi(), s.theta(), 0.0, c);
            let p = frame.transform_point3(Vec3::new(0.0, -0.5 * b.h as f32, -b.r as f32));
            assert!(p.z.abs() < 1e-5, "contact at z = {} (t = {})", p.z, s.t);
            assert!((p.truncate() - pose.contact).length() < 1e-4);
            assert!(
                (pose.point_a.x - s.x_a as f32).abs() < 1e-4
                    && (pose.point_a.y - s.y_a as f32).abs() < 1e-4
            );
            // From the angles and A alone, as a recording gives them: the same pose.
            let from_a = BodyPose::on_table(s.phi(), s.theta(), s.psi(), [s.x_a, s.y_a], b);
            assert!(from_a.world_from_ring.abs_diff_eq(pose.world_from_ring, 1e-4), "t = {}", s.t);
            assert!((from_a.contact - pose.contact).length() < 1e-4);
            // Every point of the lower rim stays on or above the table.
            for k in 0..16 {
                let a = k as f32 * std::f32::consts::TAU / 16.0;
                let q = pose.world_from_ring.transform_point3(Vec3::new(
                    b.r as f32 * a.cos(),
                    -0.5 * b.h as f32,
                    b.r as f32 * a.sin(),
                ));
                assert!(q.z > -1e-5, "rim below the table at t = {}", s.t);
            }
        }
    }
}
