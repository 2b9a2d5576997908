//! The window's File actions beyond the recording: a case opened or saved, the run as CSV,
//! pictures, videos; and the keys for pictures, presentation mode and the UI's scale.
//!
//! A menu or a key asks for a path ([`RinglabApp::request_file`]); the live window then opens
//! the desktop's dialog, and its answer goes to [`RinglabApp::file_chosen`], which is also how
//! tests answer (kittest cannot drive a native dialog; in fixed mode none is opened).

use super::frames::FrameSource;
use super::menus::MenuAction;
use super::presentation::{Zoom, zoom_keys};
use super::recording_panel::RecordingAction;
use super::{Detail3d, Mode, RinglabApp, SideTab};
use crate::config::{CaseFile, load_case_file};
use crate::export::csv::write_run_csv;
use crate::export::picture::{from_color_image, save_png};
use crate::export::session::{FileTask, Outcome, PictureKind, VideoRequest, describe_video};
use crate::export::{Aim, ExportError, View, render_views, write_video};
use crate::render::{Gpu, RenderError, SceneRenderer};
use crate::session::Progress;
use crate::session::file_dialog::DialogOutcome;
use eframe::egui;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// A picture of the window on its way: where it goes, and the slot egui's callback fills.
pub(super) struct Screenshot {
    path: PathBuf,
    image: Arc<Mutex<Option<Arc<egui::ColorImage>>>>,
    requested: bool,
}

/// The device of the window, or (tests, headless) one of the job's own.
fn gpu_or_new(gpu: Option<Arc<Gpu>>) -> Result<Arc<Gpu>, RenderError> {
    match gpu {
        Some(g) => Ok(g),
        None => Gpu::new().map(Arc::new),
    }
}

/// A case's name as part of a file name.
fn file_stem(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '-' })
        .collect();
    if s.trim_matches('-').is_empty() { "case".into() } else { s }
}

/// `path` with the task's extension when it has none (a name typed into a save dialog).
fn with_extension(task: &FileTask, path: PathBuf) -> PathBuf {
    let ext = match task {
        FileTask::OpenCase => return path,
        FileTask::SaveCase => "toml",
        FileTask::ExportCsv => "csv",
        FileTask::Picture(_) => "png",
        FileTask::Video(v) => v.format.extension(),
        FileTask::FilmOverlay => "mp4",
    };
    if path.extension().is_some() { path } else { path.with_extension(ext) }
}

/// `folder/name`, or `name-2`, `name-3`, ... where that is taken.
fn unused_path(folder: &Path, name: &str) -> PathBuf {
    let p = folder.join(name);
    if !p.exists() {
        return p;
    }
    let (stem, ext) = match name.rsplit_once('.') {
        Some((s, e)) => (s.to_string(), format!(".{e}")),
        None => (name.to_string(), String::new()),
    };
    (2..10_000).map(|k| folder.join(format!("{stem}-{k}{ext}"))).find(|q| !q.exists()).unwrap_or(p)
}

/// Where F12 puts pictures before any folder was chosen: ~/Pictures, the home folder, or here.
fn default_picture_folder() -> PathBuf {
    let home = std::env::var_os("HOME").map(PathBuf::from).filter(|h| h.is_dir());
    match home {
        Some(h) if h.join("Pictures").is_dir() => h.join("Pictures"),
        Some(h) => h,
        None => PathBuf::from("."),
    }
}

impl RinglabApp {
    /// Does what a menu asked for.
    pub fn act_on_menu(&mut self, action: MenuAction) {
        match action {
            MenuAction::None => {}
            MenuAction::Recording(r) => {
                if r != RecordingAction::None {
                    self.side_tab = SideTab::Recording;
                }
                self.act_on_recording(r);
            }
            MenuAction::File(task) => self.request_file(task),
            MenuAction::VideoDialog => {
                let now = self.runs.first().map_or(0.0, |_| self.run_time(0));
                let end =
                    self.end_seconds().map(|s| s / self.runs.first().map_or(1.0, |r| r.time_s()));
                self.video_dialog.show(now, end, self.player.speed());
            }
            MenuAction::Presentation(on) => self.set_presentation(on),
            MenuAction::Zoom(z) => self.zoom(z),
        }
    }

    /// Presentation mode on or off (applied in the next frame).
    pub fn set_presentation(&mut self, on: bool) {
        self.presentation.on = on;
    }

    pub fn presenting(&self) -> bool {
        self.presentation.on
    }

    /// A step of the UI's scale, in the present mode's own (kept in the settings).
    pub fn zoom(&mut self, z: Zoom) {
        let on = self.presentation.on;
        let slot = if on { &mut self.settings.presentation_zoom } else { &mut self.settings.zoom };
        *slot = z.apply(*slot, on);
    }

    /// The scale the UI is drawn at now.
    pub fn zoom_now(&self) -> f32 {
        let z =
            if self.presentation.on { self.settings.presentation_zoom } else { self.settings.zoom };
        if z.is_finite() {
            z.clamp(super::presentation::ZOOM_MIN, super::presentation::ZOOM_MAX)
        } else {
            1.0
        }
    }

    /// Asks for a path for `task`: the live window opens the dialog at the end of the frame;
    /// in fixed mode the request waits for [`RinglabApp::file_chosen`].
    pub fn request_file(&mut self, task: FileTask) {
        self.exports.request(task);
    }

    /// The case file the sliders edit (the left one unless the right is chosen).
    fn edited_case(&self) -> &CaseFile {
        if self.settings.compare && self.settings.edit_second {
            &self.settings.compare_case
        } else {
            &self.settings.case
        }
    }

    /// The file name a save dialog proposes for `task`.
    pub fn default_file_name(&self, task: &FileTask) -> String {
        let case = file_stem(&self.edited_case().name);
        let t = if self.runs.is_empty() { 0.0 } else { self.run_time(0) };
        match task {
            FileTask::OpenCase => String::new(),
            FileTask::SaveCase => format!("{case}.toml"),
            FileTask::ExportCsv => format!("{case}.csv"),
            FileTask::Picture(PictureKind::Window) => format!("ringlab-{case}-t{t:.1}.png"),
            FileTask::Picture(PictureKind::View3d) => format!("ringlab-{case}-3d-t{t:.1}.png"),
            FileTask::FilmOverlay => {
                let film = self.recording.loaded().and_then(|l| l.film.as_ref());
                let stem =
                    film.and_then(|f| f.path.file_stem()).map(|s| s.to_string_lossy().into_owned());
                format!("{}-overlay.mp4", stem.unwrap_or_else(|| "film".into()))
            }
            FileTask::Video(v) => format!(
                "ringlab-{case}-t{:.1}-{:.1}.{}",
                v.spec.from,
                v.spec.to,
                v.format.extension()
            ),
        }
    }

    /// The live window: the dialog for a waiting request.
    pub(super) fn open_requested_dialog(&mut self) {
        if !self.live || self.exports.dialog_open() {
            return;
        }
        if let Some(task) = self.exports.take_request() {
            let name = self.default_file_name(&task);
            let folder = self.exports.last_folder.clone();
            self.exports.open_dialog(task, task.dialog(name, folder));
        }
    }

    /// What the dialogs, the writes and the video finished since the last frame.
    pub(super) fn take_export_outcomes(&mut self) {
        if let Some((task, outcome)) = self.exports.poll_dialog() {
            match outcome {
                DialogOutcome::Picked(p) => self.file_chosen(task, p),
                DialogOutcome::Opened { name, bytes } => self.file_opened(task, &name, &bytes),
                DialogOutcome::Cancelled => {}
                DialogOutcome::Unavailable(why) => self.recording.note = Some(why),
            }
        }
        for o in self.exports.poll() {
            self.say(o);
        }
    }

    /// Waits for the files being written and the video (tests; pictures).
    pub fn finish_export_jobs(&mut self) {
        for o in self.exports.wait() {
            self.say(o);
        }
    }

    /// An outcome in the window's message strip (the recording's: one strip for the window).
    fn say(&mut self, o: Outcome) {
        match o {
            Ok(note) => self.recording.note = Some(note),
            Err(e) => self.recording.error = Some(e),
        }
    }

    /// Does what the path was chosen for (the dialog's answer; tests call it with their own).
    pub fn file_chosen(&mut self, task: FileTask, path: PathBuf) {
        let path = with_extension(&task, path);
        let needs_desktop = matches!(
            task,
            FileTask::Picture(PictureKind::View3d) | FileTask::Video(_) | FileTask::FilmOverlay
        );
        if cfg!(target_arch = "wasm32") && needs_desktop {
            return self.say(Err(format!("{}: {}", path.display(), super::menus::DESKTOP_ONLY)));
        }
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            self.exports.last_folder = Some(dir.to_path_buf());
        }
        match task {
            FileTask::OpenCase => self.open_case(&path),
            FileTask::SaveCase => {
                let o = crate::export::deliver::save_case(&path, self.edited_case())
                    .map(|()| format!("saved the case to {}", path.display()));
                self.say(o);
            }
            FileTask::ExportCsv => self.export_csv(path),
            FileTask::Picture(PictureKind::Window) => {
                self.screenshot =
                    Some(Screenshot { path, image: Arc::default(), requested: false });
            }
            FileTask::Picture(PictureKind::View3d) => self.save_view_picture(path),
            FileTask::Video(v) => self.export_video(v, path),
            FileTask::FilmOverlay => self.export_film_overlay(path),
        }
    }

    /// The film the recording was tracked from, with its overlay (what the film panel shows:
    /// the tracked marks, and the model's where one was fitted or diagnosed), as an MP4.
    fn export_film_overlay(&mut self, path: PathBuf) {
        let Some(loaded) = self.recording.loaded() else {
            return self.say(Err("no recording is open: no film to export".into()));
        };
        let Some(film) = loaded.film.clone() else {
            return self
                .say(Err("the recording was not tracked from a film: no film to export".into()));
        };
        let rec = loaded.recording.clone();
        let model = self.recording.model_marks().cloned();
        let started = self.exports.start_video(move |ctx| {
            let overlay = crate::session::overlay::Overlay {
                tracked: &rec,
                model: model.as_deref().map(|m| m.as_slice()),
            };
            crate::export::overlay::write_overlay(
                &film.path,
                &film.options,
                &overlay,
                &path,
                &mut |done, total| {
                    ctx.report(Progress {
                        fraction: done as f32 / total.max(1) as f32,
                        text: format!("frame {done} of {total}"),
                    });
                    !ctx.cancelled()
                },
            )
            .map(|()| format!("wrote the film with its overlay to {}", path.display()))
            .map_err(|e| e.to_string())
        });
        if !started {
            self.say(Err("a video is being made: wait for it, or cancel it".into()));
        }
    }

    /// Reads a case file into the case the sliders edit (`ringlab --config` at the start).
    pub fn open_case(&mut self, path: &Path) {
        self.adopt_case_file(load_case_file(path), path);
    }

    /// A file a web page's picker read (no path on a disk): only a case is ever opened so.
    fn file_opened(&mut self, task: FileTask, name: &str, bytes: &[u8]) {
        let path = Path::new(name);
        match task {
            FileTask::OpenCase => match std::str::from_utf8(bytes) {
                Ok(text) => self.adopt_case_file(crate::config::CaseFile::parse(text, path), path),
                Err(_) => self.say(Err(format!("{name}: not a text file (a case is TOML)"))),
            },
            _ => self.say(Err(format!("{name}: only a case is opened here"))),
        }
    }

    fn adopt_case_file(
        &mut self,
        file: Result<crate::config::CaseFile, crate::config::ConfigError>,
        path: &Path,
    ) {
        match file {
            Ok(f) => {
                let name = f.name.clone();
                if self.settings.compare && self.settings.edit_second {
                    self.settings.compare_preset = name.clone();
                    self.settings.compare_case = f;
                } else {
                    self.settings.preset = name.clone();
                    self.settings.case = f;
                }
                self.error = None;
                self.rebuild_runs();
                self.say(Ok(format!("opened the case '{name}' from {}", path.display())));
            }
            Err(e) => self.say(Err(e.to_string())),
        }
    }

    fn export_csv(&mut self, path: PathBuf) {
        let case = match self.edited_case().build() {
            Ok(c) => c,
            Err(e) => return self.say(Err(format!("the case does not run, no CSV written: {e}"))),
        };
        self.exports.start_writing("export-csv", move || {
            write_run_csv(&case, &path)
                .map(|n| {
                    format!(
                        "wrote the run, {n} rows (the columns of simulate --out), to {}",
                        path.display()
                    )
                })
                .map_err(|e| e.to_string())
        });
    }

    /// The 3D view as it is now, at its size on the screen with every pixel drawn.
    fn save_view_picture(&mut self, path: PathBuf) {
        let frames = self.view_frames();
        let size = self.view_px;
        let gpu = self.gpu.clone();
        self.exports.start_writing("picture", move || {
            let gpu = gpu_or_new(gpu).map_err(|e| e.to_string())?;
            let mut renderer = SceneRenderer::new(&gpu.device, None);
            let img =
                render_views(&gpu, &mut renderer, &frames, size).map_err(|e| e.to_string())?;
            save_png(&img, &path).map_err(|e| e.to_string())?;
            Ok(format!("saved the 3D view ({}x{}) to {}", size[0], size[1], path.display()))
        });
    }

    /// F12 (the window) and Shift+F12 (the 3D view): a picture at once, into the folder of the
    /// last file saved (at first ~/Pictures), under a name not yet taken.
    pub fn quick_picture(&mut self, kind: PictureKind) {
        let folder = self.exports.last_folder.clone().unwrap_or_else(default_picture_folder);
        let task = FileTask::Picture(kind);
        let path = unused_path(&folder, &self.default_file_name(&task));
        self.file_chosen(task, path);
    }

    /// The window's picture: asked of the renderer at the end of a frame, written when it
    /// comes (a frame or two later), off the UI thread.
    pub(super) fn pump_screenshot(&mut self, ctx: &egui::Context) {
        let Some(s) = &mut self.screenshot else { return };
        if !s.requested {
            s.requested = true;
            let (slot, c) = (Arc::clone(&s.image), ctx.clone());
            ctx.request_screenshot(move |img| {
                if let Ok(mut g) = slot.lock() {
                    *g = Some(img);
                }
                c.request_repaint();
            });
            return;
        }
        let Some(img) = s.image.lock().ok().and_then(|mut g| g.take()) else { return };
        let path = s.path.clone();
        self.screenshot = None;
        self.exports.start_writing("picture", move || {
            let rgba = from_color_image(&img);
            save_png(&rgba, &path).map_err(|e| e.to_string())?;
            Ok(format!(
                "saved the window ({}x{}) to {}",
                rgba.width(),
                rgba.height(),
                path.display()
            ))
        });
    }

    /// Makes the video off the UI thread: the runs computed afresh in the job, drawn as the
    /// window draws them (the whole window: as it is outside presentation mode, unscaled), on
    /// a device of the job's own: on the window's, its waits for every frame read back also
    /// waited for the window's frames (40 units at 480x270 took 13 to 15 s there, 9 to 11 s
    /// on its own, lavapipe, the machine loaded).
    fn export_video(&mut self, v: VideoRequest, path: PathBuf) {
        let cases = match self.cases() {
            Ok(c) => c,
            Err(e) => return self.say(Err(format!("the case does not run, no video made: {e}"))),
        };
        let names = self.run_names();
        let (camera, contact) = (self.camera, self.settings.show_contact);
        let aim = if self.settings.follow { Aim::Follow } else { Aim::Fixed };
        let settings =
            super::Settings { detail_3d: Detail3d::Full, zoom: 1.0, ..self.settings.clone() };
        let started = self.exports.start_video(move |ctx| {
            let run = || -> Result<_, ExportError> {
                let gpu = Gpu::new()?;
                let mut source = match v.view {
                    View::ThreeD => FrameSource::three_d(&gpu, cases, camera, aim, contact),
                    View::Top => {
                        FrameSource::top(&gpu, names.into_iter().zip(cases).collect(), contact)
                    }
                    View::App => FrameSource::app(
                        &gpu,
                        RinglabApp::new(settings, Mode::Fixed { seconds: 0.0 }),
                    ),
                };
                write_video(&gpu, &mut source, &v.spec, v.size, &path, &mut |done, total| {
                    ctx.report(Progress {
                        fraction: done as f32 / total.max(1) as f32,
                        text: format!("frame {done} of {total}"),
                    });
                    !ctx.cancelled()
                })
            };
            describe_video(run())
        });
        if !started {
            self.say(Err(
                "a video is being made: wait for it, or cancel it (File > Export video…)".into(),
            ));
        }
    }

    /// Keys that type no text (they work while a field has the focus): F11, F12, Shift+F12,
    /// Ctrl +, Ctrl -, Ctrl 0.
    pub(super) fn classroom_keys(&mut self, ctx: &egui::Context) {
        use egui::{Key, Modifiers};
        let (f11, view3d, window) = ctx.input_mut(|i| {
            (
                i.consume_key(Modifiers::NONE, Key::F11),
                i.consume_key(Modifiers::SHIFT, Key::F12),
                i.consume_key(Modifiers::NONE, Key::F12),
            )
        });
        if f11 {
            self.set_presentation(!self.presentation.on);
        }
        if view3d {
            self.quick_picture(PictureKind::View3d);
        } else if window {
            self.quick_picture(PictureKind::Window);
        }
        if let Some(z) = zoom_keys(ctx) {
            self.zoom(z);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_for_files() {
        assert_eq!(file_stem("paper-ring"), "paper-ring");
        assert_eq!(file_stem("sample-ring.csv, fitted"), "sample-ring-csv--fitted");
        assert_eq!(file_stem("//"), "case");
        assert_eq!(
            with_extension(&FileTask::ExportCsv, PathBuf::from("/tmp/run")),
            PathBuf::from("/tmp/run.csv")
        );
        assert_eq!(
            with_extension(&FileTask::SaveCase, PathBuf::from("/tmp/a.txt")),
            PathBuf::from("/tmp/a.txt")
        );
        let dir = std::env::temp_dir().join(format!("ringlab-unused-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        assert_eq!(unused_path(&dir, "a.png"), dir.join("a.png"));
        std::fs::write(dir.join("a.png"), b"x").unwrap();
        assert_eq!(unused_path(&dir, "a.png"), dir.join("a-2.png"));
        std::fs::remove_dir_all(&dir).ok();
    }
}
