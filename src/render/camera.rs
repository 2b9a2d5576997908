//! The orbit camera: it looks at a target on the table from a yaw, a pitch and a distance.

use glam::{Mat4, Vec3};

/// Vertical field of view.
pub const FOV_Y: f32 = 0.62;
const PITCH_MIN: f32 = 0.05;
const PITCH_MAX: f32 = 1.52;

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct OrbitCamera {
    pub target: [f32; 3],
    /// Angle of the eye round the target, from +X, counter-clockwise seen from above.
    pub yaw: f32,
    /// Elevation of the eye above the table plane.
    pub pitch: f32,
    pub distance: f32,
}

/// What the renderer needs of a camera for one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraView {
    pub eye: Vec3,
    pub target: Vec3,
    pub fov_y: f32,
    /// Some: an orthographic camera (a film's) whose picture is this high in world units;
    /// `fov_y` is then unused.
    pub ortho_height: Option<f32>,
}

impl OrbitCamera {
    /// The default view of a body of outer radius `scale`: from the front-left, above.
    pub fn default_for(scale: f32) -> OrbitCamera {
        OrbitCamera { target: [0.0; 3], yaw: -1.9, pitch: 0.62, distance: 9.0 * scale }
    }

    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        Vec3::from(self.target) + self.distance * Vec3::new(cp * cy, cp * sy, sp)
    }

    pub fn view(&self) -> CameraView {
        CameraView {
            eye: self.eye(),
            target: Vec3::from(self.target),
            fov_y: FOV_Y,
            ortho_height: None,
        }
    }

    /// Turns by a drag of `dx, dy` pixels.
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * 0.008;
        self.pitch = (self.pitch + dy * 0.006).clamp(PITCH_MIN, PITCH_MAX);
    }

    /// Moves in (`steps > 0`) or out by scroll steps, within `[min, max]`.
    pub fn zoom(&mut self, steps: f32, min: f32, max: f32) {
        self.distance = (self.distance * (-0.12 * steps).exp()).clamp(min, max);
    }
}

impl CameraView {
    /// Straight down on `centre` of the table from `distance` above it, orthographic, the
    /// table's `+X` to the picture's right and `+Y` up it; the picture `height` high.
    pub fn top_down(centre: glam::Vec2, height: f32, distance: f32) -> CameraView {
        CameraView {
            eye: centre.extend(distance),
            target: centre.extend(0.0),
            fov_y: FOV_Y,
            ortho_height: Some(height),
        }
    }

    pub fn view_matrix(&self) -> Mat4 {
        // Up is the table's +Y where the camera looks straight down (Z would be degenerate).
        let dir = (self.target - self.eye).normalize_or_zero();
        let up = if dir.cross(Vec3::Z).length_squared() < 1e-8 { Vec3::Y } else { Vec3::Z };
        glam::camera::rh::view::look_at_mat4(self.eye, self.target, up)
    }

    /// The size of a pixel in world units at unit distance from the eye, in a picture
    /// `height_px` high (for an orthographic camera: at the target's distance).
    pub fn pixel_angle(&self, height_px: u32) -> f32 {
        let h = height_px.max(1) as f32;
        match self.ortho_height {
            Some(world) => world / h / (self.eye - self.target).length().max(1e-6),
            None => 2.0 * (0.5 * self.fov_y).tan() / h,
        }
    }

    /// Projection for wgpu's clip space (z in [0, 1]) with near and far planes that suit the
    /// distance to the target.
    pub fn proj_matrix(&self, aspect: f32, far: f32) -> Mat4 {
        let d = (self.eye - self.target).length().max(1e-6);
        if let Some(height) = self.ortho_height {
            let (hh, hw) = (0.5 * height, 0.5 * height * aspect.max(1e-3));
            return glam::camera::rh::proj::directx::orthographic(
                -hw,
                hw,
                -hh,
                hh,
                0.02 * d,
                far.max(2.0 * d),
            );
        }
        glam::camera::rh::proj::directx::perspective(
            self.fov_y,
            aspect.max(1e-3),
            0.02 * d,
            far.max(2.0 * d),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn target_projects_to_the_centre_and_up_stays_up() {
        let cam = OrbitCamera { target: [1.0, 2.0, 0.0], ..OrbitCamera::default_for(1.0) };
        let v = cam.view();
        let m = v.proj_matrix(1.5, 100.0) * v.view_matrix();
        let c = m.project_point3(Vec3::new(1.0, 2.0, 0.0));
        assert!(c.x.abs() < 1e-5 && c.y.abs() < 1e-5);
        assert!(c.z > 0.0 && c.z < 1.0);
        let above = m.project_point3(Vec3::new(1.0, 2.0, 0.5));
        assert!(above.y > c.y, "a point above the target is higher on screen");
    }

    #[test]
    fn top_down_maps_table_to_pixels_with_x_right_and_y_up() {
        // 10 world units high on 100 x 50 pixels: 5 pixels per unit.
        let v = CameraView::top_down(glam::Vec2::new(3.0, -2.0), 10.0, 40.0);
        let m = v.proj_matrix(2.0, 100.0) * v.view_matrix();
        let ndc = |p: Vec3| m.project_point3(p);
        assert!(ndc(Vec3::new(3.0, -2.0, 0.0)).truncate().length() < 1e-6);
        let right = ndc(Vec3::new(13.0, -2.0, 0.0));
        assert!((right.x - 1.0).abs() < 1e-5 && right.y.abs() < 1e-5, "{right}");
        let up = ndc(Vec3::new(3.0, 3.0, 0.0));
        assert!((up.y - 1.0).abs() < 1e-5 && up.x.abs() < 1e-5, "{up}");
        // Height does not move a point (orthographic), and a higher one is nearer.
        let high = ndc(Vec3::new(13.0, -2.0, 5.0));
        assert!((high.x - 1.0).abs() < 1e-5 && high.z < right.z && high.z > 0.0);
        assert!((v.pixel_angle(50) - 0.2 / 40.0).abs() < 1e-7);
    }

    #[test]
    fn pitch_and_zoom_stay_within_limits() {
        let mut cam = OrbitCamera::default_for(1.0);
        cam.orbit(0.0, 1e6);
        assert!(cam.pitch <= PITCH_MAX);
        cam.zoom(1e3, 0.5, 50.0);
        assert_eq!(cam.distance, 0.5);
        cam.zoom(-1e3, 0.5, 50.0);
        assert_eq!(cam.distance, 50.0);
    }
}
