//! Frames of a run at any time: what a frame shows ([`View`]), where the camera looks
//! ([`Aim`]), what draws them ([`Frames`]) and scene frames side by side. The drawing itself
//! is the window's (`ui::frames::FrameSource`, one renderer for the screen, pictures and
//! videos): export sees it only through [`Frames`], so it knows nothing of the window.

use super::picture::side_by_side;
use crate::render::{Gpu, RenderError, SceneFrame, SceneRenderer};
use image::RgbaImage;

/// What a frame shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// The 3D scene alone (two runs: side by side).
    ThreeD,
    /// The trace panel: the path of A from above.
    Top,
    /// The whole window.
    App,
}

impl View {
    pub const ALL: [View; 3] = [View::ThreeD, View::Top, View::App];

    pub fn name(self) -> &'static str {
        match self {
            View::ThreeD => "3D scene",
            View::Top => "trace panel",
            View::App => "app",
        }
    }
}

/// Where the 3D camera looks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Aim {
    /// At the ring (the window's "camera follows the ring").
    Follow,
    /// At the camera's own target.
    Fixed,
    /// At the middle of the path of A from the start to the frame's time, or to this time
    /// (seconds) when given: a video's camera then stands still.
    PathMiddle(Option<f64>),
}

/// What draws a video's frames (the window's `ui::frames::FrameSource`).
pub trait Frames {
    /// The time unit (seconds) of the frame times: the first run's.
    fn time_unit_s(&self) -> f64;
    /// The picture at time `t` (in that unit) at `size` pixels.
    fn frame(&mut self, gpu: &Gpu, t: f64, size: [u32; 2]) -> Result<RgbaImage, RenderError>;
}

/// Gap between two views side by side (pixels).
const GAP: u32 = 4;

/// Scene frames side by side in a picture of `size` (each its share of the width).
pub fn render_views(
    gpu: &Gpu,
    renderer: &mut SceneRenderer,
    frames: &[SceneFrame],
    size: [u32; 2],
) -> Result<RgbaImage, RenderError> {
    let n = frames.len().max(1) as u32;
    let gap = if n > 1 { GAP } else { 0 };
    let w = size[0].saturating_sub(gap * (n - 1)) / n;
    let images = frames
        .iter()
        .map(|f| gpu.render_scene(renderer, f, [w.max(1), size[1]]))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(side_by_side(&images, size, gap))
}
