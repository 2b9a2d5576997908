//! Lab trackers' files read as recordings: DeepLabCut CSV, Open Source Physics Tracker (data
//! tables and `.trk` projects), Fiji TrackMate spots CSV, and a plain CSV with named columns.
//!
//! Each reader turns its file into [`PointTracks`] (named points per frame, in the file's unit
//! and y direction); [`points::assemble`] picks the four marks, converts to pixels (y down) and
//! writes the header from the file and the [`ImportOptions`]. What the files do not say (frame
//! rate, scale, the body) must come from the options: a missing one is an error, never a guess.
//! Dropped points (low likelihood, spots outside any track) are counted in [`ImportReport`].

pub mod dlc;
pub mod plain;
pub mod points;
pub mod table;
pub mod tracker;
pub mod trackmate;
pub mod trk;
pub mod unit;

pub use points::PointTracks;
pub use unit::LengthUnit;

use super::Recording;
use super::read::{MAGIC, ReadError, ReadErrorKind, parse_recording};
use crate::physics::Shape;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// The trackers ringlab reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// ringlab's own format v1.
    Ringlab,
    Dlc,
    /// Tracker's exported data table (one file per point mass).
    TrackerTable,
    /// Tracker's project file (XML).
    TrackerProject,
    TrackMate,
    /// A CSV with the frame (or time) and the marks' x and y in named columns.
    Plain,
}

impl Source {
    pub fn name(self) -> &'static str {
        match self {
            Source::Ringlab => "ringlab v1",
            Source::Dlc => "DeepLabCut CSV",
            Source::TrackerTable => "Tracker data table",
            Source::TrackerProject => "Tracker project (.trk)",
            Source::TrackMate => "TrackMate spots CSV",
            Source::Plain => "plain CSV",
        }
    }

    /// What a file's first bytes say it is (`None`: no telling; a plain CSV is never guessed).
    pub fn detect(path: &Path, bytes: &[u8]) -> Option<Source> {
        let text = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]);
        let text = text.trim_start_matches('\u{feff}');
        let mut lines = text.lines();
        let first = lines.next().unwrap_or("").trim();
        let second = lines.next().unwrap_or("").trim();
        let cells = |l: &str| -> Vec<String> {
            l.split(table::delimiter_of(l) as char)
                .map(|c| c.trim().trim_matches('"').to_string())
                .collect()
        };
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        let second = cells(second);
        let tracker_table = second.len() >= 3
            && second[0] == "t"
            && second.iter().any(|h| h == "x")
            && second.iter().any(|h| h == "y");
        if first.starts_with(MAGIC.trim_end_matches(" v1")) {
            Some(Source::Ringlab)
        } else if ext.as_deref() == Some("trk")
            || first.starts_with("<?xml")
            || first.starts_with("<object")
        {
            Some(Source::TrackerProject)
        } else if cells(first).first().is_some_and(|c| c.eq_ignore_ascii_case("scorer")) {
            Some(Source::Dlc)
        } else if ["TRACK_ID", "FRAME", "POSITION_X", "POSITION_Y"]
            .iter()
            .all(|k| cells(first).iter().any(|c| c == k))
        {
            Some(Source::TrackMate)
        } else if tracker_table {
            Some(Source::TrackerTable)
        } else {
            None
        }
    }
}

/// The format named on the command line (`--from`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Dlc,
    /// A Tracker data table or project, told apart by content.
    Tracker,
    TrackMate,
    Csv,
}

impl Format {
    pub const NAMES: &'static str = "dlc, tracker, trackmate, csv";

    pub fn parse(s: &str) -> Option<Format> {
        match s.to_ascii_lowercase().as_str() {
            "dlc" | "deeplabcut" => Some(Format::Dlc),
            "tracker" => Some(Format::Tracker),
            "trackmate" => Some(Format::TrackMate),
            "csv" => Some(Format::Csv),
            _ => None,
        }
    }
}

/// The body, for the header (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyMm {
    pub shape: Shape,
    pub outer_radius_mm: f64,
    pub width_mm: f64,
    pub thickness_mm: Option<f64>,
}

impl BodyMm {
    /// The body of a case (a preset), in mm.
    pub fn of_case(case: &crate::config::CaseFile) -> Result<BodyMm, String> {
        let b = case.build()?.in_units(crate::physics::Units::MM_S)?.model.body;
        // Presets in model units come back with the conversion's last-digit noise.
        let mm = |x: f64| (x * 1e9).round() / 1e9;
        Ok(BodyMm {
            shape: b.shape,
            outer_radius_mm: mm(b.r),
            width_mm: mm(b.h),
            thickness_mm: (b.shape == Shape::Ring).then_some(mm(b.w)),
        })
    }
}

/// What the files may not say, from the user.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportOptions {
    pub fps: Option<f64>,
    pub px_per_mm: Option<f64>,
    /// The four marks' names (bodyparts, track ids, point masses) in cyclic order.
    pub marks: Option<Vec<String>>,
    /// DeepLabCut: points below this likelihood are missing marks.
    pub min_likelihood: f64,
    pub body: Option<BodyMm>,
    /// Plain CSV: the frame (or `time:NAME`) and x1, y1 .. x4, y4 columns, by name or number.
    pub columns: Option<Vec<String>>,
    /// The positions' unit where the file does not say it.
    pub unit: Option<LengthUnit>,
    /// Plain CSV: y grows upward.
    pub y_up: bool,
}

impl Default for ImportOptions {
    fn default() -> Self {
        ImportOptions {
            fps: None,
            px_per_mm: None,
            marks: None,
            min_likelihood: DEFAULT_MIN_LIKELIHOOD,
            body: None,
            columns: None,
            unit: None,
            y_up: false,
        }
    }
}

/// DeepLabCut's usual threshold.
pub const DEFAULT_MIN_LIKELIHOOD: f64 = 0.6;

/// What an import did beyond the recording itself.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportReport {
    pub source: Source,
    pub files: Vec<PathBuf>,
    /// The names taken as marks 1 to 4.
    pub marks: Vec<String>,
    /// DeepLabCut points below `--min-likelihood`, dropped as missing marks.
    pub low_likelihood: usize,
    /// Points the file itself left blank (nothing found).
    pub blank: usize,
    /// Everything else said (points left out and why, defaults taken).
    pub notes: Vec<String>,
}

/// A recording read from any supported file, with what the import did.
#[derive(Clone, Debug, PartialEq)]
pub struct Imported {
    pub recording: Recording,
    pub report: ImportReport,
}

/// A file that could not be imported: where, and what is wrong.
#[derive(Debug, Error, Clone, PartialEq)]
#[error("{}{}: {kind}", path.display(), line.map(|l| format!(":{l}")).unwrap_or_default())]
pub struct ImportError {
    pub path: PathBuf,
    pub line: Option<usize>,
    pub kind: ImportErrorKind,
}

/// What is wrong with an imported file (or with the options for it).
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ImportErrorKind {
    #[error("cannot read the file: {0}")]
    Io(String),
    #[error("the file is empty")]
    Empty,
    #[error("{0}")]
    Csv(String),
    #[error("not valid XML: {0}")]
    Xml(String),
    #[error("not a {format}: {what}")]
    NotThisFormat { format: &'static str, what: String },
    #[error(
        "cannot tell what this file is (not ringlab v1, DeepLabCut, Tracker or TrackMate): name its format with --from {}",
        Format::NAMES
    )]
    UnknownFormat,
    #[error("{what} reads {expected}, got {got} files")]
    FileCount { what: &'static str, expected: &'static str, got: usize },
    #[error("no column '{name}' (the columns are: {available})")]
    MissingColumn { name: String, available: String },
    #[error("{what} = '{value}' is not a number")]
    NotNumeric { what: String, value: String },
    #[error("{what} = {value} is not a finite number")]
    NonFinite { what: String, value: String },
    #[error("frame '{value}' is not a whole number")]
    BadFrame { value: String },
    #[error("{what} has x but not y, or y but not x")]
    HalfPoint { what: String },
    #[error("'{name}' is given twice in frame {frame} (first on line {first_line})")]
    DuplicatePoint { name: String, frame: i64, first_line: usize },
    #[error(
        "time {t} s is not on the frame grid of {fps} frames/s (frame {frames:.3}); give --fps"
    )]
    OffGrid { t: f64, fps: f64, frames: f64 },
    #[error("--marks: '{name}' is not in the file (it has: {available})")]
    UnknownMark { name: String, available: String },
    #[error("--marks: {0}")]
    BadMarks(String),
    #[error("{found} point(s) found ({names}); four marks are needed")]
    TooFewPoints { found: usize, names: String },
    #[error(
        "marks {order} are not in cyclic order around the rim in {bad} of {frames} frames with all four (the diagonals do not cross); give them in order, e.g. --marks {suggestion}"
    )]
    NotCyclic { order: String, bad: usize, frames: usize, suggestion: String },
    #[error("the frame rate is not in the file: give --fps")]
    MissingFps,
    #[error("the scale is not in the file (positions are pixels): give --px-per-mm")]
    MissingScale,
    #[error(
        "the body is not in the file: give --preset NAME, or --shape, --outer-radius-mm, --width-mm (and --thickness-mm for a ring)"
    )]
    MissingBody,
    #[error("{0}")]
    MissingUnit(String),
    #[error("the file says its positions are in {file}, but --unit says {given}")]
    UnitConflict { file: String, given: String },
    #[error("{0}")]
    BadOption(String),
    #[error(
        "fewer than two usable frames ({usable}): a frame is usable when marks 1 and 3, or 2 and 4, are both found"
    )]
    TooFewUsableFrames { usable: usize },
    #[error("{0}")]
    Recording(ReadErrorKind),
}

impl ImportErrorKind {
    /// Whether the user can put it right with the import's options (the window then asks for
    /// them), rather than by mending the file.
    pub fn needs_options(&self) -> bool {
        use ImportErrorKind as K;
        matches!(
            self,
            K::UnknownFormat
                | K::MissingFps
                | K::MissingScale
                | K::MissingBody
                | K::MissingUnit(_)
                | K::UnitConflict { .. }
                | K::UnknownMark { .. }
                | K::BadMarks(_)
                | K::NotCyclic { .. }
                | K::TooFewPoints { .. }
                | K::MissingColumn { .. }
                | K::BadOption(_)
                | K::OffGrid { .. }
        )
    }
}

impl ImportError {
    pub fn new(path: &Path, line: Option<usize>, kind: ImportErrorKind) -> ImportError {
        ImportError { path: path.to_path_buf(), line, kind }
    }
}

impl From<ReadError> for ImportError {
    fn from(e: ReadError) -> Self {
        ImportError { path: e.path, line: e.line, kind: ImportErrorKind::Recording(e.kind) }
    }
}

/// Reads the files as one recording: format v1 as it is, every other format through its reader and [`points::assemble`].
pub fn import(
    paths: &[PathBuf],
    from: Option<Format>,
    opts: &ImportOptions,
) -> Result<Imported, ImportError> {
    let mut files = Vec::with_capacity(paths.len());
    for p in paths {
        let bytes = std::fs::read(p)
            .map_err(|e| ImportError::new(p, None, ImportErrorKind::Io(e.to_string())))?;
        files.push((p.clone(), bytes));
    }
    import_bytes(&files, from, opts)
}

/// [`import`] of files already read (a web page's: their names, and their bytes).
pub fn import_bytes(
    files: &[(PathBuf, Vec<u8>)],
    from: Option<Format>,
    opts: &ImportOptions,
) -> Result<Imported, ImportError> {
    let first = files.first().map(|(p, _)| p.as_path()).ok_or_else(|| {
        ImportError::new(Path::new("-"), None, ImportErrorKind::BadOption("no file given".into()))
    })?;
    if let Some((p, _)) = files.iter().find(|(_, b)| b.iter().all(u8::is_ascii_whitespace)) {
        return Err(ImportError::new(p, None, ImportErrorKind::Empty));
    }
    let paths: Vec<PathBuf> = files.iter().map(|(p, _)| p.clone()).collect();
    let paths = paths.as_slice();
    let detected = Source::detect(first, &files[0].1);
    let source = match (from, detected) {
        (_, Some(Source::Ringlab)) => Source::Ringlab,
        (None, Some(s)) => s,
        (None, None) => return Err(ImportError::new(first, None, ImportErrorKind::UnknownFormat)),
        (Some(Format::Dlc), _) => Source::Dlc,
        (Some(Format::TrackMate), _) => Source::TrackMate,
        (Some(Format::Csv), _) => Source::Plain,
        (Some(Format::Tracker), Some(Source::TrackerProject)) => Source::TrackerProject,
        (Some(Format::Tracker), _) => Source::TrackerTable,
    };
    let one = |what| {
        if files.len() == 1 {
            Ok(())
        } else {
            Err(ImportError::new(
                first,
                None,
                ImportErrorKind::FileCount { what, expected: "one file", got: files.len() },
            ))
        }
    };
    let tracks = match source {
        Source::Ringlab => {
            one("a ringlab recording")?;
            return ringlab_file(first, &files[0].1, from.is_some(), opts);
        }
        Source::Dlc => {
            one("a DeepLabCut CSV")?;
            dlc::read(first, &files[0].1, opts.min_likelihood)?
        }
        Source::TrackMate => {
            one("a TrackMate spots CSV")?;
            trackmate::read(first, &files[0].1)?
        }
        Source::Plain => {
            one("a plain CSV")?;
            plain::read(first, &files[0].1, opts)?
        }
        Source::TrackerProject => {
            one("a Tracker project")?;
            trk::read(first, &files[0].1)?
        }
        Source::TrackerTable => tracker::read(files, opts)?,
    };
    points::assemble(tracks, source, paths, opts)
}

/// A v1 file, read as it is: its header says everything, so options meant for trackers' files
/// (a folder may hold both) are not applied to it, and that is said.
fn ringlab_file(
    path: &Path,
    bytes: &[u8],
    format_named: bool,
    opts: &ImportOptions,
) -> Result<Imported, ImportError> {
    let set: Vec<&str> = [
        ("format", format_named),
        ("fps", opts.fps.is_some()),
        ("px per mm", opts.px_per_mm.is_some()),
        ("marks", opts.marks.is_some()),
        ("body", opts.body.is_some()),
        ("columns", opts.columns.is_some()),
        ("unit", opts.unit.is_some()),
        ("y up", opts.y_up),
    ]
    .iter()
    .filter(|(_, on)| *on)
    .map(|(n, _)| *n)
    .collect();
    let recording = parse_recording(bytes, path)?;
    let mut notes = Vec::new();
    if !set.is_empty() {
        notes.push(format!(
            "{}: a ringlab v1 recording, read by its own header (the given {} not applied)",
            path.display(),
            set.join(", ")
        ));
    }
    let report = ImportReport {
        source: Source::Ringlab,
        files: vec![path.to_path_buf()],
        marks: (1..=4).map(|i| format!("mark {i}")).collect(),
        low_likelihood: 0,
        blank: 0,
        notes,
    };
    Ok(Imported { recording, report })
}
