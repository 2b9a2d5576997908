//! A recording read and its motion recovered, and the cases the simulator adopts from it
//! (the model started from the data; the fitted model; the diagnosis's models).

use crate::analysis::diagnose::ModelFit;
use crate::analysis::fit::FitResult;
use crate::config::{
    BodySection, CaseFile, DragSection, EffectsSection, InitialSection, RunSection, UnitsSection,
};
use crate::film::{TrackOptions, TrackReport};
use crate::physics::model::ix;
use crate::physics::{Body, EffectKind, Initial, Units, paper};
use crate::recording::import::{
    Format, ImportError, ImportOptions, ImportReport, import, import_bytes,
};
use crate::recording::recover::{FrameMotion, RecoverError};
use crate::recording::{Recording, RecoveredMotion, recover};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use thiserror::Error;

/// Where a recording came from when it was tracked from a film.
#[derive(Clone, Debug)]
pub struct FilmOrigin {
    /// The video file or folder of frames.
    pub path: PathBuf,
    /// How it was tracked (`from_frame`: the film's frame of the recording's first).
    pub options: TrackOptions,
    pub report: TrackReport,
}

/// Why a recording could not be opened (the read error names the file and the line).
#[derive(Debug, Error, Clone, PartialEq)]
pub enum LoadError {
    #[error(transparent)]
    Read(#[from] ImportError),
    #[error("{}: {source}", path.display())]
    Recover { path: PathBuf, source: RecoverError },
    /// A film that could not be tracked (the message names the file).
    #[error("{0}")]
    Film(String),
    #[error("the tracking was cancelled")]
    Cancelled,
}

/// A recording read and its motion recovered.
pub struct LoadedRecording {
    pub path: PathBuf,
    pub recording: Arc<Recording>,
    pub motion: RecoveredMotion,
    /// How the file was read (a tracker's file: its marks, what was dropped, notes).
    pub import: ImportReport,
    /// The film it was tracked from, if it was.
    pub film: Option<FilmOrigin>,
}

impl LoadedRecording {
    /// Reads a recording (format v1) and recovers its motion (slow for long recordings: run
    /// it as a job).
    pub fn load(path: &Path) -> Result<LoadedRecording, LoadError> {
        Self::import(path, None, None, &ImportOptions::default())
    }

    /// Reads any file `ringlab import` reads, with what the file does not say in `opts`: from
    /// the disk, or where `bytes` are given (a web page's file, `path` its name), from those.
    pub fn import(
        path: &Path,
        bytes: Option<&[u8]>,
        format: Option<Format>,
        opts: &ImportOptions,
    ) -> Result<LoadedRecording, LoadError> {
        let imported = match bytes {
            Some(b) => import_bytes(&[(path.to_path_buf(), b.to_vec())], format, opts)?,
            None => import(&[path.to_path_buf()], format, opts)?,
        };
        let recording = imported.recording;
        let motion = recover(&recording)
            .map_err(|source| LoadError::Recover { path: path.to_path_buf(), source })?;
        Ok(LoadedRecording {
            path: path.to_path_buf(),
            recording: Arc::new(recording),
            motion,
            import: imported.report,
            film: None,
        })
    }

    /// The file's name, for labels.
    pub fn name(&self) -> String {
        self.path
            .file_name()
            .map_or_else(|| self.path.display().to_string(), |n| n.to_string_lossy().into_owned())
    }

    pub fn fps(&self) -> f64 {
        self.motion.fps
    }

    pub fn frames(&self) -> &[FrameMotion] {
        &self.motion.frames
    }

    /// Length of the recording (s).
    pub fn duration_s(&self) -> f64 {
        self.motion.frames.len().saturating_sub(1) as f64 / self.motion.fps
    }

    /// Marks missing over all frames (of four per frame).
    pub fn marks_missing(&self) -> usize {
        (4 * self.recording.frames.len()).saturating_sub(self.recording.mark_count())
    }

    /// The model's units for this recording (lengths in mean radii, the paper's `g`).
    pub fn units(&self) -> Units {
        self.motion.units
    }

    /// A case file for a model of this recording's body (model units) with drag `c` and
    /// start `initial`.
    fn case_file(
        &self,
        name: String,
        description: String,
        c: [f64; 3],
        initial: &Initial,
        t_end: f64,
    ) -> Result<CaseFile, String> {
        let body: Body =
            self.motion.body_model().map_err(|e| format!("the recording's body: {e}"))?;
        self.case_file_with(name, description, (body, EffectsSection::default()), c, initial, t_end)
    }

    /// As [`Self::case_file`] with another body (model units) and effects.
    fn case_file_with(
        &self,
        name: String,
        description: String,
        (body, effects): (Body, EffectsSection),
        c: [f64; 3],
        initial: &Initial,
        t_end: f64,
    ) -> Result<CaseFile, String> {
        let u = self.units();
        let file = CaseFile {
            name,
            description,
            source: self.path.display().to_string(),
            units: UnitsSection {
                system: "model".into(),
                mean_radius_mm: Some(u.length_mm),
                g: Some(u.g()),
            },
            body: BodySection {
                shape: body.shape.name().into(),
                outer_radius: body.r,
                width: body.h,
                thickness: Some(body.w),
            },
            drag: DragSection { c },
            initial: InitialSection {
                theta: initial.theta,
                theta_dot: initial.theta_dot,
                phi: initial.phi,
                phi_dot: initial.phi_dot,
                psi: initial.psi,
                psi_dot: initial.psi_dot,
                x: initial.x_c,
                y: initial.y_c,
            },
            run: RunSection { t_end, ..RunSection::default() },
            effects,
        };
        file.build()?;
        Ok(file)
    }

    /// The recording in model time units, with room for a model that runs on past its end.
    fn t_end_model(&self) -> f64 {
        (2.0 * self.duration_s() / self.units().time_s).max(RunSection::default().t_end)
    }

    /// The case to start the model from before any fit: the recording's body, the paper's
    /// drag (where the fit starts too), and the state reconstructed from the poses at the first
    /// inner turning point (or the nearest frame that has one). Returns the case and the
    /// frame it starts at.
    pub fn start_case(&self) -> Result<(CaseFile, usize), String> {
        let m = &self.motion;
        let f0 = m.first_inner_turn.map_or(0, |p| p.at.round().max(0.0) as usize);
        let found = (0..6).flat_map(|d| [f0 + d, f0.saturating_sub(d)]).find_map(|j| {
            m.state(j, 4, false).or_else(|| m.turning_point_state(j, false)).map(|y| (j, y))
        });
        let Some((j, mut y)) = found else {
            return Err(
                "no start state could be reconstructed near the first inner turning point".into()
            );
        };
        // A turning point: theta' = 0 there (the rates from a few noisy poses say otherwise
        // by their noise, and at the first frame they are one-sided).
        y[ix::W1] = 0.0;
        let name = format!("{}, not fitted", self.name());
        let description = format!(
            "the recording's body, started at frame {j} from the poses; the paper's drag (not fitted)"
        );
        let file = self.case_file(
            name,
            description,
            paper::C_RING,
            &Initial::from_state(&y),
            self.t_end_model(),
        )?;
        Ok((file, j))
    }

    /// The case of a fit: the recording's body, the fitted drag and start state.
    pub fn fitted_case(&self, r: &FitResult) -> Result<CaseFile, String> {
        let name = format!("{}, fitted", self.name());
        let description = format!("the model fitted to {}: rms {:.3} px", self.name(), r.rms_px);
        self.case_file(name, description, r.c, &r.start, self.t_end_model())
    }

    /// The case of a diagnosis's model (the baseline or the improved one): the body as it
    /// fitted, its drag, start state and effect. The camera's distortion is no physics: its
    /// model runs as the paper's.
    pub fn diagnosed_case(&self, m: &ModelFit) -> Result<CaseFile, String> {
        let what = if m.effect == EffectKind::None {
            "baseline".to_string()
        } else {
            format!("with {}", m.effects_label())
        };
        let name = format!("{}, diagnosed ({what})", self.name());
        let description = format!(
            "the diagnosis's model of {} ({what}): rms {:.3} px over the whole run",
            self.name(),
            m.rms_px
        );
        let e = &m.model.effects;
        let effects = EffectsSection {
            reynolds_drag: e.reynolds_drag.map(|r| [r.re_ref, r.exponent, r.max_factor]),
            rolling_friction: e.rolling_friction,
            pivot_friction: e.pivot_friction,
            translational_drag: e.translational_drag,
            slip_mu: e.slip_mu,
            slip_start_held: e.slip_start == crate::physics::SlipStart::HeldRolling,
            table_slope: e.table_slope.map(|t| [t.angle.to_degrees(), t.direction.to_degrees()]),
        };
        self.case_file_with(
            name,
            description,
            (m.model.body.clone(), effects),
            m.c,
            &m.start,
            self.t_end_model(),
        )
    }
}
