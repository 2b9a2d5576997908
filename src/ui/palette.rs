//! Colours shared by the 3D traces, the trace panel and the plots, so that a phase has one
//! colour everywhere.

use crate::physics::motion::Phase;
use eframe::egui::Color32;

/// sRGB bytes of a phase (None: before the first cycle is classified).
pub fn phase_rgb(phase: Option<Phase>) -> [u8; 3] {
    match phase {
        Some(Phase::Prograde) => [40, 110, 215],
        Some(Phase::Walk) => [225, 150, 20],
        Some(Phase::Retrograde) => [205, 35, 95],
        None => [110, 120, 135],
    }
}

pub fn phase_color(phase: Option<Phase>) -> Color32 {
    let [r, g, b] = phase_rgb(phase);
    Color32::from_rgb(r, g, b)
}

/// The same colour in linear RGB, as the 3D shaders take it.
pub fn phase_linear(phase: Option<Phase>, alpha: f32) -> [f32; 4] {
    let [r, g, b] = phase_rgb(phase).map(|c| srgb_to_linear(c as f32 / 255.0));
    [r, g, b, alpha]
}

pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

/// Grey of the contact point's path.
pub const CONTACT_RGB: [u8; 3] = [70, 70, 78];
/// Body metals (linear RGB): steel for the first body, brass for the second.
pub const BODY_LINEAR: [[f32; 3]; 2] = [[0.60, 0.63, 0.68], [0.80, 0.55, 0.22]];
/// The two runs' lines in the plots.
pub const RUN_COLORS: [Color32; 2] =
    [Color32::from_rgb(40, 110, 215), Color32::from_rgb(200, 120, 20)];
/// Shading of the intervals where the model is invalid.
pub const LIFT_OFF_FILL: Color32 = Color32::from_rgba_premultiplied(120, 20, 20, 60);
pub const SLIP_FILL: Color32 = Color32::from_rgba_premultiplied(110, 70, 0, 45);
/// A recording (its path, its ring, its series): green, apart from the phases and the runs.
pub const DATA_RGB: [u8; 3] = [22, 150, 90];
pub const DATA_COLOR: Color32 = Color32::from_rgb(DATA_RGB[0], DATA_RGB[1], DATA_RGB[2]);
/// Where a diagnosis found the model departing from the recording: the recording's path
/// there, and the shading of that window on the timelines.
pub const MISMATCH_COLOR: Color32 = Color32::from_rgb(150, 40, 170);
pub const MISMATCH_FILL: Color32 = Color32::from_rgba_premultiplied(75, 20, 85, 40);
/// The diagnosis's two models against the data: the baseline and the improved model.
pub const BASELINE_COLOR: Color32 = Color32::from_rgb(200, 120, 20);
pub const IMPROVED_COLOR: Color32 = Color32::from_rgb(40, 110, 215);
/// The recording's ring in 3D (linear RGB): a green-tinted metal.
pub const DATA_BODY_LINEAR: [f32; 3] = [0.22, 0.55, 0.34];
