//! The camera of a recording, looking down on the table. Table `X` runs to the image's right,
//! table `Y` up the image (pixel y grows downward, so `y_px = origin_y - K Y` straight
//! below the camera), `Z` up from the table; lengths in mm.
//!
//! Projection ([`Camera::distance_mm`], [`Camera::tilt_rad`]):
//! - Orthographic (`distance_mm = None`, the default; the sample agrees with it to its
//!   noise): the scale `K = px_per_mm` holds everywhere on the table plane.
//! - Pinhole at distance `D`: the optical axis meets the table at its origin (pixel
//!   `origin_px`); `K` holds at the table plane there, so the focal length is `f = K D` px.
//!   Turned by `t = tilt_rad` about the table's `X` axis, positive towards `-Y` (the camera
//!   moved towards the image's bottom edge, looking back at the origin: the convention of the
//!   independent simulator's recordings, whose 10 degree camera fits as +10), and with
//!   `u = -t`: the centre of projection is at `Cc = (0, D sin u, D cos u)`, the axis
//!   `a = -(0, sin u, cos u)`, the image directions `ex = (1, 0, 0)` and `ey = (0, -cos u, sin u)`
//!   (downward in the image). A point `P` is seen at
//!   `origin + f ((P - Cc).ex, (P - Cc).ey) / (P - Cc).a`: untilted, a point at height `z` is
//!   magnified by `D / (D - z)` about the origin. A point at or behind the camera's centre
//!   plane (`(P - Cc).a <= 0`) has no image: its pixel is `[NaN, NaN]`, which a fit's residuals
//!   treat as outside the model's domain.
//! - An orthographic camera with a tilt projects along the tilted axis (the pinhole's limit
//!   `D -> infinity` at fixed `K`): `origin + K (P.ex, P.ey)`.
//!
//! Radial lens distortion (the `camera_distortion` effect, strength `k1`), applied after the
//! projection: a point at undistorted pixel position `u` is seen at
//! `c + (u - c) (1 + k1 rho^2)`, with `c` the image centre and `rho = |u - c| / d`, `d` the
//! image's half-diagonal. So `k1 = 0.01` moves a point in the image corner outward by 1% of its
//! distance from the centre; `k1 < 0` is barrel distortion, `k1 > 0` pincushion.

use super::{FrameMarks, Header};
use crate::physics::effects::CameraNumbers;

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Camera {
    pub px_per_mm: f64,
    /// Pixel position of the table's origin (where the optical axis meets the table).
    pub origin_px: [f64; 2],
    /// Centre of the radial distortion: the image centre.
    pub centre_px: [f64; 2],
    /// Half the image diagonal in pixels (the unit of `rho`).
    pub half_diagonal_px: f64,
    /// Radial distortion coefficient (0: none).
    pub k1: f64,
    /// Distance (mm) from the centre of projection to the table along the optical axis; None:
    /// orthographic.
    pub distance_mm: Option<f64>,
    /// Angle (rad) of the optical axis from the table's normal, turned about the table's `X`
    /// axis; positive: the camera sits towards `-Y` (the image's bottom edge).
    pub tilt_rad: f64,
    /// Whether `px_per_mm` is a tracker's estimate through a near camera (the header's
    /// `px_per_mm_from` says [`NEAR_RING_SCALE`]): the marks ride above the table, so their
    /// own scale says the table's only through the camera's distance, which the perspective's
    /// fit then corrects with it.
    pub scale_free: bool,
}

/// The least tilt (degrees) of a tripod's camera: below it the camera looks down on the table
/// (a tracker leaves its perspective to the ring's scale fit and the diagnosis's pinhole,
/// `camera_perspective`, which fit it with the motion, and `recover` maps marks flat).
pub const TRIPOD_TILT_DEG: f64 = 10.0;

/// The start of the header's `px_per_mm_from` where a tracker fitted the table's scale from the
/// ring through a near camera.
pub const NEAR_RING_SCALE: &str = "ring through a near camera";

impl Camera {
    /// The numbers an effect can set (`physics::effects`).
    pub fn numbers(&self) -> CameraNumbers {
        CameraNumbers {
            px_per_mm: self.px_per_mm,
            k1: self.k1,
            distance_mm: self.distance_mm,
            tilt_rad: self.tilt_rad,
            scale_free: self.scale_free,
        }
    }

    /// Sets the numbers an effect can set.
    pub fn set_numbers(&mut self, n: &CameraNumbers) {
        self.px_per_mm = n.px_per_mm;
        self.k1 = n.k1;
        self.distance_mm = n.distance_mm;
        self.tilt_rad = n.tilt_rad;
    }

    /// An undistorted orthographic camera over an image of `width x height` pixels whose centre
    /// is the table's origin (how `synth` places the start, and the sample's `pixel_origin`).
    pub fn centred(px_per_mm: f64, width_px: f64, height_px: f64) -> Camera {
        let centre = [width_px / 2.0, height_px / 2.0];
        Camera {
            px_per_mm,
            origin_px: centre,
            centre_px: centre,
            half_diagonal_px: 0.5 * width_px.hypot(height_px),
            k1: 0.0,
            distance_mm: None,
            tilt_rad: 0.0,
            scale_free: false,
        }
    }

    /// The camera a recording describes: the image size from the header, or else the
    /// bounding box of the tracked marks (the format's default); the table's origin at the
    /// image centre; the header's distance and tilt where it gives them (orthographic and
    /// untilted otherwise); no distortion (the format does not describe it).
    pub fn for_recording(header: &Header, frames: &[FrameMarks]) -> Camera {
        let scale_free = header
            .extra
            .iter()
            .any(|(k, v)| k == "px_per_mm_from" && v.starts_with(NEAR_RING_SCALE));
        let view = |cam: Camera| Camera {
            distance_mm: header.camera_distance_mm,
            tilt_rad: header.camera_tilt_deg.map_or(0.0, f64::to_radians),
            scale_free,
            ..cam
        };
        if let (Some(w), Some(h)) = (header.image_width_px, header.image_height_px) {
            return view(Camera::centred(header.px_per_mm, w, h));
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in frames.iter().flatten().flatten() {
            for i in 0..2 {
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
        }
        if !(lo[0].is_finite() && hi[0].is_finite()) {
            return view(Camera::centred(header.px_per_mm, 2.0, 2.0));
        }
        let w = header.image_width_px.unwrap_or((hi[0] - lo[0]).max(1.0));
        let h = header.image_height_px.unwrap_or((hi[1] - lo[1]).max(1.0));
        let centre = [
            header.image_width_px.map_or(0.5 * (lo[0] + hi[0]), |w| w / 2.0),
            header.image_height_px.map_or(0.5 * (lo[1] + hi[1]), |h| h / 2.0),
        ];
        view(Camera {
            origin_px: centre,
            centre_px: centre,
            half_diagonal_px: 0.5 * w.hypot(h),
            ..Camera::centred(header.px_per_mm, w, h)
        })
    }

    /// Whether a point's height above the table moves its pixel (a pinhole or a tilted camera):
    /// where it does not, callers may skip the heights.
    #[inline]
    pub fn sees_height(&self) -> bool {
        self.distance_mm.is_some() || self.tilt_rad != 0.0
    }

    /// Pixel position of a table point given in mm.
    #[inline]
    pub fn to_px(&self, x_mm: f64, y_mm: f64) -> [f64; 2] {
        self.to_px3(x_mm, y_mm, 0.0)
    }

    /// Pixel position of a point `z_mm` above the table (`[NaN, NaN]` at or behind the
    /// camera's centre plane).
    #[inline]
    pub fn to_px3(&self, x_mm: f64, y_mm: f64, z_mm: f64) -> [f64; 2] {
        self.px3_tilted(self.tilt_sin_cos(), x_mm, y_mm, z_mm)
    }

    /// [`Camera::to_px3`] of several points: the tilt's sine and cosine once for all of them
    /// (a fit projects four marks a frame, thousands of frames a run).
    #[inline]
    pub fn to_px3_each<const N: usize>(&self, points: [[f64; 3]; N]) -> [[f64; 2]; N] {
        let sc = self.tilt_sin_cos();
        points.map(|p| self.px3_tilted(sc, p[0], p[1], p[2]))
    }

    /// `sin` and `cos` of minus the tilt (the projection's turn about the table's `X` axis).
    #[inline]
    fn tilt_sin_cos(&self) -> (f64, f64) {
        if self.tilt_rad == 0.0 { (-0.0, 1.0) } else { (-self.tilt_rad).sin_cos() }
    }

    /// [`Camera::to_px3`] with the tilt's `(s, c)` from [`Camera::tilt_sin_cos`].
    #[inline]
    fn px3_tilted(&self, (s, c): (f64, f64), x_mm: f64, y_mm: f64, z_mm: f64) -> [f64; 2] {
        let (o, k) = (self.origin_px, self.px_per_mm);
        let u = match (self.distance_mm, self.tilt_rad) {
            (None, 0.0) => [o[0] + k * x_mm, o[1] - k * y_mm],
            (None, _) => [o[0] + k * x_mm, o[1] + k * (s * z_mm - c * y_mm)],
            (Some(d), _) => {
                // (P - Cc).a, and f over it.
                let depth = d - s * y_mm - c * z_mm;
                if !(depth > 0.0) {
                    return [f64::NAN; 2];
                }
                let g = k * d / depth;
                [o[0] + g * x_mm, o[1] + g * (s * z_mm - c * y_mm)]
            }
        };
        self.distort(u)
    }

    /// Table point (mm) seen at pixel `p`: the inverse of [`Camera::to_px`].
    pub fn to_mm(&self, p: [f64; 2]) -> [f64; 2] {
        self.to_mm_at(p, 0.0)
    }

    /// The point on the plane `z_mm` above the table seen at pixel `p` (mm): the inverse of
    /// [`Camera::to_px3`] at that height. `[NaN, NaN]` where the pixel's ray does not meet the
    /// plane in front of the camera (beyond a tilted camera's horizon, or a plane above it).
    pub fn to_mm_at(&self, p: [f64; 2], z_mm: f64) -> [f64; 2] {
        let u = self.undistort(p);
        let (o, k) = (self.origin_px, self.px_per_mm);
        match (self.distance_mm, self.tilt_rad) {
            (None, 0.0) => [(u[0] - o[0]) / k, -(u[1] - o[1]) / k],
            (None, t) => {
                let (s, c) = (-t).sin_cos();
                [(u[0] - o[0]) / k, (s * z_mm - (u[1] - o[1]) / k) / c]
            }
            (Some(d), t) => {
                let (s, c) = (-t).sin_cos();
                // The ray Cc + l (m ex + n ey + a), l its depth along the axis.
                let f = k * d;
                let (m, n) = ((u[0] - o[0]) / f, (u[1] - o[1]) / f);
                let l = (z_mm - d * c) / (n * s - c);
                if !(l > 0.0 && l.is_finite()) {
                    return [f64::NAN; 2];
                }
                [l * m, d * s - l * (n * c + s)]
            }
        }
    }

    /// The radial distortion of an undistorted pixel position.
    #[inline]
    fn distort(&self, u: [f64; 2]) -> [f64; 2] {
        if self.k1 == 0.0 {
            return u;
        }
        let d = [u[0] - self.centre_px[0], u[1] - self.centre_px[1]];
        let f = 1.0
            + self.k1 * (d[0] * d[0] + d[1] * d[1])
                / (self.half_diagonal_px * self.half_diagonal_px);
        [self.centre_px[0] + d[0] * f, self.centre_px[1] + d[1] * f]
    }

    /// The inverse of [`Camera::distort`], by Newton's method on the radius (exact where the
    /// mapping is monotone).
    fn undistort(&self, p: [f64; 2]) -> [f64; 2] {
        if self.k1 == 0.0 {
            return p;
        }
        let d = [p[0] - self.centre_px[0], p[1] - self.centre_px[1]];
        let rd = d[0].hypot(d[1]) / self.half_diagonal_px;
        if !(rd > 0.0) {
            return p;
        }
        // Solve r (1 + k1 r^2) = rd for the undistorted radius r.
        let mut r = rd;
        for _ in 0..30 {
            let g = r * (1.0 + self.k1 * r * r) - rd;
            let dg = 1.0 + 3.0 * self.k1 * r * r;
            if dg <= 1e-12 {
                break;
            }
            let step = g / dg;
            r -= step;
            if step.abs() < 1e-15 {
                break;
            }
        }
        let s = r / rd;
        [self.centre_px[0] + d[0] * s, self.centre_px[1] + d[1] * s]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distortion_round_trips() {
        for k1 in [-0.05, 0.0, 0.02, 0.1] {
            let cam = Camera { k1, ..Camera::centred(3.0, 1280.0, 1024.0) };
            for p in [[0.0, 0.0], [100.0, -50.0], [-200.0, 150.0]] {
                let back = cam.to_mm(cam.to_px(p[0], p[1]));
                assert!(
                    (back[0] - p[0]).abs() < 1e-9 && (back[1] - p[1]).abs() < 1e-9,
                    "k1 {k1}: {p:?} -> {back:?}"
                );
            }
        }
        // y grows downward in the image, upward on the table.
        let cam = Camera::centred(2.0, 100.0, 100.0);
        assert_eq!(cam.to_px(1.0, 1.0), [52.0, 48.0]);
        // A corner point moves out by k1 of its distance from the centre.
        let cam = Camera { k1: 0.01, ..cam };
        let corner = cam.to_px(25.0, 25.0);
        assert!((corner[0] - (50.0 + 50.0 * 1.01)).abs() < 1e-12);
    }

    #[test]
    fn points_projected_together_are_each_projected_alone() {
        let points = [[10.0, 20.0, 25.0], [-30.0, 5.0, 0.0], [0.0, -40.0, 12.0]];
        let base = Camera { k1: 0.02, ..Camera::centred(2.0, 1280.0, 1024.0) };
        for (distance_mm, tilt_rad) in
            [(None, 0.0), (None, 0.3), (Some(500.0), 0.0), (Some(500.0), -0.5)]
        {
            let cam = Camera { distance_mm, tilt_rad, ..base };
            let each = cam.to_px3_each(points);
            for (p, e) in points.iter().zip(each) {
                // To the bit: the tilt's sine and cosine are the same numbers either way.
                assert_eq!(e, cam.to_px3(p[0], p[1], p[2]), "{distance_mm:?}, tilt {tilt_rad}");
            }
        }
    }

    #[test]
    fn orthographic_ignores_height() {
        let cam = Camera::centred(3.364764, 1280.0, 1024.0);
        assert!(!cam.sees_height());
        for p in [[0.0, 0.0, 0.0], [12.5, -40.0, 30.0], [-200.0, 150.0, -5.0]] {
            let expected = [640.0 + 3.364764 * p[0], 512.0 - 3.364764 * p[1]];
            assert_eq!(cam.to_px3(p[0], p[1], p[2]), expected);
            assert_eq!(cam.to_mm_at(expected, p[2]), cam.to_mm(expected));
        }
    }

    #[test]
    fn pinhole_by_hand() {
        let close =
            |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9;
        // K = 2 px/mm, D = 500 mm, untilted, origin (640, 512): the point (10, 20, 25) is
        // magnified by D / (D - z) = 500 / 475 about the axis, so it is seen at
        // (640 + 2 * 10 * 500 / 475, 512 - 2 * 20 * 500 / 475) = (640 + 21.0526316, 512 - 42.1052632).
        let cam = Camera { distance_mm: Some(500.0), ..Camera::centred(2.0, 1280.0, 1024.0) };
        assert!(close(
            cam.to_px3(10.0, 20.0, 25.0),
            [661.052_631_578_947_4, 469.894_736_842_105_3]
        ));
        // On the table the scale is K everywhere, as orthographic.
        assert!(close(cam.to_px(10.0, 20.0), [660.0, 472.0]));
        // Tilted by 30 degrees towards +Y (tilt -30, u = 30: sin u 0.5, cos u sqrt(3)/2 =
        // 0.8660254), same point: f = K D = 1000, depth (P - Cc).a = D - y sin u - z cos u = 500 - 10 - 21.6506351 = 468.3493649,
        // (P - Cc).ex = x = 10, (P - Cc).ey = z sin u - y cos u = 12.5 - 17.3205081 = -4.8205081,
        // so the pixel is (640 + 1000 * 10 / 468.3493649, 512 - 1000 * 4.8205081 / 468.3493649)
        // = (640 + 21.3515823, 512 - 10.2925475).
        let cam = Camera { tilt_rad: -30f64.to_radians(), ..cam };
        assert!(close(
            cam.to_px3(10.0, 20.0, 25.0),
            [661.351_582_278_797_5, 501.707_452_519_632_3]
        ));
        // The axis point stays at the origin; the scale along X holds there, Y is foreshortened.
        assert!(close(cam.to_px(0.0, 0.0), [640.0, 512.0]));
        let (dx, dy) = (cam.to_px(1e-4, 0.0)[0] - 640.0, cam.to_px(0.0, 1e-4)[1] - 512.0);
        assert!(
            (dx / 1e-4 - 2.0).abs() < 1e-6
                && (dy / 1e-4 + 2.0 * 30f64.to_radians().cos()).abs() < 1e-6,
            "{dx} {dy}"
        );
    }

    #[test]
    fn pinhole_round_trips() {
        for distance in [None, Some(150.0), Some(450.0), Some(2000.0)] {
            for tilt in [-0.6, -0.2, 0.0, 0.25, 0.7] {
                for k1 in [0.0, -0.03] {
                    let cam = Camera {
                        distance_mm: distance,
                        tilt_rad: tilt,
                        k1,
                        ..Camera::centred(3.0, 1280.0, 1024.0)
                    };
                    for p in [
                        [0.0, 0.0, 0.0],
                        [60.0, -35.0, 0.0],
                        [-80.0, 50.0, 28.0],
                        [30.0, 90.0, 12.0],
                        [-45.0, -70.0, -3.0],
                    ] {
                        let px = cam.to_px3(p[0], p[1], p[2]);
                        assert!(px.iter().all(|v| v.is_finite()), "{distance:?} {tilt}: {p:?}");
                        let back = cam.to_mm_at(px, p[2]);
                        let err = (back[0] - p[0]).hypot(back[1] - p[1]);
                        assert!(
                            err < 1e-9,
                            "{distance:?} {tilt} {k1}: {p:?} -> {px:?} -> {back:?}"
                        );
                        if p[2] == 0.0 {
                            assert_eq!(cam.to_px(p[0], p[1]), px);
                            assert!((cam.to_mm(px)[0] - back[0]).abs() < 1e-12);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn heights_magnify_towards_the_camera() {
        let cam = Camera { distance_mm: Some(450.0), ..Camera::centred(3.0, 1280.0, 1024.0) };
        assert!(cam.sees_height());
        let (low, high) = (cam.to_px3(40.0, -30.0, 0.0), cam.to_px3(40.0, -30.0, 45.0));
        let r = |p: [f64; 2]| (p[0] - 640.0).hypot(p[1] - 512.0);
        assert!((r(high) / r(low) - 450.0 / 405.0).abs() < 1e-12);
        // An orthographic camera tilted towards +Y sees a raised point shifted down the image.
        let tilted = Camera { tilt_rad: -0.3, ..Camera::centred(3.0, 1280.0, 1024.0) };
        assert!(tilted.sees_height());
        assert!((tilted.to_px3(0.0, 0.0, 10.0)[1] - (512.0 + 30.0 * 0.3f64.sin())).abs() < 1e-12);
    }

    #[test]
    fn behind_the_camera_has_no_image() {
        let cam = Camera { distance_mm: Some(100.0), ..Camera::centred(3.0, 1280.0, 1024.0) };
        assert!(cam.to_px3(5.0, 5.0, 100.0).iter().all(|v| v.is_nan()));
        assert!(cam.to_px3(5.0, 5.0, 150.0).iter().all(|v| v.is_nan()));
        assert!(cam.to_mm_at([700.0, 500.0], 120.0).iter().all(|v| v.is_nan()));
        // Tilted 60 degrees towards +Y: far enough along +Y the table is behind the camera, and
        // a pixel far enough down the image (towards -Y) looks above the horizon.
        let cam = Camera { tilt_rad: -60f64.to_radians(), ..cam };
        assert!(cam.to_px(0.0, 200.0).iter().all(|v| v.is_nan()));
        assert!(cam.to_px(0.0, -200.0).iter().all(|v| v.is_finite()));
        assert!(cam.to_mm([640.0, 5000.0]).iter().all(|v| v.is_nan()));
        assert!(cam.to_mm([640.0, 600.0]).iter().all(|v| v.is_finite()));
    }
}
