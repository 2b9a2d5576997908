//! Fiji TrackMate's spots table: a row of keys (`TRACK_ID`, `FRAME`, `POSITION_X`,
//! `POSITION_Y`, in any order), up to three more header rows (names, short names, units), then
//! one row per spot in any order. Image coordinates: y down; the unit from the units row.

use super::points::PointTracks;
use super::table::{self, Row};
use super::unit::LengthUnit;
use super::{ImportError, ImportErrorKind};
use std::collections::HashMap;
use std::path::Path;

const FORMAT: &str = "TrackMate spots CSV";
const KEYS: [&str; 4] = ["TRACK_ID", "FRAME", "POSITION_X", "POSITION_Y"];

pub fn read(path: &Path, bytes: &[u8]) -> Result<PointTracks, ImportError> {
    let err = |line, kind| ImportError::new(path, line, kind);
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]).into_owned();
    let delimiter = table::delimiter_of(text.lines().next().unwrap_or(""));
    let rows = table::rows(path, bytes, delimiter)?;
    let Some(keys) = rows.first() else { return Err(err(None, ImportErrorKind::Empty)) };
    let mut col = [0usize; 4];
    for (k, key) in KEYS.iter().enumerate() {
        col[k] = keys.cells.iter().position(|c| c == key).ok_or_else(|| {
            err(
                Some(keys.line),
                ImportErrorKind::MissingColumn {
                    name: key.to_string(),
                    available: table::listed(keys),
                },
            )
        })?;
    }
    let t_col = keys.cells.iter().position(|c| c == "POSITION_T");
    // Header rows end at the first row whose FRAME is a number.
    let data_start = rows
        .iter()
        .skip(1)
        .position(|r| table::frame(r.cell(col[1])).is_ok())
        .map_or(rows.len(), |i| i + 1);
    if data_start > 4 {
        let what = format!(
            "{} header rows before the first spot (at most 4: keys, names, short names, units)",
            data_start
        );
        return Err(err(
            Some(rows[data_start.min(rows.len() - 1)].line),
            ImportErrorKind::NotThisFormat { format: FORMAT, what },
        ));
    }
    let units_row: Option<&Row> =
        rows[1..data_start].iter().find(|r| r.cell(col[2]).starts_with('('));
    let unit = match units_row {
        Some(r) => {
            let u = r.cell(col[2]);
            Some(LengthUnit::parse(u).ok_or_else(|| {
                err(
                    Some(r.line),
                    ImportErrorKind::MissingUnit(format!(
                        "POSITION_X's unit {u} is not one of {}",
                        LengthUnit::NAMES
                    )),
                )
            })?)
        }
        None => None,
    };
    let t_unit = units_row
        .zip(t_col)
        .map(|(r, c)| r.cell(c).trim_matches(|c| c == '(' || c == ')').to_ascii_lowercase());

    let mut out = PointTracks::new(unit, Some(LengthUnit::Px), false);
    if unit.is_none() {
        out.notes.push("no units row: positions taken as pixels (--unit to say otherwise)".into());
    }
    let mut ids: Vec<(String, i64)> = Vec::new();
    let mut spots: Vec<(String, i64, [f64; 2], usize)> = Vec::new();
    let mut untracked = 0usize;
    let mut times: Vec<(i64, f64)> = Vec::new();
    for row in &rows[data_start..] {
        let at = |k| err(Some(row.line), k);
        let id = row.cell(col[0]);
        let frame = table::frame(row.cell(col[1])).map_err(at)?;
        let Some(p) = table::point("spot", row.cell(col[2]), row.cell(col[3])).map_err(at)? else {
            return Err(at(ImportErrorKind::HalfPoint {
                what: "a spot without a position".into(),
            }));
        };
        if id.is_empty() || id.eq_ignore_ascii_case("none") {
            untracked += 1;
            continue;
        }
        let order = table::frame(id).map_err(|_| {
            at(ImportErrorKind::NotNumeric { what: "TRACK_ID".into(), value: table::clip(id) })
        })?;
        if !ids.iter().any(|(n, _)| n == id) {
            ids.push((id.to_string(), order));
        }
        if let Some(t) = t_col.and_then(|c| table::number("POSITION_T", row.cell(c)).ok().flatten())
        {
            times.push((frame, t));
        }
        spots.push((id.to_string(), frame, p, row.line));
    }
    // Tracks in the order of their ids, so that the default marks are tracks 0 to 3.
    ids.sort_by_key(|(_, n)| *n);
    for (id, _) in &ids {
        out.track_mut(id);
    }
    let mut first_line: HashMap<(String, i64), usize> = HashMap::new();
    for (id, frame, p, line) in spots {
        if let Some(first) = first_line.insert((id.clone(), frame), line) {
            return Err(err(
                Some(line),
                ImportErrorKind::DuplicatePoint {
                    name: format!("track {id}"),
                    frame,
                    first_line: first,
                },
            ));
        }
        out.track_mut(&id).points.insert(frame, p);
    }
    if untracked > 0 {
        out.notes.push(format!("{untracked} spots belong to no track (TRACK_ID None): left out"));
    }
    out.fps = fps_from_times(&times, t_unit.as_deref());
    Ok(out)
}

/// Frames per second from the spots' `POSITION_T` when it is in seconds.
fn fps_from_times(times: &[(i64, f64)], unit: Option<&str>) -> Option<f64> {
    let per_s = match unit? {
        "sec" | "s" | "second" | "seconds" => 1.0,
        "ms" => 1e3,
        _ => return None,
    };
    let (f0, t0) = *times.iter().min_by_key(|(f, _)| *f)?;
    let (f1, t1) = *times.iter().max_by_key(|(f, _)| *f)?;
    let fps = (f1 - f0) as f64 / (t1 - t0) * per_s;
    (f1 > f0 && fps.is_finite() && fps > 0.0).then_some(fps)
}
