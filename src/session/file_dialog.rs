//! The desktop's file dialogs (rfd: File > Open recording, Open video, Open case, Save case,
//! the exports), each on a thread of its own so that the window keeps drawing while it is open.
//!
//! In a web page (wasm32) there are no paths: an open dialog is the browser's file picker and
//! gives the file's name and bytes ([`DialogOutcome::Opened`]); a save gives the name alone,
//! and what is written with it becomes a download (`crate::session::download`).
//!
//! On Linux rfd asks the XDG desktop portal over D-Bus (libdbus, loaded at run time) and falls
//! back to `zenity`; where neither is there it returns nothing, as it does when the user
//! cancels. To tell the two apart, rfd's own log lines are caught: a failed fallback is a
//! dialog that could not be shown, and the user is told to drop the file on the window.

use super::job::Job;
use std::path::PathBuf;
#[cfg(not(target_arch = "wasm32"))]
use std::sync::Mutex;

/// What came of the dialog.
#[derive(Clone, Debug, PartialEq)]
pub enum DialogOutcome {
    Picked(PathBuf),
    /// A file read by a web page's picker: its name and bytes (no path on any disk).
    Opened {
        name: String,
        bytes: std::sync::Arc<[u8]>,
    },
    Cancelled,
    /// No dialog could be shown; why.
    Unavailable(String),
}

/// rfd's warnings and errors since the last dialog opened.
#[cfg(not(target_arch = "wasm32"))]
static RFD_LOG: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// Catches the log lines of rfd (and nothing else: no other crate's lines are wanted).
#[cfg(not(target_arch = "wasm32"))]
struct RfdLog;

#[cfg(not(target_arch = "wasm32"))]
impl log::Log for RfdLog {
    fn enabled(&self, m: &log::Metadata) -> bool {
        m.target().starts_with("rfd") && m.level() <= log::Level::Warn
    }

    fn log(&self, r: &log::Record) {
        if self.enabled(r.metadata())
            && let Ok(mut v) = RFD_LOG.lock()
            && v.len() < 16
        {
            v.push(r.args().to_string());
        }
    }

    fn flush(&self) {}
}

#[cfg(not(target_arch = "wasm32"))]
static LOGGER: RfdLog = RfdLog;

/// Installs the catcher once; false where another logger was there first.
#[cfg(not(target_arch = "wasm32"))]
fn catch_rfd_log() -> bool {
    static INSTALLED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *INSTALLED.get_or_init(|| {
        let ok = log::set_logger(&LOGGER).is_ok();
        if ok {
            log::set_max_level(log::LevelFilter::Warn);
        }
        ok
    })
}

#[cfg(not(target_arch = "wasm32"))]
/// Why no dialog could be shown, from what rfd logged (None: it was shown, or cancelled);
/// `instead` says what the user can do without one.
fn failure(lines: &[String], instead: &str) -> Option<String> {
    // rfd logs "Failed to pick file with zenity: ..." (or "save file") when its last fallback failed.
    lines.iter().any(|l| l.contains("zenity") && l.contains("Failed")).then(|| {
        format!(
            "no file dialog is available here (it needs an XDG desktop portal or zenity): {instead}"
        )
    })
}

/// One dialog: to open a file, or to save one under a name.
#[derive(Clone, Debug, PartialEq)]
pub struct DialogRequest {
    pub title: String,
    /// Name and extensions of the files shown first ("all files" is always offered too).
    pub filter: (String, Vec<String>),
    /// A save dialog with this file name proposed (None: an open dialog).
    pub save_as: Option<String>,
    /// The folder it starts in.
    pub folder: Option<PathBuf>,
    /// What to do where no dialog can be shown (said to the user).
    pub instead: String,
}

/// Opens the dialog (a thread of its own when `background`).
#[cfg(not(target_arch = "wasm32"))]
pub fn run_dialog(background: bool, request: DialogRequest) -> Job<DialogOutcome> {
    Job::start("file-dialog", background, move |_| {
        // Where another logger came first a failure reads as a cancel (nothing else breaks).
        catch_rfd_log();
        if let Ok(mut v) = RFD_LOG.lock() {
            v.clear();
        }
        let (name, extensions) = &request.filter;
        let mut dialog = rfd::FileDialog::new()
            .set_title(&request.title)
            .add_filter(name, extensions)
            .add_filter("all files", &["*"]);
        if let Some(folder) = &request.folder {
            dialog = dialog.set_directory(folder);
        }
        let picked = match &request.save_as {
            Some(file_name) => dialog.set_file_name(file_name).save_file(),
            None => dialog.pick_file(),
        };
        match picked {
            Some(p) => DialogOutcome::Picked(p),
            None => {
                let lines = RFD_LOG.lock().map(|v| v.clone()).unwrap_or_default();
                failure(&lines, &request.instead)
                    .map_or(DialogOutcome::Cancelled, DialogOutcome::Unavailable)
            }
        }
    })
}

/// Opens the browser's file picker (its answer comes with the file's bytes), or for a save,
/// gives the proposed name at once: the page's files are downloads.
#[cfg(target_arch = "wasm32")]
pub fn run_dialog(_background: bool, request: DialogRequest) -> Job<DialogOutcome> {
    if let Some(name) = request.save_as {
        return Job::done(DialogOutcome::Picked(PathBuf::from(name)));
    }
    let (job, tx) = Job::waiting();
    let (name, extensions) = &request.filter;
    let dialog = rfd::AsyncFileDialog::new()
        .set_title(&request.title)
        .add_filter(name, extensions)
        .add_filter("all files", &["*"]);
    wasm_bindgen_futures::spawn_local(async move {
        let outcome = match dialog.pick_file().await {
            Some(file) => {
                let bytes: std::sync::Arc<[u8]> = file.read().await.into();
                DialogOutcome::Opened { name: file.file_name(), bytes }
            }
            None => DialogOutcome::Cancelled,
        };
        // The job may have been dropped meanwhile: nobody waits for the file then.
        let _ = tx.send(outcome);
    });
    job
}

/// A file the browser reads asynchronously (one dropped on the page), as a dialog's answer.
#[cfg(target_arch = "wasm32")]
pub fn read_later(
    name: String,
    read: impl std::future::Future<Output = Result<Vec<u8>, String>> + 'static,
) -> Job<DialogOutcome> {
    let (job, tx) = Job::waiting();
    wasm_bindgen_futures::spawn_local(async move {
        let outcome = match read.await {
            Ok(bytes) => DialogOutcome::Opened { name, bytes: bytes.into() },
            Err(e) => {
                DialogOutcome::Unavailable(format!("{name}: the browser could not read it: {e}"))
            }
        };
        let _ = tx.send(outcome);
    });
    job
}

/// File > Open recording's dialog (a film is taken too: it is tracked).
pub fn pick_recording(background: bool) -> Job<DialogOutcome> {
    let mut extensions: Vec<String> = ["csv", "trk", "txt", "tsv"].map(String::from).to_vec();
    extensions.extend(VIDEO_FILTER.map(String::from));
    run_dialog(
        background,
        DialogRequest {
            title: "Open a recording (format v1), a tracker's file or a film".into(),
            filter: ("recordings, trackers' files and films".into(), extensions),
            save_as: None,
            folder: None,
            instead: "drop the .csv file onto the window instead".into(),
        },
    )
}

/// The videos File > Open video shows first.
const VIDEO_FILTER: [&str; 4] = ["mp4", "mov", "avi", "mkv"];

/// File > Open video's dialog.
pub fn pick_video(background: bool) -> Job<DialogOutcome> {
    run_dialog(
        background,
        DialogRequest {
            title: "Open a film of a ring with four marks (its marks are tracked)".into(),
            filter: ("videos".into(), VIDEO_FILTER.map(String::from).to_vec()),
            save_as: None,
            folder: None,
            instead: "drop the video file onto the window instead".into(),
        },
    )
}

#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests {
    use super::failure;

    #[test]
    fn a_failed_zenity_fallback_means_no_dialog() {
        let lines = vec![
            "Using zenity fallback".to_string(),
            "Failed to pick file with zenity: No such file or directory".to_string(),
        ];
        assert!(
            failure(&lines, "drop the .csv file").is_some_and(|m| m.contains("drop the .csv file"))
        );
        assert_eq!(failure(&["Using zenity fallback".to_string()], "x"), None);
        assert_eq!(failure(&[], "x"), None);
    }
}
