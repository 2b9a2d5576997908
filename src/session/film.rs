//! A film opened in the window: its marks tracked in a job ([`crate::film::track`]), the
//! recording made of them loaded as any recording is (so that the fit and the diagnosis work
//! on it), and the film kept so that its frames can be shown; the model's marks over it, once
//! fitted or diagnosed.

use super::job::{JobContext, Progress};
use super::loaded::{FilmOrigin, LoadError, LoadedRecording};
use crate::analysis::diagnose::ModelFit;
use crate::analysis::fit::shooting::predict_samples;
use crate::film::{FilmError, FilmErrorKind, TrackOptions, TrackedFilm, track};
use crate::physics::RunOptions;
use crate::physics::model::ix;
use crate::recording::import::{ImportError, ImportErrorKind, ImportOptions, ImportReport, Source};
use crate::recording::marks::{MarkGeometry, MarkOrder};
use crate::recording::{Recording, recover};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The model's four marks in pixels per stored frame of the recording (`None` where it has
/// none): what is drawn over the film.
pub type ModelMarks = Vec<Option<[[f64; 2]; 4]>>;

/// The tracking's options for the window: what the import options give (the body, a frame
/// rate where the film has none), the marks' style told from the film, the scale measured
/// from the ring unless `px_per_mm` is given. None where no body is known.
pub fn film_options(opts: &ImportOptions, px_per_mm: Option<f64>) -> Option<TrackOptions> {
    Some(TrackOptions { fps: opts.fps, px_per_mm, ..TrackOptions::for_body(opts.body?) })
}

/// What the film lacks, as the import dialog asks for it; None for any other failure.
fn needs_options(e: &FilmError) -> Option<ImportErrorKind> {
    match e.kind {
        FilmErrorKind::NeedsFps => Some(ImportErrorKind::MissingFps),
        FilmErrorKind::NoScale => Some(ImportErrorKind::MissingScale),
        _ => None,
    }
}

/// The import dialog's question for a film without a body.
pub fn missing_body(path: &Path) -> ImportError {
    ImportError { path: path.to_path_buf(), line: None, kind: ImportErrorKind::MissingBody }
}

/// Tracks the film on the job (its progress, its cancel) and loads the recording it gives.
pub(super) fn track_and_load(
    path: &Path,
    options: TrackOptions,
    ctx: &JobContext,
) -> Result<LoadedRecording, LoadError> {
    let mut progress = |done: u64, total: Option<u64>| {
        let text = match total {
            Some(n) => format!("tracking the film: frame {done} of {n}"),
            None => format!("tracking the film: frame {done}"),
        };
        let fraction = total.map_or(0.0, |n| (done as f32 / n.max(1) as f32).min(1.0));
        ctx.report(Progress { fraction, text });
    };
    match track(path, &options, &mut progress, ctx.cancel_flag()) {
        Ok(t) => LoadedRecording::from_film(path, t, options),
        Err(e) if matches!(e.kind, FilmErrorKind::Cancelled) => Err(LoadError::Cancelled),
        Err(e) => match needs_options(&e) {
            Some(kind) => Err(LoadError::Read(ImportError { path: e.path, line: None, kind })),
            None => Err(LoadError::Film(e.to_string())),
        },
    }
}

impl LoadedRecording {
    /// The recording tracked from a film, its motion recovered.
    pub fn from_film(
        path: &Path,
        tracked: TrackedFilm,
        options: TrackOptions,
    ) -> Result<LoadedRecording, LoadError> {
        let TrackedFilm { recording, report, .. } = tracked;
        let motion = recover(&recording)
            .map_err(|source| LoadError::Recover { path: path.to_path_buf(), source })?;
        let mut notes = vec![format!(
            "tracked from the film: {} marks, found from frame {}; {} of {} marks found",
            report.style.name(),
            report.acquired_at,
            report.marks_found,
            4 * report.frames
        )];
        notes.extend(report.notes.iter().cloned());
        let import = ImportReport {
            source: Source::Ringlab,
            files: vec![path.to_path_buf()],
            marks: (1..=4).map(|k| format!("mark {k}")).collect(),
            low_likelihood: 0,
            blank: 0,
            notes,
        };
        Ok(LoadedRecording {
            path: path.to_path_buf(),
            recording: Arc::new(recording),
            motion,
            import,
            film: Some(FilmOrigin { path: path.to_path_buf(), options, report }),
        })
    }
}

/// The marks of a diagnosis's model (fitted over the whole run from one start state) at every
/// stored frame from its start on, through its camera; `order`: the recording's numbering.
pub fn diagnosed_marks(rec: &Recording, order: MarkOrder, m: &ModelFit) -> ModelMarks {
    let n = rec.frames.len();
    let mut out = vec![None; n];
    let fps = rec.header.fps;
    let start = (m.start_s * fps).round() - rec.first_frame as f64;
    if !(start >= 0.0) || !(start < n as f64) || !(m.units.time_s > 0.0) {
        return out;
    }
    let start = start as usize;
    let dt = 1.0 / (fps * m.units.time_s);
    let run = RunOptions::default();
    let Some(samples) = predict_samples(&m.model, &run, dt, &m.start.to_state(), start..n) else {
        return out;
    };
    let geometry = MarkGeometry::of_body(&m.model.body, order);
    let k = m.units.length_mm;
    for (slot, s) in out[start..].iter_mut().zip(&samples) {
        let (phi, theta, psi) = (s.y[ix::PHI], s.y[ix::THETA], s.y[ix::PSI]);
        let a = [s.x_a, s.y_a];
        *slot = Some(if m.camera.sees_height() {
            geometry
                .marks3(a, phi, theta, psi)
                .map(|p| m.camera.to_px3(p[0] * k, p[1] * k, p[2] * k))
        } else {
            geometry.marks(a, phi, theta, psi).map(|p| m.camera.to_px(p[0] * k, p[1] * k))
        });
    }
    out
}

impl super::RecordingSession {
    /// Starts tracking the film at `path` (the dialog's, File > Open video's and a drop's way
    /// in for a film); `px_per_mm`: the scale where the ring cannot give it. Without a body
    /// in the import options the import dialog asks for one first.
    pub fn open_film(&mut self, path: PathBuf, px_per_mm: Option<f64>) {
        self.error = None;
        self.note = None;
        self.pending_import = None;
        let Some(options) = film_options(&self.import_options, px_per_mm) else {
            self.pending_import =
                Some(super::PendingImport { error: missing_body(&path), path, bytes: None });
            return;
        };
        let p = path.clone();
        let read = move |ctx: &JobContext| track_and_load(&p, options, ctx);
        self.loading = Some((path, None, super::Job::start("track-film", self.background, read)));
    }

    /// Tracks the open film again with other options (the film panel's Tracking: the marks'
    /// style, the frames, the region, the scale); the recording it gives replaces this one.
    pub fn track_film_again(&mut self, options: TrackOptions) {
        let Some(path) = self.film().map(|f| f.path.clone()) else { return };
        self.error = None;
        self.note = None;
        self.pending_import = None;
        let p = path.clone();
        let read = move |ctx: &JobContext| track_and_load(&p, options, ctx);
        self.loading = Some((path, None, super::Job::start("track-film", self.background, read)));
    }

    /// File > Open video's dialog (its answer arrives through `poll`).
    pub fn open_video_dialog(&mut self) {
        if self.dialog.is_none() {
            self.note = None;
            self.dialog = Some(super::file_dialog::pick_video(self.background));
        }
    }

    /// Where the reading or the tracking is, while it runs.
    pub fn loading_progress(&self) -> Option<Progress> {
        self.loading.as_ref().map(|(_, _, j)| j.progress())
    }

    /// Asks the tracking of a film (or a reading) to stop.
    pub fn cancel_loading(&mut self) {
        if let Some((_, _, j)) = &self.loading {
            j.cancel();
        }
    }

    /// The film the loaded recording was tracked from, if it was.
    pub fn film(&self) -> Option<&FilmOrigin> {
        self.loaded.as_ref()?.film.as_ref()
    }

    /// Asks for the film's frame shown at display time `seconds` (the recording's frame
    /// there: before the first, the first).
    pub fn want_film_frame(&mut self, seconds: f64) {
        let Some(first) = self.loaded.as_ref().map(|l| l.recording.first_frame) else { return };
        let k = self.frame_at(seconds).unwrap_or(0) as u64;
        if let Some(f) = &mut self.film_frames {
            f.want(first + k);
        }
    }

    /// The film's frame decoded last, with the recording's stored frame it shows.
    pub fn film_frame(&self) -> Option<(usize, &crate::film::Frame)> {
        let first = self.loaded.as_ref()?.recording.first_frame;
        let (n, frame) = self.film_frames.as_ref()?.shown()?;
        Some((n.checked_sub(first)? as usize, frame))
    }

    /// Why the film's last frame asked for could not be read.
    pub fn film_error(&self) -> Option<&str> {
        self.film_frames.as_ref()?.error.as_deref()
    }

    /// The marks of the model last given to the simulator (fitted, or a diagnosis's), at
    /// every stored frame: for a film's recording only.
    pub fn model_marks(&self) -> Option<&Arc<ModelMarks>> {
        self.model_marks.as_ref()
    }
}
