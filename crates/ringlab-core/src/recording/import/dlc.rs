//! DeepLabCut's CSV: header rows `scorer`, `individuals` (multi-animal files only),
//! `bodyparts`, `coords`; per point the columns `x, y, likelihood`; the first column the frame
//! index; pixels, y down; blank cells where nothing was found.

use super::points::PointTracks;
use super::table::{self, Row};
use super::unit::LengthUnit;
use super::{ImportError, ImportErrorKind};
use std::path::Path;

const FORMAT: &str = "DeepLabCut CSV";

pub fn read(path: &Path, bytes: &[u8], min_likelihood: f64) -> Result<PointTracks, ImportError> {
    let err = |line, kind| ImportError::new(path, line, kind);
    if !(0.0..=1.0).contains(&min_likelihood) {
        let msg = format!("--min-likelihood = {min_likelihood}: must lie between 0 and 1");
        return Err(err(None, ImportErrorKind::BadOption(msg)));
    }
    let rows = table::rows(path, bytes, b',')?;
    let not_dlc = |row: Option<&Row>, what: String| {
        err(row.map(|r| r.line), ImportErrorKind::NotThisFormat { format: FORMAT, what })
    };
    // The header rows, found by their first cell.
    let mut header: Vec<&Row> = Vec::new();
    for row in rows.iter().take(4) {
        match row.cell(0).to_ascii_lowercase().as_str() {
            "scorer" | "individuals" | "bodyparts" | "coords" => header.push(row),
            _ => break,
        }
    }
    let find = |key: &str| header.iter().find(|r| r.cell(0).eq_ignore_ascii_case(key)).copied();
    let (Some(scorer), Some(parts), Some(coords)) =
        (find("scorer"), find("bodyparts"), find("coords"))
    else {
        return Err(not_dlc(
            rows.first(),
            "the header rows 'scorer', 'bodyparts' and 'coords' are needed".into(),
        ));
    };
    let individuals = find("individuals");
    if scorer.line != rows[0].line {
        return Err(not_dlc(Some(scorer), "'scorer' must be the first row".into()));
    }
    // Columns in threes: x, y, likelihood of one point.
    let width = coords.cells.len();
    let mut points: Vec<(String, [usize; 3])> = Vec::new();
    let mut c = 1;
    while c < width {
        let names: Vec<&str> = (0..3).map(|k| coords.cell(c + k)).collect();
        if names != ["x", "y", "likelihood"] {
            let what = format!(
                "columns {} to {} of 'coords' are '{}', expected 'x, y, likelihood'",
                c + 1,
                c + 3,
                names.join(", ")
            );
            return Err(not_dlc(Some(coords), what));
        }
        let part = parts.cell(c);
        if part.is_empty() || (1..3).any(|k| parts.cell(c + k) != part) {
            return Err(not_dlc(
                Some(parts),
                format!("column {}: the bodypart name must head its x, y and likelihood", c + 1),
            ));
        }
        let name = match individuals.map(|r| r.cell(c)) {
            Some(ind) if !ind.is_empty() => format!("{ind}/{part}"),
            _ => part.to_string(),
        };
        points.push((name, [c, c + 1, c + 2]));
        c += 3;
    }
    if points.is_empty() {
        return Err(not_dlc(Some(coords), "no x, y, likelihood columns".into()));
    }
    // One individual: call the points by bodypart alone.
    let single = individuals.is_none_or(|r| r.cells[1..].iter().all(|c| c == r.cell(1)));
    if single {
        for (name, _) in &mut points {
            if let Some((_, part)) = name.split_once('/') {
                *name = part.to_string();
            }
        }
    }

    let mut out = PointTracks::new(Some(LengthUnit::Px), Some(LengthUnit::Px), false);
    for (name, _) in &points {
        out.track_mut(name);
    }
    let mut seen = std::collections::HashMap::new();
    let last_header = header.iter().map(|r| r.line).max().unwrap_or(0);
    for row in rows.iter().filter(|r| r.line > last_header) {
        if row.cells.len() != width {
            let what = format!("{} cells, the header has {width}", row.cells.len());
            return Err(err(Some(row.line), ImportErrorKind::Csv(what)));
        }
        let frame = table::frame(row.cell(0)).map_err(|k| err(Some(row.line), k))?;
        if let Some(first) = seen.insert(frame, row.line) {
            let kind =
                ImportErrorKind::DuplicatePoint { name: "frame".into(), frame, first_line: first };
            return Err(err(Some(row.line), kind));
        }
        for (k, (name, cols)) in points.iter().enumerate() {
            let at = |e| err(Some(row.line), e);
            let p = table::point(name, row.cell(cols[0]), row.cell(cols[1])).map_err(at)?;
            let likelihood =
                table::number(&format!("{name} likelihood"), row.cell(cols[2])).map_err(at)?;
            match (p, likelihood) {
                (None, _) => out.blank += 1,
                (Some(_), Some(l)) if l < min_likelihood => out.low_likelihood += 1,
                (Some(p), _) => {
                    out.tracks[k].points.insert(frame, p);
                }
            }
        }
    }
    if out.low_likelihood > 0 {
        out.notes.push(format!(
            "{} points below likelihood {min_likelihood} dropped as missing marks",
            out.low_likelihood
        ));
    }
    Ok(out)
}
