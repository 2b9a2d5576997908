//! The app's side of a recording: opening it (menu, dialog, dropped files), adopting what its
//! jobs finished (the model started from the recording, the fitted model), the user's actions
//! (the recording's and the diagnosis's).

use super::diagnose_panel::DiagnoseAction;
use super::import_dialog::{ImportDialogAction, import_dialog_ui};
use super::recording_panel::RecordingAction;
use super::{RinglabApp, SideTab};
use crate::config::CaseFile;
use crate::session::SessionEvent;
use eframe::egui;

/// The sample recording (`tests/data/sample-ring.csv`), built in so that a page (no disk) and
/// a fresh install have a recording to try.
const SAMPLE_RECORDING: &[u8] = include_bytes!("../../tests/data/sample-ring.csv");

impl RinglabApp {
    /// Opens a recording (the file dialog's and drag-and-drop's way in): read and recovered
    /// off the UI thread, or at once in fixed mode. A film is tracked first.
    pub fn open_recording(&mut self, path: std::path::PathBuf) {
        self.recording.open(path);
        self.side_tab = SideTab::Recording;
        self.take_recording_events();
    }

    /// Opens a recording handed over with its bytes (a web page's file).
    pub fn open_recording_bytes(&mut self, name: &str, bytes: std::sync::Arc<[u8]>) {
        self.recording.open_bytes(name, bytes);
        self.side_tab = SideTab::Recording;
        self.take_recording_events();
    }

    /// Files dropped onto the page this frame: the first is read (a browser reads files
    /// asynchronously) and then opened.
    #[cfg(target_arch = "wasm32")]
    pub(super) fn take_dropped_files(&mut self, ctx: &egui::Context) {
        let first = ctx.input(|i| i.raw.dropped_files.first().cloned());
        if let Some(file) = first {
            let name = file.path().display().to_string();
            let read = async move { file.bytes_async().await };
            self.recording.open_when_read(crate::session::file_dialog::read_later(name, read));
            self.side_tab = SideTab::Recording;
        }
    }

    /// Files dropped onto the window this frame: the first is opened.
    #[cfg(not(target_arch = "wasm32"))]
    pub(super) fn take_dropped_files(&mut self, ctx: &egui::Context) {
        let dropped: Vec<std::path::PathBuf> =
            ctx.input(|i| i.raw.dropped_files.iter().map(|f| f.path().to_path_buf()).collect());
        if let Some(first) = dropped.into_iter().next() {
            self.open_recording(first);
        }
    }

    /// The import dialog's complaint about its fields, if any.
    pub fn import_problem_text(&self) -> Option<&str> {
        self.import_problem.as_deref()
    }

    /// The dialog for a tracker's file that needs options, while one waits.
    pub(super) fn import_dialog(&mut self, ctx: &egui::Context) {
        let Some(pending) = self.recording.pending_import().cloned() else { return };
        match import_dialog_ui(ctx, &pending, &mut self.settings.import, &mut self.import_problem) {
            Some(ImportDialogAction::Open(format, opts)) => {
                self.recording.retry_import(format, opts);
                self.take_recording_events();
            }
            Some(ImportDialogAction::Cancel) => self.recording.dismiss_import(),
            None => {}
        }
    }

    /// Adopts what the recording's jobs finished: the model started from the recording, or
    /// the fitted model.
    pub(super) fn take_recording_events(&mut self) {
        let events = self.recording.poll();
        self.adopt_events(events);
    }

    /// Waits for the recording's jobs and adopts their results (tests; pictures).
    pub fn finish_recording_jobs(&mut self) {
        let events = self.recording.wait();
        self.adopt_events(events);
    }

    fn adopt_events(&mut self, events: Vec<SessionEvent>) {
        for ev in events {
            match ev {
                SessionEvent::Loaded(Some(case)) | SessionEvent::Fitted(case) => {
                    self.adopt_case(case)
                }
                // The model stays; the clock starts again with the recording.
                SessionEvent::Loaded(None) => self.player.reset(),
            }
        }
    }

    /// Runs `case` alone (side by side off), from its start.
    fn adopt_case(&mut self, case: CaseFile) {
        self.settings.compare = false;
        self.settings.edit_second = false;
        self.settings.preset = case.name.clone();
        self.settings.case = case;
        self.error = None;
        self.rebuild_runs();
    }

    /// Does what the File menu or the Recording tab asked for (also for tests and pictures:
    /// in fixed mode the work is done when this returns).
    pub fn act_on_recording(&mut self, action: RecordingAction) {
        use RecordingAction as A;
        match action {
            A::None => {}
            A::Open => self.recording.open_dialog(),
            A::OpenSample => {
                let bytes: std::sync::Arc<[u8]> = SAMPLE_RECORDING.into();
                self.recording.open_bytes("sample-ring.csv", bytes);
            }
            A::OpenVideo => self.recording.open_video_dialog(),
            A::CancelOpen => self.recording.cancel_loading(),
            A::Close => self.recording.close(),
            A::Fit => self.recording.start_fit(),
            A::CancelFit => self.recording.cancel_fit(),
            A::UseFit => {
                if let Some(SessionEvent::Fitted(case)) = self.recording.readopt_fit() {
                    self.adopt_case(case);
                }
            }
        }
        self.take_recording_events();
    }

    /// Does what the Diagnose tab asked for (in fixed mode the work is done when this returns).
    pub fn act_on_diagnosis(&mut self, action: DiagnoseAction) {
        match action {
            DiagnoseAction::None => {}
            DiagnoseAction::Diagnose => self.recording.start_diagnose(),
            DiagnoseAction::Cancel => self.recording.cancel_diagnose(),
            DiagnoseAction::Adopt(which) => {
                if let Some(SessionEvent::Fitted(case)) = self.recording.adopt_diagnosed(which) {
                    self.adopt_case(case);
                }
            }
        }
        self.take_recording_events();
    }
}
