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
}

/// A compiled-in preset (they are part of the binary and checked by the tests).
pub(super) fn builtin(name: &str) -> CaseFile {
    let text = BUILTIN_PRESETS.iter().find(|p| p.0 == name).map(|p| p.1).unwrap_or(BUILTIN_PRESETS[0].1);
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
        }
    }
}

