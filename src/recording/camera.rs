//! The camera of a recording: it looks straight down on the table (orthographic: the
//! format's scale `px_per_mm` holds everywhere on the table plane, and the sample recording
//! agrees with it to its noise). Pixel x grows to the right, y downward; the table's `Y`
//! grows upward, so `y_px = origin_y - K Y`.
//!
//! Radial lens distortion (the `camera_distortion` effect, strength `k1`): a point at
//! undistorted pixel position `u` is seen at `c + (u - c) (1 + k1 rho^2)`, with `c` the image
//! centre and `rho = |u - c| / d`, `d` the image's half-diagonal. So `k1 = 0.01` moves a
//! point in the image corner outward by 1% of its distance from the centre; `k1 < 0` is
//! barrel distortion, `k1 > 0` pincushion.

use super::{FrameMarks, Header};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub px_per_mm: f64,
    /// Pixel position of the table's origin.
    pub origin_px: [f64; 2],
    /// Centre of the radial distortion: the image centre.
    pub centre_px: [f64; 2],
    /// Half the image diagonal in pixels (the unit of `rho`).
    pub half_diagonal_px: f64,
    /// Radial distortion coefficient (0: none).
    pub k1: f64,
}

impl Camera {
    /// An undistorted camera over an image of `width x height` pixels whose centre is the
    /// table's origin (how `synth` places the start, and the sample's `pixel_origin`).
    pub fn centred(px_per_mm: f64, width_px: f64, height_px: f64) -> Camera {
        let centre = [width_px / 2.0, height_px / 2.0];
        Camera { px_per_mm, origin_px: centre, centre_px: centre, half_diagonal_px: 0.5 * width_px.hypot(height_px), k1: 0.0 }
    }

    /// The camera a recording describes: the image size from the header, or else the
    /// bounding box of the tracked marks (the format's default); the table's origin at the
    /// image centre; no distortion (the format does not describe it).
    pub fn for_recording(header: &Header, frames: &[FrameMarks]) -> Camera {
        if let (Some(w), Some(h)) = (header.image_width_px, header.image_height_px) {
            return Camera::centred(header.px_per_mm, w, h);
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in frames.iter().flatten().flatten() {
            for i in 0..2 {
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
        }
        if !(lo[0].is_finite() && hi[0].is_finite()) {
            return Camera::centred(header.px_per_mm, 2.0, 2.0);
        }
        let w = header.image_width_px.unwrap_or((hi[0] - lo[0]).max(1.0));
        let h = header.image_height_px.unwrap_or((hi[1] - lo[1]).max(1.0));
        let centre = [
            header.image_width_px.map_or(0.5 * (lo[0] + hi[0]), |w| w / 2.0),
            header.image_height_px.map_or(0.5 * (lo[1] + hi[1]), |h| h / 2.0),
        ];
        Camera { px_per_mm: header.px_per_mm, origin_px: centre, centre_px: centre, half_diagonal_px: 0.5 * w.hypot(h), k1: 0.0 }
    }

    /// Pixel position of a table point given in mm.
    #[inline]
    pub fn to_px(&self, x_mm: f64, y_mm: f64) -> [f64; 2] {
        let u = [self.origin_px[0] + self.px_per_mm * x_mm, self.origin_px[1] - self.px_per_mm * y_mm];
        if self.k1 == 0.0 {
            return u;
        }
        let d = [u[0] - self.centre_px[0], u[1] - self.centre_px[1]];
        let f = 1.0 + self.k1 * (d[0] * d[0] + d[1] * d[1]) / (self.half_diagonal_px * self.half_diagonal_px);
        [self.centre_px[0] + d[0] * f, self.centre_px[1] + d[1] * f]
    }

    /// Table point (mm) seen at pixel `p`: the inverse of [`Camera::to_px`]. The distortion
    /// is undone by Newton's method on the radius (exact where the mapping is monotone).
    pub fn to_mm(&self, p: [f64; 2]) -> [f64; 2] {
        let mut u = p;
        if self.k1 != 0.0 {
            let d = [p[0] - self.centre_px[0], p[1] - self.centre_px[1]];
            let rd = d[0].hypot(d[1]) / self.half_diagonal_px;
            if rd > 0.0 {
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
                u = [self.centre_px[0] + d[0] * s, self.centre_px[1] + d[1] * s];
            }
        }
        [(u[0] - self.origin_px[0]) / self.px_per_mm, -(u[1] - self.origin_px[1]) / self.px_per_mm]
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
                assert!((back[0] - p[0]).abs() < 1e-9 && (back[1] - p[1]).abs() < 1e-9, "k1 {k1}: {p:?} -> {back:?}");
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
}
