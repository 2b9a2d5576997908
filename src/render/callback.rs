//! The 3D view inside egui: a paint callback that renders the scene offscreen while egui
//! prepares its frame (on egui's encoder) and copies it into the view's rectangle when egui
//! paints. The [`SceneRenderer`] lives in egui-wgpu's callback resources.

use super::kit::{ResourcePaint, resource_callback};
use super::renderer::SceneRenderer;
use super::scene::SceneFrame;
use eframe::egui_wgpu::{self, ScreenDescriptor};
use eframe::{egui, wgpu};

pub struct SceneCallback {
    /// Which of the renderer's views (0, or 1 for the second of two side by side).
    pub slot: usize,
    pub frame: SceneFrame,
    /// The view's rectangle in points.
    pub rect: egui::Rect,
    /// The share of the rectangle's pixels (width and height) the scene is drawn at; the copy
    /// into the rectangle scales it up (1: pixel for pixel).
    pub scale: f32,
}

/// Puts the scene renderer, and the painter of egui's shapes used on software rasterisers
/// ([`super::ui_painter`]), where the callbacks find them; call once with the window's (or
/// the test harness's) render state.
pub fn install(render_state: &egui_wgpu::RenderState) {
    let renderer = SceneRenderer::new(&render_state.device, Some(render_state.target_format));
    let painter =
        super::ui_painter::UiPainter::new(&render_state.device, render_state.target_format);
    let mut egui_renderer = render_state.renderer.write();
    egui_renderer.callback_resources.insert(renderer);
    egui_renderer.callback_resources.insert(painter);
}

/// The paint callback for view `slot` showing `frame` in `rect`, drawn at `scale` of its
/// pixels (clamped to 0.25..1).
pub fn paint_callback(
    slot: usize,
    rect: egui::Rect,
    scale: f32,
    frame: SceneFrame,
) -> egui::PaintCallback {
    let scale = if scale.is_finite() { scale.clamp(0.25, 1.0) } else { 1.0 };
    resource_callback(rect, SceneCallback { slot, frame, rect, scale })
}

impl ResourcePaint for SceneCallback {
    type Resource = SceneRenderer;

    fn prepare(
        &self,
        renderer: &mut SceneRenderer,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        screen: &ScreenDescriptor,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let ppp = screen.pixels_per_point * self.scale;
        let size = [
            (self.rect.width() * ppp).round().max(1.0) as u32,
            (self.rect.height() * ppp).round().max(1.0) as u32,
        ];
        renderer.render(device, queue, encoder, self.slot, &self.frame, size);
    }

    fn paint(
        &self,
        renderer: &SceneRenderer,
        _info: &egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
    ) {
        renderer.paint(self.slot, pass);
    }
}
