//! Open Source Physics Tracker's exported data tables, one file per point mass: line 1 its
//! name, line 2 the column headings (tab by default, comma possible), then rows `t, x, y` in
//! calibrated units with y up and the origin anywhere. The unit is not in the file. Frames are
//! counted from the earliest time in any of the files.

use super::points::PointTracks;
use super::table;
use super::{ImportError, ImportErrorKind, ImportOptions};
use std::path::{Path, PathBuf};

const FORMAT: &str = "Tracker data table";

pub fn read(
    files: &[(PathBuf, Vec<u8>)],
    opts: &ImportOptions,
) -> Result<PointTracks, ImportError> {
    let mut out = PointTracks::new(None, None, true);
    // (track, time, position, file, line) for every row, framed once the rate is known.
    let mut rows: Vec<(usize, f64, Option<[f64; 2]>, usize, usize)> = Vec::new();
    for (f, (path, bytes)) in files.iter().enumerate() {
        let (name, found) = read_one(path, bytes)?;
        if out.tracks.iter().any(|t| t.name == name) {
            let msg = format!("two files hold the point mass '{name}'");
            return Err(ImportError::new(path, Some(1), ImportErrorKind::BadOption(msg)));
        }
        out.track_mut(&name);
        let track = out.tracks.len() - 1;
        rows.extend(found.into_iter().map(|(t, p, line)| (track, t, p, f, line)));
    }
    let times: Vec<f64> = rows.iter().map(|r| r.1).collect();
    let t0 = times.iter().copied().fold(f64::INFINITY, f64::min);
    let fps = match opts.fps {
        Some(fps) => fps,
        None => {
            let fps = fps_from_times(&times)
                .ok_or_else(|| ImportError::new(&files[0].0, None, ImportErrorKind::MissingFps))?;
            out.notes
                .push(format!("frame rate {fps:.6} frames/s from the times (--fps to set it)"));
            fps
        }
    };
    out.fps = Some(fps);
    let mut first_line = std::collections::HashMap::new();
    for (track, t, p, f, line) in rows {
        let path = &files[f].0;
        let frames = (t - t0) * fps;
        let frame = frames.round();
        if (frames - frame).abs() > 0.25 {
            return Err(ImportError::new(
                path,
                Some(line),
                ImportErrorKind::OffGrid { t, fps, frames },
            ));
        }
        let frame = frame as i64;
        if let Some(first) = first_line.insert((track, frame), line) {
            let kind = ImportErrorKind::DuplicatePoint {
                name: out.tracks[track].name.clone(),
                frame,
                first_line: first,
            };
            return Err(ImportError::new(path, Some(line), kind));
        }
        match p {
            Some(p) => {
                out.tracks[track].points.insert(frame, p);
            }
            None => out.blank += 1,
        }
    }
    Ok(out)
}

/// The point mass's name and its rows `(t, position, line)`.
fn read_one(
    path: &Path,
    bytes: &[u8],
) -> Result<(String, Vec<(f64, Option<[f64; 2]>, usize)>), ImportError> {
    let err = |line, kind| ImportError::new(path, line, kind);
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]).into_owned();
    let second = text.lines().nth(1).unwrap_or("");
    let rows = table::rows(path, bytes, table::delimiter_of(second))?;
    let not_table = |line, what: &str| {
        err(line, ImportErrorKind::NotThisFormat { format: FORMAT, what: what.into() })
    };
    let Some(name_row) = rows.first() else { return Err(err(None, ImportErrorKind::Empty)) };
    let name = name_row.cells.join(" ").trim().to_string();
    if name.is_empty() || name_row.line != 1 {
        return Err(not_table(Some(1), "line 1 must name the point mass"));
    }
    let Some(headings) = rows.get(1) else {
        return Err(not_table(None, "no column headings on line 2"));
    };
    let col = |h: &str| {
        table::column(headings, h).ok_or_else(|| {
            err(
                Some(headings.line),
                ImportErrorKind::MissingColumn {
                    name: h.into(),
                    available: table::listed(headings),
                },
            )
        })
    };
    let (ct, cx, cy) = (col("t")?, col("x")?, col("y")?);
    let mut out = Vec::with_capacity(rows.len());
    for row in &rows[2..] {
        let at = |k| err(Some(row.line), k);
        let Some(t) = table::number("t", row.cell(ct)).map_err(at)? else {
            return Err(at(ImportErrorKind::NotNumeric { what: "t".into(), value: String::new() }));
        };
        let p = table::point(&name, row.cell(cx), row.cell(cy)).map_err(at)?;
        out.push((t, p, row.line));
    }
    Ok((name, out))
}

/// Frames per second from times on a frame grid, perhaps with gaps and rounded in export:
/// a first step from the usual short step, refined by least squares over a window that
/// doubles while the frame count stays unambiguous.
pub fn fps_from_times(times: &[f64]) -> Option<f64> {
    let mut t: Vec<f64> = times.iter().copied().filter(|t| t.is_finite()).collect();
    t.sort_by(f64::total_cmp);
    t.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * (1.0 + a.abs()));
    let mut steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    let min = steps.iter().copied().fold(f64::INFINITY, f64::min);
    steps.retain(|s| *s < 1.5 * min);
    if steps.is_empty() || !(min > 0.0) {
        return None;
    }
    steps.sort_by(f64::total_cmp);
    let mut dt = steps[steps.len() / 2];
    let t0 = t[0];
    let mut window = 16.0 * dt;
    loop {
        let (mut sn2, mut snt) = (0.0, 0.0);
        for &ti in t.iter().take_while(|&&ti| ti - t0 <= window) {
            let n = ((ti - t0) / dt).round();
            sn2 += n * n;
            snt += n * (ti - t0);
        }
        if sn2 > 0.0 {
            dt = snt / sn2;
        }
        if window >= t[t.len() - 1] - t0 {
            break;
        }
        window *= 2.0;
    }
    (dt > 0.0 && dt.is_finite()).then(|| 1.0 / dt)
}
