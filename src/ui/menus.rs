//! The menus of the top bar: File (the recording, the case, the exports) and View (presentation
//! mode, the UI's zoom).

use super::presentation::Zoom;
use super::recording_panel::RecordingAction;
use crate::export::session::{ExportSession, FileTask, PictureKind};
use crate::session::RecordingSession;
use eframe::egui;

/// What the user asked for in a menu.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MenuAction {
    None,
    Recording(RecordingAction),
    /// A file to choose (the dialog), then what is done with it.
    File(FileTask),
    /// The Export video window.
    VideoDialog,
    Presentation(bool),
    Zoom(Zoom),
}

fn item(
    ui: &mut egui::Ui,
    enabled: bool,
    label: &str,
    keys: &str,
    hover: &str,
    action: MenuAction,
    out: &mut MenuAction,
) {
    // A shortcut is part of the button's accessible label: none where there is no key.
    let button = if keys.is_empty() {
        egui::Button::new(label)
    } else {
        egui::Button::new(label).shortcut_text(keys)
    };
    let r = ui.add_enabled(enabled, button);
    if r.on_hover_text(hover).clicked() {
        *out = action;
        ui.close();
    }
}

/// A web page has no ffmpeg to decode or encode video and cannot read the 3D view back from
/// the GPU at once: what needs either is said on the item instead of offered.
pub const DESKTOP_ONLY: &str = "in the desktop app only (ringlab for Windows, Linux, or built \
     from source): a web page has no ffmpeg to decode or encode video, nor a way to read the 3D \
     view back from the GPU at once; Save picture of the window works here";

/// The File menu.
pub fn file_menu_ui(
    ui: &mut egui::Ui,
    recording: &RecordingSession,
    exports: &ExportSession,
) -> MenuAction {
    let mut a = MenuAction::None;
    ui.menu_button("File", |ui| {
        let idle = !exports.dialog_open();
        let web = cfg!(target_arch = "wasm32");
        let desktop = |hover: &'static str| if web { DESKTOP_ONLY } else { hover };
        let rec = |r| MenuAction::Recording(r);
        item(ui, !recording.dialog_open(), "Open recording…", "", "a recording of a ring's marks (format v1), or a tracker's file (DeepLabCut, Tracker, TrackMate, a plain CSV); or drop the file onto the window", rec(RecordingAction::Open), &mut a);
        item(ui, !web && !recording.dialog_open(), "Open video…", "", desktop("a film of a ring with four marks (MP4, MOV, AVI, MKV: ffmpeg decodes it): its marks are tracked into a recording, and the film is shown with them drawn over it; the body is the import options' (asked for the first time)"), rec(RecordingAction::OpenVideo), &mut a);
        item(ui, recording.loaded().is_some(), "Close recording", "", "forget the recording", rec(RecordingAction::Close), &mut a);
        ui.separator();
        let file = MenuAction::File;
        item(ui, idle, "Open case…", "", "a case file in the presets' TOML shape (ringlab --config FILE opens one at the start)", file(FileTask::OpenCase), &mut a);
        item(ui, idle, "Save case…", "", "the case as the sliders have it, as TOML in the presets' shape", file(FileTask::SaveCase), &mut a);
        item(ui, idle, "Export run as CSV…", "", "every output state of the run from its start: the columns of ringlab simulate --out", file(FileTask::ExportCsv), &mut a);
        ui.separator();
        let picture = |k| MenuAction::File(FileTask::Picture(k));
        item(ui, idle, "Save picture of the window…", "F12", "a PNG of the window as it is (F12 saves one at once, without asking where)", picture(PictureKind::Window), &mut a);
        item(ui, idle && !web, "Save picture of the 3D view…", "Shift+F12", desktop("a PNG of the 3D view alone, every pixel drawn (Shift+F12: at once)"), picture(PictureKind::View3d), &mut a);
        item(ui, idle && !web, "Export video…", "", desktop("the run as a GIF or an MP4: the 3D view, the trace or the window"), MenuAction::VideoDialog, &mut a);
        let film = recording.loaded().is_some_and(|l| l.film.is_some());
        item(ui, idle && film && !web, "Export film with overlay…", "", desktop("the film the recording was tracked from, as an MP4, with the tracked marks and, once fitted or diagnosed, the model's marks and path of A drawn over it"), file(FileTask::FilmOverlay), &mut a);
    });
    a
}

/// The View menu (presentation mode, zoom); `presenting`: in presentation mode now.
pub fn view_menu_ui(ui: &mut egui::Ui, presenting: bool) -> MenuAction {
    let mut a = MenuAction::None;
    ui.menu_button("View", |ui| a = view_items_ui(ui, presenting).unwrap_or(MenuAction::None));
    a
}

fn view_items_ui(ui: &mut egui::Ui, presenting: bool) -> Option<MenuAction> {
    let mut a = MenuAction::None;
    let label = if presenting { "Leave presentation" } else { "Presentation" };
    item(
        ui,
        true,
        label,
        "F11",
        "full screen, larger text, a high-contrast theme and thick lines; the side panel folds away",
        MenuAction::Presentation(!presenting),
        &mut a,
    );
    item(
        ui,
        true,
        "Zoom in",
        "Ctrl +",
        "a larger UI (kept for next time)",
        MenuAction::Zoom(Zoom::In),
        &mut a,
    );
    item(ui, true, "Zoom out", "Ctrl -", "a smaller UI", MenuAction::Zoom(Zoom::Out), &mut a);
    item(
        ui,
        true,
        "Reset zoom",
        "Ctrl 0",
        "the mode's own scale",
        MenuAction::Zoom(Zoom::Reset),
        &mut a,
    );
    (a != MenuAction::None).then_some(a)
}
