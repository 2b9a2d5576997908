//! A film's marks: four flat discs lying in the plane of the top edge, each centred on the
//! point where the recording format puts a mark. Seen by an orthographic camera a flat disc is
//! an ellipse centred on the image of its centre, so the true mark is the visible one's centre;
//! and as the whole body lies below that plane, the body never hides them from above.

use super::mesh::{BodyGeometry, MeshData, Vertex};
use std::f32::consts::{FRAC_PI_2, TAU};

/// Triangles per disc.
const DISC_SEGMENTS: usize = 48;
/// How far above the top edge the discs float, in outer radii: above the top face in the
/// depth test, far below a pixel.
const LIFT: f32 = 2e-4;

/// Four discs, marks 1 to 4 at 0, 90, 180 and 270 degrees from the ring's own `+X` towards
/// `+Z` (the format's forward order, `recording::marks`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarkDiscs {
    /// Radius of the circle the discs' centres sit on (the format's mark radius).
    pub circle: f32,
    /// Radius of each disc.
    pub radius: f32,
    /// Paint of marks 1 to 4: linear RGB, multiplied by the body's colour.
    pub colours: [[f32; 3]; 4],
}

impl MarkDiscs {
    /// A key for caching meshes.
    pub fn key(&self) -> [u32; 14] {
        let mut k = [0u32; 14];
        k[0] = self.circle.to_bits();
        k[1] = self.radius.to_bits();
        for (m, c) in self.colours.iter().enumerate() {
            for (j, v) in c.iter().enumerate() {
                k[2 + 3 * m + j] = v.to_bits();
            }
        }
        k
    }

    /// The discs' triangles for a body of geometry `g`, facing `+Y`.
    pub fn mesh(&self, g: &BodyGeometry) -> MeshData {
        let mut m = MeshData::default();
        let y = 0.5 * g.h + LIFT * g.r;
        let normal = [0.0, 1.0, 0.0];
        for (k, rgb) in self.colours.iter().enumerate() {
            let a = k as f32 * FRAC_PI_2;
            let c = [self.circle * a.cos(), y, self.circle * a.sin()];
            // Matte: a highlight would wash a dark mark out seen from above.
            let color = [rgb[0], rgb[1], rgb[2], -1.0];
            let base = m.vertices.len() as u32;
            m.vertices.push(Vertex { pos: c, normal, color });
            for i in 0..DISC_SEGMENTS {
                let b = i as f32 * TAU / DISC_SEGMENTS as f32;
                let pos = [c[0] + self.radius * b.cos(), y, c[2] + self.radius * b.sin()];
                m.vertices.push(Vertex { pos, normal, color });
            }
            for i in 0..DISC_SEGMENTS as u32 {
                let (p0, p1) = (base + 1 + i, base + 1 + (i + 1) % DISC_SEGMENTS as u32);
                // Counter-clockwise seen from +Y: from +X towards +Z turns clockwise there.
                m.indices.extend_from_slice(&[base, p1, p0]);
            }
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn discs_face_up_above_the_top_edge_centred_on_the_marks() {
        let g = BodyGeometry { r: 20.0, h: 18.0, w: 1.0 };
        let d = MarkDiscs { circle: 19.5, radius: 1.0, colours: [[1.0, 0.0, 0.0]; 4] };
        let m = d.mesh(&g);
        for t in m.indices.chunks(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| m.vertices[i as usize].pos);
            let (u, v) = ([b[0] - a[0], b[2] - a[2]], [c[0] - a[0], c[2] - a[2]]);
            // The Y component of (b - a) x (c - a).
            assert!(u[1] * v[0] - u[0] * v[1] > 0.0, "triangle {t:?} faces down");
        }
        assert!(m.vertices.iter().all(|v| v.pos[1] > 9.0 && v.pos[1] < 9.01));
        for (k, want) in [[19.5, 0.0], [0.0, 19.5], [-19.5, 0.0], [0.0, -19.5]].iter().enumerate() {
            let rim = &m.vertices[k * (DISC_SEGMENTS + 1) + 1..(k + 1) * (DISC_SEGMENTS + 1)];
            let n = rim.len() as f32;
            let mean = [
                rim.iter().map(|v| v.pos[0]).sum::<f32>() / n,
                rim.iter().map(|v| v.pos[2]).sum::<f32>() / n,
            ];
            assert!((mean[0] - want[0]).abs() < 1e-4 && (mean[1] - want[1]).abs() < 1e-4);
        }
        assert_ne!(d.key(), MarkDiscs { radius: 1.1, ..d }.key());
    }
}
