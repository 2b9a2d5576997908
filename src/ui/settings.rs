//! What persists between sessions (eframe storage).

use crate::config::{BUILTIN_PRESETS, CaseFile};
use serde::{Deserialize, Serialize};

/// The key of the settings in eframe's storage.
pub const SETTINGS_KEY: &str = "ringlab-settings";

/// What persists between sessions.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct Settings {
    /// The preset the case was taken from (its values set the sliders' ranges).
    pub preset: String,
    pub case: CaseFile,
    pub compare_preset: String,
    pub compare_case: CaseFile,
    /// Two runs side by side.
    pub compare: bool,
    /// Which of the two the sliders edit.
    pub edit_second: bool,
    pub speed: f64,
    pub follow: bool,
    pub show_contact: bool,
    pub show_why: bool,
    /// A change of drag or friction continues from the current state instead of restarting.
    pub continue_on_change: bool,
    /// How many pixels the 3D view draws.
    pub detail_3d: Detail3d,
    /// What the last tracker's file needed (frame rate, scale, body, marks).
    pub import: super::import_dialog::ImportForm,
    /// The UI's scale (Ctrl +, Ctrl -, Ctrl 0), and its scale in presentation mode.
    pub zoom: f32,
    pub presentation_zoom: f32,
}

/// The 3D view's resolution: every pixel of the view, or fewer (scaled up when shown) where
/// every pixel costs CPU time.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
pub enum Detail3d {
    /// Full on a GPU, fast on a software rasteriser (lavapipe).
    #[default]
    Auto,
    Full,
    Fast,
}

/// The share of the view's width and height that [`Detail3d::Fast`] draws (half the pixels).
pub const FAST_3D_SCALE: f32 = 0.7;

impl Detail3d {
    pub const ALL: [Detail3d; 3] = [Detail3d::Auto, Detail3d::Full, Detail3d::Fast];

    /// The share of the view's width and height drawn, on a software rasteriser or not.
    pub fn scale(self, software: bool) -> f32 {
        match self {
            Detail3d::Full => 1.0,
            Detail3d::Fast => FAST_3D_SCALE,
            Detail3d::Auto if software => FAST_3D_SCALE,
            Detail3d::Auto => 1.0,
        }
    }

    pub fn describe(self) -> &'static str {
        match self {
            Detail3d::Auto => "auto (fast without a GPU)",
            Detail3d::Full => "full",
            Detail3d::Fast => "fast (half the pixels)",
        }
    }
}

/// A compiled-in preset (they are part of the binary and checked by the tests).
pub(super) fn builtin(name: &str) -> CaseFile {
    let text =
        BUILTIN_PRESETS.iter().find(|p| p.0 == name).map(|p| p.1).unwrap_or(BUILTIN_PRESETS[0].1);
    CaseFile::parse(text, std::path::Path::new(name)).expect("compiled-in presets parse")
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            preset: "paper-ring".into(),
            case: builtin("paper-ring"),
            compare_preset: "paper-disk-drag".into(),
            compare_case: builtin("paper-disk-drag"),
            compare: false,
            edit_second: false,
            // A quarter of real time: at 1x the paper's ring wobbles 15 times a second.
            speed: 0.25,
            follow: true,
            show_contact: true,
            show_why: false,
            continue_on_change: false,
            detail_3d: Detail3d::Auto,
            import: Default::default(),
            zoom: 1.0,
            presentation_zoom: super::presentation::PRESENTATION_ZOOM,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_3d_detail_is_fast_only_where_asked_or_without_a_gpu() {
        assert_eq!(Detail3d::Auto.scale(false), 1.0);
        assert_eq!(Detail3d::Auto.scale(true), FAST_3D_SCALE);
        assert_eq!(Detail3d::Full.scale(true), 1.0);
        assert_eq!(Detail3d::Fast.scale(false), FAST_3D_SCALE);
        const {
            assert!(
                FAST_3D_SCALE * FAST_3D_SCALE < 0.55,
                "fast draws about half the pixels or fewer"
            )
        };
    }

    #[test]
    fn settings_saved_before_the_3d_detail_existed_still_load() {
        let mut v = serde_json::to_value(Settings::default()).expect("serialises");
        v.as_object_mut().expect("an object").remove("detail_3d");
        let s: Settings = serde_json::from_value(v).expect("loads");
        assert_eq!(s.detail_3d, Detail3d::Auto);
    }

    #[test]
    fn settings_saved_before_the_zoom_existed_load_unscaled() {
        let mut v = serde_json::to_value(Settings::default()).expect("serialises");
        let o = v.as_object_mut().expect("an object");
        o.remove("zoom");
        o.remove("presentation_zoom");
        let s: Settings = serde_json::from_value(v).expect("loads");
        assert_eq!(
            (s.zoom, s.presentation_zoom),
            (1.0, super::super::presentation::PRESENTATION_ZOOM)
        );
    }
}
