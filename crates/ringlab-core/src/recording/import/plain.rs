//! A plain CSV: a header row, then one row per frame with the frame number (or the time in
//! seconds) and each mark's x and y in columns named by `--columns` (names or 1-based
//! numbers), by default `frame, x1, y1, .., x4, y4`. Pixels and y down unless told otherwise.

use super::points::PointTracks;
use super::table::{self, Row};
use super::tracker::fps_from_times;
use super::unit::LengthUnit;
use super::{ImportError, ImportErrorKind, ImportOptions};
use crate::recording::MARKS;
use std::path::Path;

/// The default column names.
pub const DEFAULT_COLUMNS: [&str; 9] = ["frame", "x1", "y1", "x2", "y2", "x3", "y3", "x4", "y4"];

pub fn read(path: &Path, bytes: &[u8], opts: &ImportOptions) -> Result<PointTracks, ImportError> {
    let err = |line, kind| ImportError::new(path, line, kind);
    if opts.marks.is_some() {
        let msg =
            "--marks does not apply to a plain CSV: --columns names the marks' columns".to_string();
        return Err(err(None, ImportErrorKind::BadOption(msg)));
    }
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]).into_owned();
    let header_text = text
        .lines()
        .find(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .unwrap_or("");
    let rows: Vec<Row> = table::rows(path, bytes, table::delimiter_of(header_text))?
        .into_iter()
        .filter(|r| !r.cell(0).starts_with('#'))
        .collect();
    let Some(header) = rows.first() else { return Err(err(None, ImportErrorKind::Empty)) };

    let spec: Vec<String> = match &opts.columns {
        Some(c) => c.clone(),
        None => DEFAULT_COLUMNS.iter().map(|s| s.to_string()).collect(),
    };
    if spec.len() != 1 + 2 * MARKS {
        let msg = format!(
            "--columns: give 9 columns (the frame or time:NAME, then x1,y1,..,x4,y4), got {}",
            spec.len()
        );
        return Err(err(None, ImportErrorKind::BadOption(msg)));
    }
    let (time_spec, frame_spec) = match spec[0].strip_prefix("time:") {
        Some(name) => (true, name.to_string()),
        None => (false, spec[0].clone()),
    };
    let find = |s: &str| -> Result<usize, ImportError> {
        if let Ok(n) = s.parse::<usize>()
            && n >= 1
            && n <= header.cells.len()
        {
            return Ok(n - 1);
        }
        table::column(header, s).ok_or_else(|| {
            let hint = if opts.columns.is_none() { " (name them with --columns)" } else { "" };
            err(
                Some(header.line),
                ImportErrorKind::MissingColumn {
                    name: format!("{s}{hint}"),
                    available: table::listed(header),
                },
            )
        })
    };
    let frame_col = find(&frame_spec)?;
    let mut cols = [0usize; 2 * MARKS];
    for (k, s) in spec[1..].iter().enumerate() {
        cols[k] = find(s)?;
    }

    let unit = opts.unit.unwrap_or(LengthUnit::Px);
    let mut out = PointTracks::new(Some(unit), Some(unit), opts.y_up);
    for k in 0..MARKS {
        out.track_mut(&format!("mark {}", k + 1));
    }
    // (frame or time, marks, line)
    let mut parsed: Vec<(f64, [Option<[f64; 2]>; MARKS], usize)> = Vec::new();
    for row in &rows[1..] {
        let at = |k| err(Some(row.line), k);
        let key = if time_spec {
            table::number(&frame_spec, row.cell(frame_col)).map_err(at)?.ok_or_else(|| {
                at(ImportErrorKind::NotNumeric { what: frame_spec.clone(), value: String::new() })
            })?
        } else {
            table::frame(row.cell(frame_col)).map_err(at)? as f64
        };
        let mut marks = [None; MARKS];
        for (k, m) in marks.iter_mut().enumerate() {
            *m = table::point(
                &format!("mark {}", k + 1),
                row.cell(cols[2 * k]),
                row.cell(cols[2 * k + 1]),
            )
            .map_err(at)?;
        }
        parsed.push((key, marks, row.line));
    }
    let (fps, t0) = if time_spec {
        let times: Vec<f64> = parsed.iter().map(|p| p.0).collect();
        let fps = opts
            .fps
            .or_else(|| fps_from_times(&times))
            .ok_or(err(None, ImportErrorKind::MissingFps))?;
        (fps, times.iter().copied().fold(f64::INFINITY, f64::min))
    } else {
        (1.0, 0.0)
    };
    if time_spec {
        out.fps = Some(fps);
    }
    let mut first_line = std::collections::HashMap::new();
    for (key, marks, line) in parsed {
        let frames = (key - t0) * fps;
        let frame = frames.round();
        if (frames - frame).abs() > 0.25 {
            return Err(err(Some(line), ImportErrorKind::OffGrid { t: key, fps, frames }));
        }
        let frame = frame as i64;
        if let Some(first) = first_line.insert(frame, line) {
            return Err(err(
                Some(line),
                ImportErrorKind::DuplicatePoint { name: "frame".into(), frame, first_line: first },
            ));
        }
        for (k, m) in marks.iter().enumerate() {
            match m {
                Some(p) => {
                    out.tracks[k].points.insert(frame, *p);
                }
                None => out.blank += 1,
            }
        }
    }
    Ok(out)
}
