//! The reader of format v1. Every problem the format names (missing required keys,
//! non-numeric or non-finite values, frames out of order, fewer than two usable frames, a
//! scale or frame rate that is not positive) is a [`ReadError`] with the file and the line;
//! nothing is skipped silently and nothing panics, whatever the bytes.
//!
//! The optional camera keys must make a camera: `camera_distance_mm` a positive number,
//! `camera_tilt_deg` within (-80, 80) degrees (beyond, the table would be seen edge-on).
//!
//! Accepted beyond the letter of the format: `\r\n` line ends, blank lines, and `#` lines
//! without `=` (comments). A frame may be given with all marks empty (nothing tracked).

use super::{FrameMarks, Header, MARKS, Recording, is_usable};
use crate::physics::Shape;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// The first line of a v1 recording.
pub const MAGIC: &str = "# ringlab-recording v1";
/// The largest camera tilt a recording may give (degrees, exclusive).
pub const MAX_TILT_DEG: f64 = 80.0;
/// The column header line.
pub const COLUMNS: [&str; 9] = ["frame", "x1", "y1", "x2", "y2", "x3", "y3", "x4", "y4"];

/// A recording that could not be read: where, and what is wrong.
#[derive(Debug, Error, Clone, PartialEq)]
#[error("{}{}: {kind}", path.display(), line.map(|l| format!(":{l}")).unwrap_or_default())]
pub struct ReadError {
    pub path: PathBuf,
    /// 1-based line number (none for problems of the whole file).
    pub line: Option<usize>,
    pub kind: ReadErrorKind,
}

/// What is wrong with a recording.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ReadErrorKind {
    #[error("cannot read the file: {0}")]
    Io(String),
    #[error("the file is empty")]
    Empty,
    #[error("not a ringlab recording: the first line must be '{MAGIC}', found '{found}'")]
    NotARecording { found: String },
    #[error("format version '{found}' is not supported (this reader reads v1)")]
    UnsupportedVersion { found: String },
    #[error("the line is not valid UTF-8")]
    InvalidUtf8,
    #[error("header key '{key}' is empty")]
    EmptyKey { key: String },
    #[error("header key '{key}' is given twice (first on line {first_line})")]
    DuplicateKey { key: String, first_line: usize },
    #[error("missing required header key '{key}'")]
    MissingKey { key: &'static str },
    #[error("{what} = '{value}' is not a number")]
    NotNumeric { what: String, value: String },
    #[error("{what} = {value} is not a finite number")]
    NonFinite { what: String, value: String },
    #[error("{key} = {value} must be greater than zero")]
    NotPositive { key: &'static str, value: f64 },
    #[error("{key} = {value} must lie between {lo} and {hi} (exclusive)")]
    OutOfRange { key: &'static str, value: f64, lo: f64, hi: f64 },
    #[error("shape = '{value}' is neither 'ring' nor 'disk'")]
    UnknownShape { value: String },
    #[error("the body is impossible: {0}")]
    InvalidBody(String),
    #[error("no column header 'frame,x1,y1,x2,y2,x3,y3,x4,y4' after the header")]
    MissingColumns,
    #[error("the column header must be 'frame,x1,y1,x2,y2,x3,y3,x4,y4', found '{found}'")]
    BadColumns { found: String },
    #[error("expected 9 fields (frame, then x and y of marks 1 to 4), found {found}")]
    FieldCount { found: usize },
    #[error("frame number '{value}' is not a whole number >= 0")]
    BadFrameNumber { value: String },
    #[error(
        "frames out of order: frame {found} follows frame {previous} (frames must be consecutive)"
    )]
    FrameOutOfOrder { previous: u64, found: u64 },
    #[error("mark {mark} has {present} but not {missing} (a mark has both coordinates or neither)")]
    HalfMark { mark: usize, present: &'static str, missing: &'static str },
    #[error(
        "fewer than two usable frames ({usable}); a frame is usable when both marks of an opposite pair (1 and 3, or 2 and 4) are tracked"
    )]
    TooFewUsableFrames { usable: usize },
}

/// Reads a recording from a file.
pub fn read_recording(path: &Path) -> Result<Recording, ReadError> {
    let bytes = std::fs::read(path).map_err(|e| ReadError {
        path: path.to_path_buf(),
        line: None,
        kind: ReadErrorKind::Io(e.to_string()),
    })?;
    parse_recording(&bytes, path)
}

/// Parses a recording held in memory; `path` only names it in errors.
pub fn parse_recording(bytes: &[u8], path: &Path) -> Result<Recording, ReadError> {
    let err = |line: Option<usize>, kind| ReadError { path: path.to_path_buf(), line, kind };
    let mut lines = Lines { rest: bytes, number: 0 };

    // Line 1: the magic line.
    let first = match lines.next() {
        None => return Err(err(None, ReadErrorKind::Empty)),
        Some((n, l)) => (n, text(l).map_err(|k| err(Some(n), k))?),
    };
    let magic = first.1.trim_start_matches('\u{feff}').trim();
    if magic != MAGIC {
        let kind = match magic.strip_prefix("# ringlab-recording ") {
            Some(v) => ReadErrorKind::UnsupportedVersion { found: v.trim().to_string() },
            None => ReadErrorKind::NotARecording { found: clip(magic) },
        };
        return Err(err(Some(first.0), kind));
    }

    // Header lines up to the column header.
    let mut keys: Vec<(String, String, usize)> = Vec::new();
    let columns_line = loop {
        let Some((n, raw)) = lines.next() else {
            return Err(err(None, ReadErrorKind::MissingColumns));
        };
        let line = text(raw).map_err(|k| err(Some(n), k))?.trim();
        if line.is_empty() {
            continue;
        }
        if let Some(body) = line.strip_prefix('#') {
            let Some((k, v)) = body.split_once('=') else { continue };
            let (k, v) = (k.trim(), v.trim());
            if k.is_empty() {
                return Err(err(Some(n), ReadErrorKind::EmptyKey { key: clip(body) }));
            }
            if let Some((_, _, first_line)) = keys.iter().find(|(key, _, _)| key == k) {
                let kind =
                    ReadErrorKind::DuplicateKey { key: k.to_string(), first_line: *first_line };
                return Err(err(Some(n), kind));
            }
            keys.push((k.to_string(), v.to_string(), n));
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields != COLUMNS {
            return Err(err(Some(n), ReadErrorKind::BadColumns { found: clip(line) }));
        }
        break n;
    };
    let header = parse_header(&keys, columns_line).map_err(|(line, kind)| err(Some(line), kind))?;

    // Frames.
    let mut frames: Vec<FrameMarks> = Vec::with_capacity(bytes.len() / 64);
    let mut first_frame = 0u64;
    let mut last_line = columns_line;
    let mut usable = 0usize;
    while let Some((n, raw)) = lines.next() {
        last_line = n;
        let line = text(raw).map_err(|k| err(Some(n), k))?.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let (number, marks) = parse_frame(line).map_err(|k| err(Some(n), k))?;
        if let Some(prev) = frames.len().checked_sub(1).map(|i| first_frame + i as u64) {
            if prev.checked_add(1) != Some(number) {
                return Err(err(
                    Some(n),
                    ReadErrorKind::FrameOutOfOrder { previous: prev, found: number },
                ));
            }
        } else {
            first_frame = number;
        }
        usable += is_usable(&marks) as usize;
        frames.push(marks);
    }
    if usable < 2 {
        return Err(err(Some(last_line), ReadErrorKind::TooFewUsableFrames { usable }));
    }
    Ok(Recording { header, first_frame, frames })
}

/// Splits bytes into lines (`\n`, with a trailing `\r` removed), numbered from 1.
struct Lines<'a> {
    rest: &'a [u8],
    number: usize,
}

impl<'a> Lines<'a> {
    fn next(&mut self) -> Option<(usize, &'a [u8])> {
        if self.rest.is_empty() {
            return None;
        }
        self.number += 1;
        let (line, rest) = match self.rest.iter().position(|&b| b == b'\n') {
            Some(i) => (&self.rest[..i], &self.rest[i + 1..]),
            None => (self.rest, &self.rest[self.rest.len()..]),
        };
        self.rest = rest;
        Some((self.number, line.strip_suffix(b"\r").unwrap_or(line)))
    }
}

fn text(line: &[u8]) -> Result<&str, ReadErrorKind> {
    std::str::from_utf8(line).map_err(|_| ReadErrorKind::InvalidUtf8)
}

/// A value quoted in an error, cut to a readable length.
fn clip(s: &str) -> String {
    const MAX: usize = 60;
    match s.char_indices().nth(MAX) {
        Some((i, _)) => format!("{}...", &s[..i]),
        None => s.to_string(),
    }
}

/// Parses a finite number; `what` names it in the error.
fn parse_number(what: &str, value: &str) -> Result<f64, ReadErrorKind> {
    match value.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(ReadErrorKind::NonFinite { what: what.to_string(), value: clip(value) }),
        Err(_) => Err(ReadErrorKind::NotNumeric { what: what.to_string(), value: clip(value) }),
    }
}

type HeaderError = (usize, ReadErrorKind);

fn parse_header(
    keys: &[(String, String, usize)],
    columns_line: usize,
) -> Result<Header, HeaderError> {
    let find = |key: &str| keys.iter().find(|(k, _, _)| k == key);
    let required =
        |key: &'static str| find(key).ok_or((columns_line, ReadErrorKind::MissingKey { key }));
    let positive = |key: &'static str,
                    entry: &(String, String, usize)|
     -> Result<f64, HeaderError> {
        let v = parse_number(key, &entry.1).map_err(|k| (entry.2, k))?;
        if v > 0.0 { Ok(v) } else { Err((entry.2, ReadErrorKind::NotPositive { key, value: v })) }
    };
    let fps = positive("fps", required("fps")?)?;
    let px_per_mm = positive("px_per_mm", required("px_per_mm")?)?;
    let shape_entry = required("shape")?;
    let shape = Shape::parse(&shape_entry.1)
        .ok_or((shape_entry.2, ReadErrorKind::UnknownShape { value: clip(&shape_entry.1) }))?;
    let outer = required("outer_radius_mm")?;
    let outer_radius_mm = positive("outer_radius_mm", outer)?;
    let width_mm = positive("width_mm", required("width_mm")?)?;
    let thickness_mm = match (shape, find("thickness_mm")) {
        (Shape::Ring, None) => {
            return Err((columns_line, ReadErrorKind::MissingKey { key: "thickness_mm" }));
        }
        (_, Some(e)) => Some(positive("thickness_mm", e)?),
        (Shape::Disk, None) => None,
    };
    let image_width_px =
        find("image_width_px").map(|e| positive("image_width_px", e)).transpose()?;
    let image_height_px =
        find("image_height_px").map(|e| positive("image_height_px", e)).transpose()?;
    let camera_distance_mm =
        find("camera_distance_mm").map(|e| positive("camera_distance_mm", e)).transpose()?;
    let camera_tilt_deg = find("camera_tilt_deg")
        .map(|e| {
            const KEY: &str = "camera_tilt_deg";
            let v = parse_number(KEY, &e.1).map_err(|k| (e.2, k))?;
            let (lo, hi) = (-MAX_TILT_DEG, MAX_TILT_DEG);
            if v > lo && v < hi {
                Ok(v)
            } else {
                Err((e.2, ReadErrorKind::OutOfRange { key: KEY, value: v, lo, hi }))
            }
        })
        .transpose()?;
    const KNOWN: [&str; 10] = [
        "fps",
        "px_per_mm",
        "shape",
        "outer_radius_mm",
        "width_mm",
        "thickness_mm",
        "image_width_px",
        "image_height_px",
        "camera_distance_mm",
        "camera_tilt_deg",
    ];
    let extra = keys
        .iter()
        .filter(|(k, _, _)| !KNOWN.contains(&k.as_str()))
        .map(|(k, v, _)| (k.clone(), v.clone()))
        .collect();
    let header = Header {
        fps,
        px_per_mm,
        shape,
        outer_radius_mm,
        width_mm,
        thickness_mm,
        image_width_px,
        image_height_px,
        camera_distance_mm,
        camera_tilt_deg,
        extra,
    };
    if let Err(e) = header.body_mm() {
        let line = find("thickness_mm").map(|e| e.2).unwrap_or(outer.2);
        return Err((line, ReadErrorKind::InvalidBody(e.to_string())));
    }
    Ok(header)
}

const MARK_COLUMNS: [[&str; 2]; MARKS] = [["x1", "y1"], ["x2", "y2"], ["x3", "y3"], ["x4", "y4"]];

fn parse_frame(line: &str) -> Result<(u64, FrameMarks), ReadErrorKind> {
    let mut fields = [""; 9];
    let mut count = 0;
    for f in line.split(',') {
        if count < fields.len() {
            fields[count] = f.trim();
        }
        count += 1;
    }
    if count != fields.len() {
        return Err(ReadErrorKind::FieldCount { found: count });
    }
    let number = fields[0]
        .parse::<u64>()
        .map_err(|_| ReadErrorKind::BadFrameNumber { value: clip(fields[0]) })?;
    let mut marks: FrameMarks = [None; MARKS];
    for (k, names) in MARK_COLUMNS.iter().enumerate() {
        let (x, y) = (fields[1 + 2 * k], fields[2 + 2 * k]);
        marks[k] = match (x.is_empty(), y.is_empty()) {
            (true, true) => None,
            (false, true) => {
                return Err(ReadErrorKind::HalfMark {
                    mark: k + 1,
                    present: names[0],
                    missing: names[1],
                });
            }
            (true, false) => {
                return Err(ReadErrorKind::HalfMark {
                    mark: k + 1,
                    present: names[1],
                    missing: names[0],
                });
            }
            (false, false) => Some([parse_number(names[0], x)?, parse_number(names[1], y)?]),
        };
    }
    Ok((number, marks))
}
