//! What the window does with a recording, without egui: opening it (the file dialog
//! ([`file_dialog`]), a tracker's file and the options it needs), reading it and recovering its
//! motion, fitting the model to it or diagnosing it, each as a [`Job`] off the UI thread; what
//! was loaded, fitted and diagnosed; the recording frame by frame on the display's clock; the
//! cases the simulator adopts. (The live run of the model is [`crate::sim`]'s.)
//!
//! The clock: the display counts seconds from the model's start (t = 0). The model starts at
//! the recording's first inner turning point (reconstructed from the poses on loading, the
//! fitted start after a fit), so frame `i` is shown at `i / fps - offset`, `offset` the time of
//! that start from the first stored frame (frames are counted from the first stored one, as
//! the fit counts them).

mod diagnosing;
pub mod file_dialog;
mod film;
mod film_frames;
mod fitting;
pub mod job;
mod loaded;
pub mod overlay;
pub mod page_worker;

pub use diagnosing::Diagnosed;
pub use film::{ModelMarks, diagnosed_marks};
pub use film_frames::FilmFrames;
pub use fitting::describe_fit_progress;
pub use loaded::{FilmOrigin, LoadError, LoadedRecording};

use crate::analysis::diagnose::{DiagnoseError, Diagnosis};
use crate::analysis::fit::{FitError, FitResult};
use crate::config::CaseFile;
use crate::recording::import::{Format, ImportError, ImportOptions};
use crate::recording::recover::{Angles, FrameMotion};
use diagnosing::run_diagnose;
use file_dialog::{DialogOutcome, pick_recording};
use fitting::run_fit;
pub use job::{Job, JobContext, JobLost, Progress};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A fit done, and the case it gives.
pub struct Fitted {
    pub result: FitResult,
    pub case: CaseFile,
    /// The fitted model's marks at every frame (a film's recording only: drawn over it).
    pub marks: Option<Arc<ModelMarks>>,
}

/// What the app should do after [`RecordingSession::poll`].
#[derive(Clone, Debug, PartialEq)]
pub enum SessionEvent {
    /// A recording is loaded: start the model from this case (None: it has no start state;
    /// the model stays as it was).
    Loaded(Option<CaseFile>),
    /// A fit is done, or a diagnosis's model was chosen: adopt this case.
    Fitted(CaseFile),
}

/// Which of a diagnosis's models to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiagnosedModel {
    Baseline,
    Improved,
}

/// Everything about the recording in the window.
pub struct RecordingSession {
    /// Jobs on threads (the live window) or at once (tests, pictures).
    background: bool,
    loaded: Option<LoadedRecording>,
    loading: Option<(PathBuf, Option<Arc<[u8]>>, Job<Result<LoadedRecording, LoadError>>)>,
    dialog: Option<Job<DialogOutcome>>,
    fitting: Option<Job<Result<(FitResult, Option<Arc<ModelMarks>>), FitError>>>,
    fitted: Option<Fitted>,
    diagnosing: Option<Job<Result<(Diagnosis, Option<[Arc<ModelMarks>; 2]>), DiagnoseError>>>,
    diagnosed: Option<Diagnosed>,
    /// Seconds from the first stored frame to the model's t = 0.
    offset_s: f64,
    /// A film's frames, where the recording was tracked from one.
    film_frames: Option<FilmFrames>,
    /// The model's marks drawn over a film: the fit's, the diagnosis's chosen model's once
    /// diagnosed, or the model last put in the simulator.
    model_marks: Option<Arc<ModelMarks>>,
    /// The web page's workers of the running fit and diagnosis (ended on Cancel).
    #[cfg(target_arch = "wasm32")]
    fit_worker: Option<page_worker::PageWorker>,
    #[cfg(target_arch = "wasm32")]
    diagnose_worker: Option<page_worker::PageWorker>,
    /// A problem to show until dismissed (a file that could not be read, a failed fit).
    pub error: Option<String>,
    /// Something to know that is no error (a cancelled fit, no dialog).
    pub note: Option<String>,
    /// What trackers' files do not say, as last given (used for every file opened).
    pub import_options: ImportOptions,
    pub import_format: Option<Format>,
    /// A tracker's file that needs options before it can be read: the window asks for them.
    pending_import: Option<PendingImport>,
}

/// A file waiting for the import's options, and what was missing.
#[derive(Clone, Debug, PartialEq)]
pub struct PendingImport {
    pub path: PathBuf,
    /// The file's bytes where it has no path on a disk (a web page's file).
    pub bytes: Option<Arc<[u8]>>,
    pub error: ImportError,
}

impl RecordingSession {
    pub fn new(background: bool) -> RecordingSession {
        RecordingSession {
            background,
            loaded: None,
            loading: None,
            dialog: None,
            fitting: None,
            fitted: None,
            diagnosing: None,
            diagnosed: None,
            offset_s: 0.0,
            film_frames: None,
            model_marks: None,
            #[cfg(target_arch = "wasm32")]
            fit_worker: None,
            #[cfg(target_arch = "wasm32")]
            diagnose_worker: None,
            error: None,
            note: None,
            import_options: ImportOptions::default(),
            import_format: None,
            pending_import: None,
        }
    }

    /// The file waiting for the import's options, if any.
    pub fn pending_import(&self) -> Option<&PendingImport> {
        self.pending_import.as_ref()
    }

    /// Reads the waiting file again with these options (remembered for the next files).
    pub fn retry_import(&mut self, format: Option<Format>, options: ImportOptions) {
        self.import_format = format;
        self.import_options = options;
        if let Some(p) = self.pending_import.take() {
            if crate::film::is_film(&p.path) {
                // A film's scale is measured from the ring: one given is taken where it cannot be.
                let scale = p.error.kind == crate::recording::import::ImportErrorKind::MissingScale;
                let px_per_mm = self.import_options.px_per_mm.filter(|_| scale);
                self.open_film(p.path, px_per_mm);
            } else {
                self.open_with(p.path, p.bytes);
            }
        }
    }

    /// Gives up on the waiting file.
    pub fn dismiss_import(&mut self) {
        self.pending_import = None;
    }

    pub fn loaded(&self) -> Option<&LoadedRecording> {
        self.loaded.as_ref()
    }

    pub fn fitted(&self) -> Option<&Fitted> {
        self.fitted.as_ref()
    }

    pub fn diagnosed(&self) -> Option<&Diagnosed> {
        self.diagnosed.as_ref()
    }

    /// Where the diagnosis is, while one runs.
    pub fn diagnose_progress(&self) -> Option<Progress> {
        self.diagnosing.as_ref().map(|j| j.progress())
    }

    pub fn diagnose_cancelling(&self) -> bool {
        self.diagnosing.as_ref().is_some_and(|j| j.is_cancelling())
    }

    /// The mismatch window of the diagnosis on the display's clock (s from the model's t = 0).
    pub fn mismatch_display_s(&self) -> Option<(f64, f64)> {
        let l = self.loaded.as_ref()?;
        self.diagnosed.as_ref()?.mismatch_display_s(l.recording.first_frame, l.fps(), self.offset_s)
    }

    /// The file being read, if any.
    pub fn loading(&self) -> Option<&Path> {
        self.loading.as_ref().map(|(p, _, _)| p.as_path())
    }

    pub fn dialog_open(&self) -> bool {
        self.dialog.is_some()
    }

    /// Where the fit is, while one runs.
    pub fn fit_progress(&self) -> Option<Progress> {
        self.fitting.as_ref().map(|j| j.progress())
    }

    pub fn fit_cancelling(&self) -> bool {
        self.fitting.as_ref().is_some_and(|j| j.is_cancelling())
    }

    /// Whether anything runs that the window should redraw for.
    pub fn busy(&self) -> bool {
        self.loading.is_some()
            || self.fitting.is_some()
            || self.dialog.is_some()
            || self.diagnosing.is_some()
            || self.film_frames.as_ref().is_some_and(FilmFrames::busy)
    }

    /// Opens the file dialog (its answer arrives through [`RecordingSession::poll`]).
    pub fn open_dialog(&mut self) {
        if self.dialog.is_none() {
            self.note = None;
            self.dialog = Some(pick_recording(self.background));
        }
    }

    /// Opens the file once `read` (a page's file being read) gives it, as a dialog's answer.
    pub fn open_when_read(&mut self, read: Job<DialogOutcome>) {
        self.note = None;
        self.dialog = Some(read);
    }

    /// Starts reading `path` (the dialog's and drag-and-drop's way in). A fit of the previous
    /// recording is stopped; the previous recording stays until the new one is read.
    pub fn open(&mut self, path: PathBuf) {
        self.open_with(path, None)
    }

    /// Starts reading a file handed over with its bytes and no path on a disk (a web page's
    /// file, dropped or picked: `name` is its name).
    pub fn open_bytes(&mut self, name: &str, bytes: Arc<[u8]>) {
        self.open_with(PathBuf::from(name), Some(bytes))
    }

    fn open_with(&mut self, path: PathBuf, bytes: Option<Arc<[u8]>>) {
        if crate::film::is_film(&path) {
            if bytes.is_some() {
                self.error = Some(format!(
                    "{}: films are tracked by the desktop app (it decodes them with ffmpeg), not \
                     in a web page; track it there (`ringlab track`) and open the recording here",
                    path.display()
                ));
                return;
            }
            return self.open_film(path, None);
        }
        self.error = None;
        self.note = None;
        self.pending_import = None;
        let (p, b) = (path.clone(), bytes.clone());
        let (format, opts) = (self.import_format, self.import_options.clone());
        let read = move |_: &_| LoadedRecording::import(&p, b.as_deref(), format, &opts);
        self.loading = Some((path, bytes, Job::start("read-recording", self.background, read)));
    }

    /// Forgets the recording (a running fit or diagnosis stops).
    pub fn close(&mut self) {
        self.loaded = None;
        self.fitted = None;
        self.fitting = None;
        #[cfg(target_arch = "wasm32")]
        {
            self.fit_worker = None;
            self.diagnose_worker = None;
        }
        self.diagnosed = None;
        self.diagnosing = None;
        self.loading = None;
        self.note = None;
        self.offset_s = 0.0;
        self.film_frames = None;
        self.model_marks = None;
    }

    /// Starts a fit of the loaded recording (none while one runs).
    pub fn start_fit(&mut self) {
        let Some(l) = &self.loaded else { return };
        if self.fitting.is_some() {
            return;
        }
        self.note = None;
        let rec = Arc::clone(&l.recording);
        let background = self.background;
        let film = l.film.is_some();
        #[cfg(target_arch = "wasm32")]
        if background
            && let Some((job, worker)) =
                page_worker::in_worker(page_worker::Work::Fit, &rec, |answer| {
                    answer
                        .and_then(|t| page_worker::result_from_text(&t))
                        .map(|r| (r, None))
                        .map_err(FitError::Apart)
                })
        {
            self.fitting = Some(job);
            self.fit_worker = Some(worker);
            return;
        }
        self.fitting = Some(Job::start("fit", background, move |ctx| {
            let r = run_fit(&rec, ctx, background)?;
            let marks = film.then(|| Arc::new(r.predicted_marks(&rec.frames)));
            Ok((r, marks))
        }));
    }

    /// Asks a running fit to stop.
    pub fn cancel_fit(&mut self) {
        if let Some(j) = &self.fitting {
            j.cancel();
        }
        // A worker has no flag to look at: it is ended, and the fit with it.
        #[cfg(target_arch = "wasm32")]
        if self.fit_worker.take().is_some() {
            self.fitting = None;
            self.note = Some("the fit was cancelled".into());
        }
    }

    /// Starts a diagnosis of the loaded recording (none while one runs).
    pub fn start_diagnose(&mut self) {
        let Some(l) = &self.loaded else { return };
        if self.diagnosing.is_some() {
            return;
        }
        self.note = None;
        let rec = Arc::clone(&l.recording);
        let background = self.background;
        let order = l.film.as_ref().map(|_| l.motion.mark_order);
        // A page's recordings are never films: no marks to draw over one.
        #[cfg(target_arch = "wasm32")]
        if background
            && let Some((job, worker)) =
                page_worker::in_worker(page_worker::Work::Diagnose, &rec, |answer| {
                    answer
                        .and_then(|t| page_worker::result_from_text(&t))
                        .map(|d| (d, None))
                        .map_err(DiagnoseError::Apart)
                })
        {
            self.diagnosing = Some(job);
            self.diagnose_worker = Some(worker);
            return;
        }
        self.diagnosing = Some(Job::start("diagnose", background, move |ctx| {
            let d = run_diagnose(&rec, ctx, background)?;
            let marks =
                order.map(|o| [&d.before, &d.after].map(|m| Arc::new(diagnosed_marks(&rec, o, m))));
            Ok((d, marks))
        }));
    }

    /// Asks a running diagnosis to stop.
    pub fn cancel_diagnose(&mut self) {
        if let Some(j) = &self.diagnosing {
            j.cancel();
        }
        #[cfg(target_arch = "wasm32")]
        if self.diagnose_worker.take().is_some() {
            self.diagnosing = None;
            self.note = Some("the diagnosis was cancelled".into());
        }
    }

    /// The case of one of the diagnosis's models, for the simulator; the clock's offset moves
    /// to its start. None without a diagnosis; the error where the model cannot be run.
    pub fn adopt_diagnosed(&mut self, which: DiagnosedModel) -> Option<SessionEvent> {
        let l = self.loaded.as_ref()?;
        let d = self.diagnosed.as_ref()?;
        let case = match which {
            DiagnosedModel::Baseline => &d.baseline,
            DiagnosedModel::Improved => &d.improved,
        };
        match case {
            Ok(c) => {
                self.offset_s = d.offset_s(l.recording.first_frame, l.fps());
                let k = if which == DiagnosedModel::Baseline { 0 } else { 1 };
                if let Some(m) = &d.model_marks {
                    self.model_marks = Some(Arc::clone(&m[k]));
                }
                Some(SessionEvent::Fitted(c.clone()))
            }
            Err(e) => {
                self.error = Some(format!("The diagnosed model cannot be run: {e}"));
                None
            }
        }
    }

    /// Takes in what the jobs have finished, without waiting; says what the app should adopt.
    pub fn poll(&mut self) -> Vec<SessionEvent> {
        let mut events = Vec::new();
        if let Some(outcome) = self.dialog.as_mut().and_then(|j| j.poll()) {
            self.dialog = None;
            match outcome {
                Ok(DialogOutcome::Picked(p)) => self.open(p),
                Ok(DialogOutcome::Opened { name, bytes }) => self.open_bytes(&name, bytes),
                Ok(DialogOutcome::Cancelled) => {}
                Ok(DialogOutcome::Unavailable(why)) => self.note = Some(why),
                Err(JobLost) => {
                    self.note = Some(
                        "the file dialog failed: drop the .csv file onto the window instead".into(),
                    )
                }
            }
        }
        if let Some(done) = self.loading.as_mut().and_then(|(_, _, j)| j.poll()) {
            let (path, bytes) = self.loading.take().map(|(p, b, _)| (p, b)).unwrap_or_default();
            match done {
                Ok(Ok(l)) => events.push(self.adopt_loaded(l)),
                Ok(Err(LoadError::Read(e))) if e.kind.needs_options() => {
                    self.pending_import = Some(PendingImport { path, bytes, error: e })
                }
                Ok(Err(LoadError::Cancelled)) => {
                    self.note = Some("the tracking was cancelled".into())
                }
                Ok(Err(LoadError::Film(e))) => {
                    self.error = Some(format!("Could not track the film: {e}"))
                }
                Ok(Err(e)) => self.error = Some(format!("Could not open the recording: {e}")),
                Err(JobLost) => {
                    self.error = Some(format!(
                        "Could not open the recording {}: reading it failed unexpectedly",
                        path.display()
                    ))
                }
            }
        }
        if let Some(done) = self.fitting.as_mut().and_then(|j| j.poll()) {
            self.fitting = None;
            #[cfg(target_arch = "wasm32")]
            {
                self.fit_worker = None;
            }
            match done {
                Ok(Ok((r, marks))) => events.extend(self.adopt_fit(r, marks)),
                Ok(Err(FitError::Cancelled)) => self.note = Some("the fit was cancelled".into()),
                Ok(Err(e)) => self.error = Some(format!("The fit failed: {e}")),
                Err(JobLost) => self.error = Some("The fit stopped unexpectedly".into()),
            }
        }
        if let Some(done) = self.diagnosing.as_mut().and_then(|j| j.poll()) {
            self.diagnosing = None;
            #[cfg(target_arch = "wasm32")]
            {
                self.diagnose_worker = None;
            }
            match done {
                Ok(Ok((d, model_marks))) => {
                    if let Some(l) = &self.loaded {
                        let baseline = l.diagnosed_case(&d.before);
                        let improved = l.diagnosed_case(&d.after);
                        if let Some(m) = &model_marks {
                            self.model_marks = Some(Arc::clone(&m[1]));
                        }
                        self.diagnosed =
                            Some(Diagnosed { result: d, baseline, improved, model_marks });
                    }
                }
                Ok(Err(DiagnoseError::Cancelled)) => {
                    self.note = Some("the diagnosis was cancelled".into())
                }
                Ok(Err(e)) => self.error = Some(format!("The diagnosis failed: {e}")),
                Err(JobLost) => self.error = Some("The diagnosis stopped unexpectedly".into()),
            }
        }
        if let Some(f) = &mut self.film_frames {
            f.poll();
        }
        events
    }

    /// Waits for every job to finish and takes in their results (tests; a caller that must
    /// have the result now).
    pub fn wait(&mut self) -> Vec<SessionEvent> {
        let mut events = Vec::new();
        while self.busy() {
            self.dialog.iter_mut().for_each(Job::finish);
            self.loading.iter_mut().for_each(|(_, _, j)| j.finish());
            self.fitting.iter_mut().for_each(Job::finish);
            self.diagnosing.iter_mut().for_each(Job::finish);
            self.film_frames.iter_mut().for_each(FilmFrames::finish);
            events.extend(self.poll());
        }
        events
    }

    fn adopt_loaded(&mut self, l: LoadedRecording) -> SessionEvent {
        self.fitting = None;
        self.fitted = None;
        self.diagnosing = None;
        self.diagnosed = None;
        self.model_marks = None;
        self.film_frames =
            l.film.as_ref().map(|f| FilmFrames::new(f.path.clone(), self.background));
        let start = l.start_case();
        let fps = l.fps();
        self.loaded = Some(l);
        match start {
            Ok((case, frame)) => {
                self.offset_s = frame as f64 / fps;
                SessionEvent::Loaded(Some(case))
            }
            Err(why) => {
                self.offset_s = 0.0;
                self.note = Some(format!("{why}: the model was left as it was"));
                SessionEvent::Loaded(None)
            }
        }
    }

    fn adopt_fit(&mut self, r: FitResult, marks: Option<Arc<ModelMarks>>) -> Option<SessionEvent> {
        let l = self.loaded.as_ref()?;
        match l.fitted_case(&r) {
            Ok(case) => {
                self.offset_s = r.start_t * r.units.time_s;
                self.model_marks = marks.clone();
                self.fitted = Some(Fitted { result: r, case: case.clone(), marks });
                Some(SessionEvent::Fitted(case))
            }
            Err(e) => {
                self.error = Some(format!("The fitted model cannot be run: {e}"));
                None
            }
        }
    }

    /// The fitted case again (after the sliders moved away from it).
    pub fn readopt_fit(&mut self) -> Option<SessionEvent> {
        let f = self.fitted.as_ref()?;
        self.offset_s = f.result.start_t * f.result.units.time_s;
        self.model_marks = f.marks.clone();
        Some(SessionEvent::Fitted(f.case.clone()))
    }

    /// Seconds from the first stored frame to the model's t = 0.
    pub fn offset_s(&self) -> f64 {
        self.offset_s
    }

    /// The display time (s from the model's start) of frame `i`.
    pub fn frame_seconds(&self, i: usize) -> Option<f64> {
        let l = self.loaded.as_ref()?;
        Some(i as f64 / l.fps() - self.offset_s)
    }

    /// The display time of the last frame.
    pub fn end_seconds(&self) -> Option<f64> {
        let n = self.loaded.as_ref()?.frames().len();
        self.frame_seconds(n.checked_sub(1)?)
    }

    /// The frame shown at display time `seconds`: the nearest one; None before the first
    /// frame, the last one after the end (the ring lies where it stopped).
    pub fn frame_at(&self, seconds: f64) -> Option<usize> {
        let l = self.loaded.as_ref()?;
        let k = ((seconds + self.offset_s) * l.fps()).round();
        if !(k >= 0.0) {
            return None;
        }
        Some((k as usize).min(l.frames().len().checked_sub(1)?))
    }

    /// The frames shown up to display time `seconds` (all of them before it).
    pub fn frames_until(&self, seconds: f64) -> &[FrameMotion] {
        match (self.loaded.as_ref(), self.frame_at(seconds)) {
            (Some(l), Some(k)) => &l.frames()[..=k],
            _ => &[],
        }
    }

    /// The pose at display time `seconds`: the angles and point A (mm) blended linearly
    /// between the two frames around it where both have a pose on one stretch (the angles are
    /// continuous there; a frame is up to 1/fps apart from the model's interpolated state, a
    /// visible turn of a fast ring), else from the nearest frame with a pose (within three).
    pub fn pose_at(&self, seconds: f64) -> Option<(Angles, [f64; 2])> {
        let l = self.loaded.as_ref()?;
        let k = self.frame_at(seconds)?;
        let frames = l.frames();
        let n = frames.len();
        let pose = |j: usize| frames.get(j).and_then(|f| Some((f.angles?, f.a_mm?, f.stretch)));
        let at = (seconds + self.offset_s) * l.fps();
        let i = at.floor();
        if i >= 0.0
            && let (Some((a0, p0, s0)), Some((a1, p1, s1))) =
                (pose(i as usize), pose(i as usize + 1))
            && s0.is_some()
            && s0 == s1
        {
            let u = at - i;
            let mix = |x: f64, y: f64| x + (y - x) * u;
            let angles = Angles {
                phi: mix(a0.phi, a1.phi),
                theta: mix(a0.theta, a1.theta),
                psi: mix(a0.psi, a1.psi),
            };
            return Some((angles, [mix(p0[0], p1[0]), mix(p0[1], p1[1])]));
        }
        (0..=3)
            .flat_map(|d| [k + d, k.saturating_sub(d)])
            .filter(|&j| j < n)
            .find_map(|j| pose(j).map(|(a, p, _)| (a, p)))
    }
}
