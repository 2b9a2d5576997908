//! Triangle meshes of the bodies, in the ring's own frame: symmetry axis along local +Y (the
//! paper's `e2`), the circle in the local XZ plane (`e1`, `e3`), centre of mass at the origin.
//! The ring is a real tube (outer and inner wall, both rims); a disk is a solid cylinder. The
//! four tracking marks are painted at the top edge (`+h/2`, the edge of point A), 90 degrees
//! apart, mark 1 in its own colour, so the spin reads in the picture.

use bytemuck::{Pod, Zeroable};
use std::f32::consts::TAU;

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct Vertex {
    pub pos: [f32; 3],
    pub normal: [f32; 3],
    /// Paint multiplied by the body's colour; alpha 1 for bare metal, 0 for paint, -1 for
    /// matte paint (no highlight).
    pub color: [f32; 4],
}

#[derive(Clone, Debug, Default)]
pub struct MeshData {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
}

/// The body's shape and size, what a mesh depends on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyGeometry {
    /// Outer radius R.
    pub r: f32,
    /// Width h along the axis.
    pub h: f32,
    /// Wall thickness w; `w >= r` is a solid disk.
    pub w: f32,
}

impl BodyGeometry {
    pub fn is_disk(&self) -> bool {
        self.w >= self.r
    }
    /// A key for caching meshes (sizes to about 1e-6 relative).
    pub fn key(&self) -> [u32; 3] {
        [self.r.to_bits(), self.h.to_bits(), self.w.to_bits()]
    }
}

/// Segments around the circle: 96, so that the marks (two segments wide, 7.5 degrees) fall on
/// segment boundaries.
pub const SEGMENTS: usize = 96;
/// Fraction of the width, from the top edge down, that the marks cover on the walls.
const MARK_DEPTH: f32 = 0.3;
const METAL: [f32; 4] = [1.0, 1.0, 1.0, 1.0];
const MARK_ONE: [f32; 4] = [0.85, 0.12, 0.10, 0.0];
const MARK: [f32; 4] = [0.08, 0.09, 0.12, 0.0];

fn on_circle(a: f32, radius: f32, y: f32) -> [f32; 3] {
    [radius * a.cos(), y, radius * a.sin()]
}

/// The paint of segment `i` (between angles `i` and `i+1` steps): the marks sit on the two
/// segments either side of 0, 90, 180 and 270 degrees.
fn mark_paint(i: usize) -> Option<[f32; 4]> {
    let quarter = SEGMENTS / 4;
    let k = i % quarter;
    if k == 0 || k == quarter - 1 {
        let mark = ((i + 1) % SEGMENTS) / quarter;
        Some(if mark == 0 { MARK_ONE } else { MARK })
    } else {
        None
    }
}

impl MeshData {
    /// Adds `other`'s triangles.
    pub fn append(&mut self, other: MeshData) {
        let base = self.vertices.len() as u32;
        self.vertices.extend(other.vertices);
        self.indices.extend(other.indices.into_iter().map(|i| i + base));
    }

    fn quad(&mut self, p: [[f32; 3]; 4], n: [[f32; 3]; 4], color: [f32; 4]) {
        let base = self.vertices.len() as u32;
        for k in 0..4 {
            self.vertices.push(Vertex { pos: p[k], normal: n[k], color });
        }
        self.indices.extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
    }

    /// A wall of radius `radius` between heights `y0 < y1`; normals outward (`sign` 1) or
    /// toward the axis (-1). `paint`'s marks cover the band above `y_mark`.
    fn wall(&mut self, radius: f32, y0: f32, y1: f32, sign: f32, y_mark: f32, paint: Paint) {
        let step = TAU / SEGMENTS as f32;
        for band in 0..2 {
            let (lo, hi) = if band == 0 { (y0, y_mark) } else { (y_mark, y1) };
            for i in 0..SEGMENTS {
                let (a0, a1) = (i as f32 * step, (i + 1) as f32 * step);
                let n0 = [sign * a0.cos(), 0.0, sign * a0.sin()];
                let n1 = [sign * a1.cos(), 0.0, sign * a1.sin()];
                let color = if band == 1 { paint(i).unwrap_or(METAL) } else { METAL };
                let p = [
                    on_circle(a0, radius, lo),
                    on_circle(a1, radius, lo),
                    on_circle(a1, radius, hi),
                    on_circle(a0, radius, hi),
                ];
                // Counter-clockwise seen from outside the surface.
                if sign > 0.0 {
                    self.quad([p[0], p[3], p[2], p[1]], [n0, n0, n1, n1], color);
                } else {
                    self.quad(p, [n0, n1, n1, n0], color);
                }
            }
        }
    }

    /// An annulus (or a disk, `inner = 0`) at height `y` facing `+Y` (`up`) or `-Y`;
    /// `paint`'s marks are painted on the top one beyond `r_mark`.
    fn annulus(
        &mut self,
        inner: f32,
        outer: f32,
        y: f32,
        up: bool,
        r_mark: Option<f32>,
        paint: Paint,
    ) {
        let step = TAU / SEGMENTS as f32;
        let n = [0.0, if up { 1.0 } else { -1.0 }, 0.0];
        let rings: Vec<(f32, f32, bool)> = match r_mark {
            Some(rm) if rm > inner && rm < outer => vec![(inner, rm, false), (rm, outer, true)],
            Some(_) => vec![(inner, outer, true)],
            None => vec![(inner, outer, false)],
        };
        for (r0, r1, marked) in rings {
            for i in 0..SEGMENTS {
                let (a0, a1) = (i as f32 * step, (i + 1) as f32 * step);
                let color = if marked { paint(i).unwrap_or(METAL) } else { METAL };
                let p = [
                    on_circle(a0, r0, y),
                    on_circle(a0, r1, y),
                    on_circle(a1, r1, y),
                    on_circle(a1, r0, y),
                ];
                if up {
                    self.quad([p[0], p[3], p[2], p[1]], [n; 4], color);
                } else {
                    self.quad(p, [n; 4], color);
                }
            }
        }
    }
}

/// The paint of segment `i`, if any.
type Paint = fn(usize) -> Option<[f32; 4]>;

/// The mesh of a ring (tube) or, for `w >= r`, a solid disk, with its four painted marks.
pub fn body_mesh(g: &BodyGeometry) -> MeshData {
    mesh_painted(g, mark_paint)
}

/// The same body in bare metal: a film's marks are drawn apart ([`super::mark_discs`]).
pub fn bare_body_mesh(g: &BodyGeometry) -> MeshData {
    mesh_painted(g, |_| None)
}

fn mesh_painted(g: &BodyGeometry, paint: Paint) -> MeshData {
    let mut m = MeshData::default();
    let (r, a) = (g.r, 0.5 * g.h);
    let y_mark = a - MARK_DEPTH * g.h;
    m.wall(r, -a, a, 1.0, y_mark, paint);
    if g.is_disk() {
        m.annulus(0.0, r, a, true, Some(0.72 * r), paint);
        m.annulus(0.0, r, -a, false, None, paint);
    } else {
        let ri = r - g.w;
        m.wall(ri, -a, a, -1.0, y_mark, paint);
        m.annulus(ri, r, a, true, Some(ri), paint);
        m.annulus(ri, r, -a, false, None, paint);
    }
    m
}

/// The table: a unit square in the plane z = 0 (scaled and moved by its model matrix).
pub fn table_mesh() -> MeshData {
    let n = [0.0, 0.0, 1.0];
    let c = [1.0, 1.0, 1.0, 0.0];
    let mut m = MeshData::default();
    m.quad([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]], [n; 4], c);
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    }
    fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }
    fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    /// Every triangle winds counter-clockwise seen from the side its normals face.
    fn assert_outward(m: &MeshData) {
        for t in m.indices.chunks(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| m.vertices[i as usize]);
            let face = cross(sub(b.pos, a.pos), sub(c.pos, a.pos));
            if dot(face, face) < 1e-14 {
                continue; // the sliver at a disk's centre
            }
            assert!(dot(face, a.normal) > 0.0, "triangle {t:?} winds against its normal");
        }
    }

    #[test]
    fn ring_is_a_tube_with_both_walls_and_rims() {
        let g = BodyGeometry { r: 1.025, h: 0.88, w: 0.05 };
        let m = body_mesh(&g);
        assert_outward(&m);
        let radii: Vec<f32> = m.vertices.iter().map(|v| v.pos[0].hypot(v.pos[2])).collect();
        let min = radii.iter().cloned().fold(f32::MAX, f32::min);
        let max = radii.iter().cloned().fold(0.0, f32::max);
        assert!((min - 0.975).abs() < 1e-5 && (max - 1.025).abs() < 1e-5, "walls at R - w and R");
        let ys: Vec<f32> = m.vertices.iter().map(|v| v.pos[1]).collect();
        assert!(ys.iter().all(|y| y.abs() <= 0.44 + 1e-6));
        // Four marks, one of them in its own colour, at the top only.
        let marked: Vec<&Vertex> = m.vertices.iter().filter(|v| v.color[3] == 0.0).collect();
        assert!(!marked.is_empty() && marked.iter().all(|v| v.pos[1] > 0.0));
        assert!(marked.iter().any(|v| v.color == MARK_ONE));
    }

    #[test]
    fn disk_is_solid() {
        let g = BodyGeometry { r: 1.0, h: 0.2, w: 1.0 };
        let m = body_mesh(&g);
        assert_outward(&m);
        assert!(m.vertices.iter().any(|v| v.pos[0].hypot(v.pos[2]) < 1e-6), "caps reach the axis");
    }

    #[test]
    fn marks_are_ninety_degrees_apart() {
        let marked: Vec<usize> = (0..SEGMENTS).filter(|&i| mark_paint(i).is_some()).collect();
        assert_eq!(marked.len(), 8);
        assert_eq!(mark_paint(0), Some(MARK_ONE));
        assert_eq!(mark_paint(SEGMENTS - 1), Some(MARK_ONE));
        assert_eq!(mark_paint(SEGMENTS / 4), Some(MARK));
    }
}
