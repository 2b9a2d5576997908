//! The 3D view: one or two scenes side by side in the central panel, the orbit camera (drag to
//! turn, scroll to zoom, double-click to reset), drawn through the renderer's paint callback.

use crate::render::callback::paint_callback;
use crate::render::{OrbitCamera, SceneFrame};
use eframe::egui::{self, Rect, Sense};

/// Lays out `n` views (1 or 2) in the space given, moves `camera` by the pointer, then draws
/// the frames `frame(i, camera)` builds, each at `scale` of its pixels' width and height.
/// Returns the views' rectangles (for overlays).
pub fn view3d_ui(
    ui: &mut egui::Ui,
    camera: &mut OrbitCamera,
    home: OrbitCamera,
    n: usize,
    scale: f32,
    mut frame: impl FnMut(usize, &OrbitCamera) -> SceneFrame,
) -> Vec<Rect> {
    let size = ui.available_size().max(egui::vec2(40.0, 40.0));
    let (rect, response) = ui.allocate_exact_size(size, Sense::click_and_drag());
    response.widget_info(|| {
        egui::WidgetInfo::labeled(
            egui::Role::Canvas,
            true,
            "3D view: drag to turn, scroll to zoom, double-click to reset",
        )
    });
    if response.dragged() {
        let d = response.drag_delta();
        camera.orbit(d.x, d.y);
    }
    if response.hovered() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        if scroll != 0.0 {
            camera.zoom(scroll / 40.0, 0.8 * home.distance / 9.0, 40.0 * home.distance);
        }
    }
    if response.double_clicked() {
        *camera = OrbitCamera { target: camera.target, ..home };
    }
    let n = n.clamp(1, 2);
    let gap = 4.0;
    let w = (rect.width() - gap * (n as f32 - 1.0)) / n as f32;
    let rects: Vec<Rect> = (0..n)
        .map(|i| {
            Rect::from_min_size(
                rect.min + egui::vec2(i as f32 * (w + gap), 0.0),
                egui::vec2(w, rect.height()),
            )
        })
        .collect();
    for (i, r) in rects.iter().enumerate() {
        ui.painter().add(paint_callback(i, *r, scale, frame(i, camera)));
    }
    rects
}
