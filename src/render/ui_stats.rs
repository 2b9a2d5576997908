//! How much drawing one egui frame asks of the rasteriser, for the benchmarks.
//!
//! A software rasteriser (lavapipe) runs the fragment shader on whole 4x4 blocks of pixels, so
//! a long sliver triangle or a one-pixel line costs far more than the pixels it covers; the
//! count of 4x4 blocks each triangle touches is the measure that tracks its time.

use eframe::egui::{self, Pos2, epaint::ClippedPrimitive};
use serde::Serialize;

#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct UiStats {
    pub meshes: usize,
    pub triangles: usize,
    pub paint_callbacks: usize,
    /// Pixels covered by egui's triangles (overlaps counted each time).
    pub pixels: f64,
    /// 4x4 blocks of pixels touched by egui's triangles (within their clip rectangles).
    pub blocks_4x4: usize,
    /// Of those, the blocks of text (glyph quads).
    pub text_blocks_4x4: usize,
}

impl UiStats {
    pub fn of(primitives: &[ClippedPrimitive]) -> UiStats {
        let mut s = UiStats::default();
        for p in primitives {
            let mesh = match &p.primitive {
                egui::epaint::Primitive::Mesh(m) => m,
                egui::epaint::Primitive::Callback(_) => {
                    s.paint_callbacks += 1;
                    continue;
                }
            };
            s.meshes += 1;
            s.triangles += mesh.indices.len() / 3;
            for t in mesh.indices.chunks_exact(3) {
                let v = [t[0], t[1], t[2]].map(|i| &mesh.vertices[i as usize]);
                let [a, b, c] = v.map(|v| v.pos);
                s.pixels += 0.5 * f64::from(cross(a, b, c).abs());
                let blocks = blocks_touched([a, b, c], p.clip_rect);
                s.blocks_4x4 += blocks;
                // Glyphs sample the font atlas; solid shapes all use its one white texel.
                if v[0].uv != v[1].uv || v[0].uv != v[2].uv {
                    s.text_blocks_4x4 += blocks;
                }
            }
        }
        s
    }

    /// Both counts together.
    pub fn plus(self, o: &UiStats) -> UiStats {
        UiStats {
            meshes: self.meshes + o.meshes,
            triangles: self.triangles + o.triangles,
            paint_callbacks: self.paint_callbacks + o.paint_callbacks,
            pixels: self.pixels + o.pixels,
            blocks_4x4: self.blocks_4x4 + o.blocks_4x4,
            text_blocks_4x4: self.text_blocks_4x4 + o.text_blocks_4x4,
        }
    }
}

/// Twice the signed area of the triangle (a, b, c).
fn cross(a: Pos2, b: Pos2, c: Pos2) -> f32 {
    (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)
}

/// The 4x4 blocks of pixels (aligned to the screen) with at least one pixel centre inside the
/// triangle and the clip rectangle.
fn blocks_touched(tri: [Pos2; 3], clip: egui::Rect) -> usize {
    let [a, b, c] = tri;
    let area = cross(a, b, c);
    if area.abs() < 1e-6 {
        return 0;
    }
    let lo = a.min(b).min(c).max(clip.min);
    let hi = a.max(b).max(c).min(clip.max);
    let inside = |p: Pos2| {
        let w = [cross(b, c, p) / area, cross(c, a, p) / area, cross(a, b, p) / area];
        w.iter().all(|w| *w >= 0.0) && clip.contains(p)
    };
    let mut n = 0;
    let mut by = (lo.y / 4.0).floor() * 4.0;
    while by < hi.y {
        let mut bx = (lo.x / 4.0).floor() * 4.0;
        while bx < hi.x {
            let hit = (0..16)
                .any(|k| inside(egui::pos2(bx + (k % 4) as f32 + 0.5, by + (k / 4) as f32 + 0.5)));
            n += usize::from(hit);
            bx += 4.0;
        }
        by += 4.0;
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sliver_touches_many_more_blocks_than_a_square_of_its_area() {
        let clip = egui::Rect::from_min_size(Pos2::ZERO, egui::vec2(1000.0, 1000.0));
        // 64 x 64 pixel square's half: 2048 pixels, 16 x 16 blocks' half plus the diagonal.
        let square = blocks_touched(
            [egui::pos2(0.0, 0.0), egui::pos2(64.0, 0.0), egui::pos2(0.0, 64.0)],
            clip,
        );
        assert!((136..=160).contains(&square), "{square}");
        // A sliver 640 pixels long and 3 high at one end: 960 pixels over some 130 blocks.
        let sliver = blocks_touched(
            [egui::pos2(0.0, 0.0), egui::pos2(640.0, 0.0), egui::pos2(0.0, 3.0)],
            clip,
        );
        assert!(sliver >= 120, "{sliver}");
        // Clipped away: nothing.
        let outside = blocks_touched(
            [egui::pos2(2000.0, 0.0), egui::pos2(2064.0, 0.0), egui::pos2(2000.0, 64.0)],
            clip,
        );
        assert_eq!(outside, 0);
    }
}
