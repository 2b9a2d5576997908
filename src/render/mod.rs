//! The renderer: wgpu pipelines of our own (WGSL in `shaders/`) for the ring or disk on its
//! table, with shadows and the traces, drawn offscreen and then shown inside egui (the window)
//! or read back (headless PNGs, tests). The UI sees only [`SceneFrame`] (what to draw),
//! [`SceneRenderer`] and the helpers here.

pub mod adapter;
pub mod callback;
pub mod camera;
pub mod headless;
mod kit;
pub mod lean_paint;
pub mod mark_discs;
pub mod mesh;
mod pipelines;
pub mod pose;
mod renderer;
pub mod scene;
pub mod ui_painter;
pub mod ui_stats;

pub use camera::{CameraView, OrbitCamera};
pub use headless::{Gpu, RenderError, UiRenderer};
pub use mark_discs::MarkDiscs;
pub use mesh::BodyGeometry;
pub use pipelines::COLOR_FORMAT;
pub use pose::{BodyPose, world_from_ring};
pub use renderer::{BACKGROUND, MAX_VIEWS, SceneRenderer};
pub use scene::{BodyDraw, SceneFrame, TraceSegment, nice_step};
