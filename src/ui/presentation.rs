//! Presentation mode (F11, View > Presentation): full screen, the UI scaled up (Ctrl +,
//! Ctrl -, Ctrl 0; the scale of each mode kept in the settings), a light high-contrast theme for
//! a projector with thick path lines, and the side panel folded away.

use eframe::egui::{self, Color32, Stroke};
use std::sync::Arc;

/// The UI's scale in presentation mode until changed (a 1920x1080 projector shows the window
/// as 1280x720 points).
pub const PRESENTATION_ZOOM: f32 = 1.5;
/// How much thicker the paths are drawn (3D view, trace panel, plots).
pub const THICK_LINES: f32 = 2.5;
/// Ctrl + and Ctrl - scale by this.
pub const ZOOM_STEP: f32 = 1.1;
pub const ZOOM_MIN: f32 = 0.5;
pub const ZOOM_MAX: f32 = 3.0;

/// A change of the UI's scale.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Zoom {
    In,
    Out,
    /// Back to the mode's own (1, or [`PRESENTATION_ZOOM`]).
    Reset,
}

impl Zoom {
    /// The scale after this change of `zoom`, in presentation mode or not.
    pub fn apply(self, zoom: f32, presenting: bool) -> f32 {
        let z = match self {
            Zoom::In => zoom * ZOOM_STEP,
            Zoom::Out => zoom / ZOOM_STEP,
            Zoom::Reset if presenting => PRESENTATION_ZOOM,
            Zoom::Reset => 1.0,
        };
        // Steps of 10% from 1 drift in the last digits; two decimals are what the eye sees.
        ((z * 100.0).round() / 100.0).clamp(ZOOM_MIN, ZOOM_MAX)
    }
}

/// The keys that change the scale this frame (egui's own zoom keys are off: its scale would not
/// be kept per mode).
pub fn zoom_keys(ctx: &egui::Context) -> Option<Zoom> {
    use egui::gui_zoom::kb_shortcuts::{ZOOM_IN, ZOOM_IN_SECONDARY, ZOOM_OUT, ZOOM_RESET};
    ctx.input_mut(|i| {
        if i.consume_shortcut(&ZOOM_IN) || i.consume_shortcut(&ZOOM_IN_SECONDARY) {
            Some(Zoom::In)
        } else if i.consume_shortcut(&ZOOM_OUT) {
            Some(Zoom::Out)
        } else if i.consume_shortcut(&ZOOM_RESET) {
            Some(Zoom::Reset)
        } else {
            None
        }
    })
}

/// The window's state of presentation mode.
#[derive(Default)]
pub struct Presentation {
    /// Asked for (menu, F11, tests).
    pub on: bool,
    /// The side panel unfolded for a moment.
    pub side_open: bool,
    /// The style before presentation mode, put back after it; Some while it is applied.
    normal_style: Option<Arc<egui::Style>>,
}

impl Presentation {
    /// Puts the theme and the full screen in line with `on` (once per change).
    pub fn apply(&mut self, ctx: &egui::Context, live: bool) {
        match (self.on, self.normal_style.is_some()) {
            (true, false) => {
                let normal = ctx.style_of(egui::Theme::Light);
                ctx.set_style_of(egui::Theme::Light, projector_style(&normal));
                self.normal_style = Some(normal);
                self.side_open = false;
                set_line_scale(ctx, THICK_LINES);
                if live {
                    ctx.send_viewport_cmd(egui::ViewportCommand::Fullscreen(true));
                }
            }
            (false, true) => {
                if let Some(normal) = self.normal_style.take() {
                    ctx.set_style_of(egui::Theme::Light, normal);
                }
                set_line_scale(ctx, 1.0);
                if live {
                    ctx.send_viewport_cmd(egui::ViewportCommand::Fullscreen(false));
                }
            }
            _ => {}
        }
    }
}

/// A light, high-contrast version of `base` for a projector: white ground, black text, strong
/// outlines and selections.
pub fn projector_style(base: &egui::Style) -> egui::Style {
    let mut s = base.clone();
    let ink = Color32::BLACK;
    let v = &mut s.visuals;
    v.override_text_color = Some(ink);
    v.panel_fill = Color32::WHITE;
    v.window_fill = Color32::WHITE;
    v.extreme_bg_color = Color32::WHITE;
    v.faint_bg_color = Color32::from_gray(235);
    v.window_stroke = Stroke::new(2.0, ink);
    v.selection.bg_fill = Color32::from_rgb(255, 210, 60);
    v.selection.stroke = Stroke::new(2.0, ink);
    v.hyperlink_color = Color32::from_rgb(0, 60, 200);
    let w = &mut v.widgets;
    w.noninteractive.fg_stroke = Stroke::new(1.5, ink);
    w.noninteractive.bg_stroke = Stroke::new(1.5, Color32::from_gray(90));
    for (state, fill) in
        [(&mut w.inactive, 225), (&mut w.hovered, 205), (&mut w.active, 185), (&mut w.open, 215)]
    {
        state.bg_fill = Color32::from_gray(fill);
        state.weak_bg_fill = Color32::from_gray(fill);
        state.bg_stroke = Stroke::new(1.5, ink);
        state.fg_stroke = Stroke::new(2.0, ink);
    }
    s
}

fn line_scale_id() -> egui::Id {
    egui::Id::unique("ringlab-line-scale")
}

fn set_line_scale(ctx: &egui::Context, k: f32) {
    ctx.data_mut(|d| d.insert_temp(line_scale_id(), k));
}

/// How much thicker than usual the paths are drawn now (1 outside presentation mode).
pub fn line_scale(ctx: &egui::Context) -> f32 {
    ctx.data(|d| d.get_temp::<f32>(line_scale_id())).unwrap_or(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zoom_steps_stay_in_range_and_reset_to_the_modes_own() {
        assert_eq!(Zoom::In.apply(1.0, false), 1.1);
        assert_eq!(Zoom::Out.apply(1.1, false), 1.0);
        assert_eq!(Zoom::Reset.apply(2.3, true), PRESENTATION_ZOOM);
        assert_eq!(Zoom::Reset.apply(2.3, false), 1.0);
        let mut z = 1.0;
        for _ in 0..40 {
            z = Zoom::In.apply(z, false);
        }
        assert_eq!(z, ZOOM_MAX);
        assert_eq!(Zoom::Out.apply(ZOOM_MIN, false), ZOOM_MIN);
    }
}
