//! The window's exports without egui: what a menu or a key asked for, the file dialog that
//! picks its path, then the work on a thread of its own (a case or CSV written, a picture, a
//! video with its progress and Cancel), and what came of each, as messages for the window.
//!
//! In the app's fixed mode (tests, headless pictures) no dialog is ever opened: the request
//! waits until [`ExportSession::take_request`] is answered with a path (what the dialog would
//! have given), and the work runs at once.

use super::video::{VideoFormat, VideoReport, VideoSpec};
use super::{ExportError, View};
use crate::session::file_dialog::{DialogOutcome, DialogRequest, run_dialog};
use crate::session::{Job, JobContext, Progress};
use std::path::PathBuf;

/// Which picture.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PictureKind {
    /// The whole window as it is on the screen.
    Window,
    /// The 3D view alone, at its size on the screen, every pixel drawn.
    View3d,
}

/// A video asked for in the window (its file comes from the dialog).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VideoRequest {
    pub view: View,
    pub spec: VideoSpec,
    pub size: [u32; 2],
    pub format: VideoFormat,
}

/// What a path is wanted for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FileTask {
    OpenCase,
    SaveCase,
    ExportCsv,
    Picture(PictureKind),
    Video(VideoRequest),
    /// The film the recording was tracked from, with the marks and the model drawn over it.
    FilmOverlay,
}

impl FileTask {
    /// The dialog that asks for its path; `name` the file name proposed (saving), `folder`
    /// where it starts.
    pub fn dialog(&self, name: String, folder: Option<PathBuf>) -> DialogRequest {
        let (title, filter, save) = match self {
            FileTask::OpenCase => {
                ("Open a case (TOML, the presets' shape)", ("cases", "toml"), false)
            }
            FileTask::SaveCase => ("Save the case (TOML)", ("cases", "toml"), true),
            FileTask::ExportCsv => {
                ("Export the run as CSV (the columns of simulate --out)", ("CSV", "csv"), true)
            }
            FileTask::Picture(_) => ("Save a picture (PNG)", ("PNG pictures", "png"), true),
            FileTask::FilmOverlay => (
                "Export the film with the marks and the model drawn over it (MP4)",
                ("MP4", "mp4"),
                true,
            ),
            FileTask::Video(v) => (
                "Export a video",
                if v.format == VideoFormat::Gif { ("GIF", "gif") } else { ("MP4", "mp4") },
                true,
            ),
        };
        let instead = match self {
            FileTask::OpenCase => "start ringlab with --config FILE.toml instead",
            FileTask::Picture(_) => {
                "F12 saves a picture of the window without asking (Shift+F12: the 3D view)"
            }
            FileTask::FilmOverlay => {
                "ringlab track FILM --out REC.csv --overlay OUT.mp4 --fit writes the same film"
            }
            _ => "ringlab's command line writes the same files (see ringlab --help)",
        };
        DialogRequest {
            title: title.into(),
            filter: (filter.0.into(), vec![filter.1.into()]),
            save_as: save.then_some(name),
            folder,
            instead: instead.into(),
        }
    }
}

/// What came of an export: a message for the window.
pub type Outcome = Result<String, String>;

pub struct ExportSession {
    background: bool,
    /// Asked for, its dialog not yet open (fixed mode: waiting for a path).
    request: Option<FileTask>,
    dialog: Option<(FileTask, Job<DialogOutcome>)>,
    writing: Vec<Job<Outcome>>,
    video: Option<Job<Outcome>>,
    /// Where the last file was put (the next dialog starts there).
    pub last_folder: Option<PathBuf>,
}

impl ExportSession {
    pub fn new(background: bool) -> ExportSession {
        ExportSession {
            background,
            request: None,
            dialog: None,
            writing: Vec::new(),
            video: None,
            last_folder: None,
        }
    }

    /// Asks for a path for `task` (one dialog at a time: a second request waits for none).
    pub fn request(&mut self, task: FileTask) {
        if self.dialog.is_none() {
            self.request = Some(task);
        }
    }

    /// What waits for a path, if anything.
    pub fn requested(&self) -> Option<&FileTask> {
        self.request.as_ref()
    }

    /// The request, taken (the app opens its dialog, or a test answers it).
    pub fn take_request(&mut self) -> Option<FileTask> {
        self.request.take()
    }

    /// Opens the dialog for `task` (live window only: never in fixed mode).
    pub fn open_dialog(&mut self, task: FileTask, dialog: DialogRequest) {
        if self.background && self.dialog.is_none() {
            self.dialog = Some((task, run_dialog(true, dialog)));
        }
    }

    pub fn dialog_open(&self) -> bool {
        self.dialog.is_some()
    }

    /// The dialog's answer, once there is one.
    pub fn poll_dialog(&mut self) -> Option<(FileTask, DialogOutcome)> {
        let (_, job) = self.dialog.as_mut()?;
        let outcome = job.poll()?;
        let (task, _) = self.dialog.take()?;
        Some((task, outcome.unwrap_or_else(|e| DialogOutcome::Unavailable(e.to_string()))))
    }

    /// Writes a file on a thread (at once in fixed mode).
    pub fn start_writing(&mut self, name: &str, work: impl FnOnce() -> Outcome + Send + 'static) {
        self.writing.push(Job::start(name, self.background, move |_| work()));
    }

    /// Starts a video (none while one runs); `work` reports its progress and watches for Cancel.
    pub fn start_video(
        &mut self,
        work: impl FnOnce(&JobContext) -> Outcome + Send + 'static,
    ) -> bool {
        if self.video.is_some() {
            return false;
        }
        self.video = Some(Job::start("video", self.background, work));
        true
    }

    pub fn video_progress(&self) -> Option<Progress> {
        self.video.as_ref().map(|j| j.progress())
    }

    pub fn cancel_video(&self) {
        if let Some(j) = &self.video {
            j.cancel();
        }
    }

    pub fn video_cancelling(&self) -> bool {
        self.video.as_ref().is_some_and(|j| j.is_cancelling())
    }

    /// Whether anything runs that the window should redraw for.
    pub fn busy(&self) -> bool {
        self.dialog.is_some() || !self.writing.is_empty() || self.video.is_some()
    }

    /// What finished since the last call.
    pub fn poll(&mut self) -> Vec<Outcome> {
        let mut done = Vec::new();
        self.writing.retain_mut(|j| match j.poll() {
            Some(r) => {
                done.push(r.unwrap_or_else(|e| Err(e.to_string())));
                false
            }
            None => true,
        });
        if let Some(j) = &mut self.video
            && let Some(r) = j.poll()
        {
            done.push(r.unwrap_or_else(|e| Err(e.to_string())));
            self.video = None;
        }
        done
    }

    /// Waits for every write and the video (tests; a caller that must have the file now).
    pub fn wait(&mut self) -> Vec<Outcome> {
        for j in &mut self.writing {
            j.finish();
        }
        if let Some(j) = &mut self.video {
            j.finish();
        }
        self.poll()
    }
}

/// A video's outcome as a message.
pub fn describe_video(r: Result<VideoReport, ExportError>) -> Outcome {
    match r {
        Ok(v) => Ok(format!(
            "wrote {} ({} frames of {}x{}, {:.1} MB, in {:.1} s)",
            v.path.display(),
            v.frames,
            v.size[0],
            v.size[1],
            v.bytes as f64 / 1e6,
            v.seconds
        )),
        Err(ExportError::Cancelled) => Ok("the video was cancelled (no file written)".into()),
        Err(e) => Err(e.to_string()),
    }
}
