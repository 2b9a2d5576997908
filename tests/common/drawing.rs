//! Harnesses that draw through wgpu (lavapipe) with the scene renderer installed and egui set
//! up for the adapter, as the window has them: their screenshots are real renders.

use eframe::egui_wgpu;
use egui_kittest::{Harness, SnapshotOptions, wgpu::WgpuTestRenderer};

/// A snapshot may differ from its reference in one pixel in 2,000 (lavapipe's last bits).
pub fn snapshot_options(width: u32, height: u32) -> SnapshotOptions {
    let pixels = (width * height) as usize;
    SnapshotOptions::new().threshold(1.0).max_failed_pixels(pixels / 2000)
}

/// A harness builder of `width x height` in the app's light theme (it sets it itself; a panel
/// drawn alone needs it here).
pub fn drawing_builder<S>(width: u32, height: u32) -> egui_kittest::HarnessBuilder<S> {
    let rs = egui_kittest::wgpu::create_render_state(
        egui_kittest::wgpu::default_wgpu_setup(),
        egui_wgpu::RendererOptions::PREDICTABLE,
    );
    ringlab::render::callback::install(&rs);
    let adapter = rs.adapter.get_info();
    Harness::builder()
        .with_size([width as f32, height as f32])
        .with_theme(eframe::egui::Theme::Light)
        .with_context_setup(move |ctx| ringlab::ui::adapt_to_adapter(ctx, &adapter))
        .renderer(WgpuTestRenderer::from_render_state(rs))
}
