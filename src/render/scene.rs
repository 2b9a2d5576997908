//! What one frame of the 3D view shows, as plain data: the renderer's whole input.

use super::camera::CameraView;
use super::mark_discs::MarkDiscs;
use super::mesh::BodyGeometry;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec2};

/// One body to draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyDraw {
    pub geometry: BodyGeometry,
    pub world_from_ring: Mat4,
    /// Linear RGB of the metal.
    pub color: [f32; 3],
    /// The contact point, for the contact shading of the table.
    pub contact: Vec2,
    /// Drawn behind the other bodies where their surfaces (nearly) coincide: a recording's
    /// ring under the model's when the two agree, instead of the two flickering through
    /// each other.
    pub yields: bool,
    /// A film's marks: discs where the recording format puts them, instead of the painted
    /// marks.
    pub discs: Option<MarkDiscs>,
}

/// One straight piece of a trace on the table (an instance of the trace pipeline).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct TraceSegment {
    /// Start and end on the table.
    pub ab: [f32; 4],
    /// Linear RGB and opacity.
    pub color: [f32; 4],
    /// Half width (table units) and the least half width in pixels.
    pub extra: [f32; 2],
}

impl TraceSegment {
    pub fn new(
        a: Vec2,
        b: Vec2,
        color: [f32; 4],
        half_width: f32,
        min_half_px: f32,
    ) -> TraceSegment {
        TraceSegment { ab: [a.x, a.y, b.x, b.y], color, extra: [half_width, min_half_px] }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct SceneFrame {
    pub camera: CameraView,
    pub bodies: Vec<BodyDraw>,
    /// Drawn in order; later ones on top.
    pub traces: Vec<TraceSegment>,
    /// A length that sets the size of things (the outer radius of the first body).
    pub scale: f32,
    /// Spacing of the table's minor grid lines (major lines every five); 0: no grid.
    pub grid_spacing: f32,
    /// Where the table is sharpest; it fades into the background far from here.
    pub focus: Vec2,
}

/// The "nice" length (1, 2 or 5 times a power of ten) nearest below `x`, for grid lines and
/// scale bars.
pub fn nice_step(x: f64) -> f64 {
    if !(x > 0.0) || !x.is_finite() {
        return 1.0;
    }
    let p = 10f64.powf(x.log10().floor());
    let m = x / p;
    let k = if m >= 5.0 {
        5.0
    } else if m >= 2.0 {
        2.0
    } else {
        1.0
    };
    k * p
}

#[cfg(test)]
mod tests {
    use super::nice_step;

    #[test]
    fn nice_steps() {
        assert_eq!(nice_step(1.025), 1.0);
        assert_eq!(nice_step(20.66), 20.0);
        assert_eq!(nice_step(0.7), 0.5);
        assert_eq!(nice_step(0.0), 1.0);
    }
}
