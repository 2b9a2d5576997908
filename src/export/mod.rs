//! What the classroom takes away from a run: a video (GIF or MP4) of it, pictures, the case as a
//! file, the samples as CSV; and what a lab takes away: a film of the ring as its camera would
//! take it, with the marks' true positions (`film`, `film_frames`). Frames come from the same
//! renderer and panels as the window (`ui::frames`, through the [`Frames`] trait: export knows
//! nothing of the window); encoding is the `gif` crate through `image` ([`gif`]) or an
//! `ffmpeg` found on PATH ([`mp4`]).

pub mod csv;
pub mod deliver;
pub mod film;
pub mod film_frames;
pub mod frames;
pub mod gif;
pub mod mp4;
pub mod overlay;
pub mod picture;
pub mod png_folder;
pub mod session;
pub mod sink;
pub mod video;

pub use film::{FilmMarks, FilmPlan, FilmSpec, plan_film};
pub use film_frames::{FilmReport, write_film};
pub use frames::{Aim, Frames, View, render_views};
pub use video::{VideoFormat, VideoSpec, write_video};

use std::path::PathBuf;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum ExportError {
    #[error("cannot write {path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    #[error("{0}")]
    Render(#[from] crate::render::RenderError),
    #[error("encoding {path} failed: {message}")]
    Encode { path: PathBuf, message: String },
    #[error(
        "ffmpeg was not found on PATH: an MP4 is made by ffmpeg (Debian: apt-get install ffmpeg); \
         a GIF needs nothing (name the file .gif)"
    )]
    NoFfmpeg,
    #[error("ffmpeg failed writing {path}: {message}")]
    Ffmpeg { path: PathBuf, message: String },
    #[error("{0}")]
    Invalid(String),
    #[error("cancelled")]
    Cancelled,
}

impl ExportError {
    pub(crate) fn io(path: &std::path::Path) -> impl FnOnce(std::io::Error) -> ExportError + '_ {
        move |source| ExportError::Io { path: path.to_path_buf(), source }
    }
}

/// What is wrong with a film's or a video's time span `--from`..`--to`, named as the command
/// line names them.
pub(crate) fn check_span(from: f64, to: f64) -> Result<(), String> {
    if !(from.is_finite() && from >= 0.0) {
        return Err(format!("--from = {from}: must be a time at or after the start (0)"));
    }
    if !(to.is_finite() && to > from) {
        return Err(format!("--to = {to}: must be later than --from = {from}"));
    }
    Ok(())
}
