//! egui adjusted to the adapter it is drawn on (a GPU, or a software rasteriser).

use super::lean_paint;
use eframe::egui;

/// Adjusts egui to the adapter: on a software rasteriser (lavapipe) the feathered edges that
/// anti-alias egui's lines and shapes roughly double its triangles, and every triangle is
/// drawn on the CPU, so they are left out there, and so are rounded corners (fans of slivers).
/// Remembers which it was for the 3D view's detail setting ([`on_software_adapter`]),
/// and there hands egui's shapes to our own lean painter ([`lean_paint`]), which
/// [`super::callback::install`] must have put into the renderer.
pub fn adapt_to_adapter(ctx: &egui::Context, adapter: &eframe::wgpu::AdapterInfo) {
    let software = adapter.device_type == eframe::wgpu::DeviceType::Cpu;
    ctx.data_mut(|d| d.insert_temp(software_adapter_id(), software));
    // The lean painter is for lavapipe's cost per pixel; a browser's software WebGL has no
    // base vertex for its draws (WebGL2 lacks it), and egui-wgpu's painter is drawn there.
    lean_paint::set_enabled(ctx, software && !cfg!(target_arch = "wasm32"));
    if software {
        ctx.tessellation_options_mut(|t| t.feathering = false);
        ctx.all_styles_mut(|s| {
            let v = &mut s.visuals;
            for w in [
                &mut v.widgets.noninteractive,
                &mut v.widgets.inactive,
                &mut v.widgets.hovered,
                &mut v.widgets.active,
                &mut v.widgets.open,
            ] {
                w.corner_radius = egui::CornerRadius::ZERO;
            }
            v.window_corner_radius = egui::CornerRadius::ZERO;
            v.menu_corner_radius = egui::CornerRadius::ZERO;
        });
    }
}

fn software_adapter_id() -> egui::Id {
    egui::Id::unique("ringlab-software-adapter")
}

/// Whether [`adapt_to_adapter`] found a software rasteriser.
pub fn on_software_adapter(ctx: &egui::Context) -> bool {
    ctx.data(|d| d.get_temp::<bool>(software_adapter_id())).unwrap_or(false)
}
