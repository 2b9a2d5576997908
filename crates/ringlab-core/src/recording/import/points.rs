//! Named points per frame, as a tracker gives them, made into a format v1 recording.

use super::unit::LengthUnit;
use super::{ImportError, ImportErrorKind, ImportOptions, ImportReport, Imported, Source};
use crate::recording::{FrameMarks, Header, MARKS, Recording, is_usable};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One tracked point: frame number to position, in the file's unit and y direction.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointTrack {
    pub name: String,
    pub points: BTreeMap<i64, [f64; 2]>,
}

/// Everything a reader found in its file(s).
#[derive(Clone, Debug, PartialEq)]
pub struct PointTracks {
    /// In the file's order.
    pub tracks: Vec<PointTrack>,
    /// The unit the file says its positions are in (`None`: it does not say).
    pub unit: Option<LengthUnit>,
    /// The unit the format implies when the file is silent (`None`: the user must say).
    pub unit_default: Option<LengthUnit>,
    /// Positions' y grows upward (calibrated coordinates).
    pub y_up: bool,
    /// The frame rate the file gives.
    pub fps: Option<f64>,
    /// The file's calibration, for pixel positions.
    pub px_per_mm: Option<f64>,
    pub low_likelihood: usize,
    pub blank: usize,
    pub notes: Vec<String>,
}

impl PointTracks {
    pub fn new(
        unit: Option<LengthUnit>,
        unit_default: Option<LengthUnit>,
        y_up: bool,
    ) -> PointTracks {
        PointTracks {
            tracks: Vec::new(),
            unit,
            unit_default,
            y_up,
            fps: None,
            px_per_mm: None,
            low_likelihood: 0,
            blank: 0,
            notes: Vec::new(),
        }
    }

    /// The track of this name, made when new.
    pub fn track_mut(&mut self, name: &str) -> &mut PointTrack {
        match self.tracks.iter().position(|t| t.name == name) {
            Some(i) => &mut self.tracks[i],
            None => {
                self.tracks.push(PointTrack { name: name.to_string(), points: BTreeMap::new() });
                self.tracks.last_mut().expect("just pushed")
            }
        }
    }
}

/// Scale used when calibrated positions come without `--px-per-mm`: the recording's pixels
/// are then 0.1 mm, not the camera's.
pub const DEFAULT_PX_PER_MM: f64 = 10.0;
/// Room left around the marks when positions are moved into the image (px).
const MARGIN_PX: f64 = 50.0;
/// More frames than this between the first and the last is a wrong frame column.
const MAX_FRAMES: i64 = 20_000_000;

/// The four marks picked, converted to pixels (y down) and framed as format v1.
pub fn assemble(
    t: PointTracks,
    source: Source,
    files: &[PathBuf],
    opts: &ImportOptions,
) -> Result<Imported, ImportError> {
    let path = files.first().map_or(Path::new("-"), |p| p.as_path());
    let err = |kind| ImportError::new(path, None, kind);
    let mut notes = t.notes.clone();
    let picked = pick_marks(&t, opts, &mut notes).map_err(err)?;

    let fps = opts.fps.or(t.fps).ok_or(err(ImportErrorKind::MissingFps))?;
    if !(fps.is_finite() && fps > 0.0) {
        return Err(err(ImportErrorKind::BadOption(format!(
            "--fps = {fps}: must be a positive number"
        ))));
    }
    let unit = match (t.unit, opts.unit) {
        (Some(f), Some(g)) if f != g => {
            return Err(err(ImportErrorKind::UnitConflict {
                file: f.name().into(),
                given: g.name().into(),
            }));
        }
        (Some(f), _) => f,
        (None, Some(g)) => g,
        (None, None) => t.unit_default.ok_or_else(|| {
            err(ImportErrorKind::MissingUnit(format!(
                "the file does not say its length unit: give --unit {}",
                LengthUnit::NAMES
            )))
        })?,
    };
    let (px_per_mm, px_per_unit) = match unit {
        LengthUnit::Px => {
            let s = opts.px_per_mm.or(t.px_per_mm).ok_or(err(ImportErrorKind::MissingScale))?;
            (s, 1.0)
        }
        LengthUnit::Length { mm, name } => {
            let s = opts.px_per_mm.unwrap_or_else(|| {
                notes.push(format!(
                    "positions are in {name}: written at {DEFAULT_PX_PER_MM} px per mm (no --px-per-mm given; the recording's pixels are not the camera's)"
                ));
                DEFAULT_PX_PER_MM
            });
            (s, mm * s)
        }
    };
    if !(px_per_mm.is_finite() && px_per_mm > 0.0) {
        return Err(err(ImportErrorKind::BadOption(format!(
            "px per mm = {px_per_mm}: must be a positive number"
        ))));
    }
    let body = opts.body.ok_or(err(ImportErrorKind::MissingBody))?;

    let marks: Vec<&PointTrack> = picked.iter().map(|&i| &t.tracks[i]).collect();
    let first = marks.iter().filter_map(|m| m.points.keys().next()).min().copied();
    let last = marks.iter().filter_map(|m| m.points.keys().next_back()).max().copied();
    let (Some(first), Some(last)) = (first, last) else {
        return Err(err(ImportErrorKind::TooFewUsableFrames { usable: 0 }));
    };
    if last - first > MAX_FRAMES {
        let msg = format!(
            "frames {first} to {last} span more than {MAX_FRAMES} frames: is the frame column right?"
        );
        return Err(err(ImportErrorKind::BadOption(msg)));
    }
    let sign_y = if t.y_up { -1.0 } else { 1.0 };
    let mut frames: Vec<FrameMarks> = (first..=last)
        .map(|n| {
            let mut f: FrameMarks = [None; MARKS];
            for (k, m) in marks.iter().enumerate() {
                f[k] = m.points.get(&n).map(|p| [p[0] * px_per_unit, sign_y * p[1] * px_per_unit]);
            }
            f
        })
        .collect();
    // Calibrated or y-up positions have their origin anywhere: move them into the image.
    let (lo_x, lo_y) = frames
        .iter()
        .flatten()
        .flatten()
        .fold((f64::INFINITY, f64::INFINITY), |(a, b), p| (a.min(p[0]), b.min(p[1])));
    if t.y_up || unit != LengthUnit::Px || lo_x < 0.0 || lo_y < 0.0 {
        for p in frames.iter_mut().flatten().flatten() {
            p[0] += MARGIN_PX - lo_x;
            p[1] += MARGIN_PX - lo_y;
        }
    }
    check_cyclic(&frames, &t, &picked).map_err(err)?;
    let usable = frames.iter().filter(|f| is_usable(f)).count();
    if usable < 2 {
        return Err(err(ImportErrorKind::TooFewUsableFrames { usable }));
    }
    let first_frame = if first < 0 {
        notes.push(format!("frames start at {first}: numbered from 0 in the recording"));
        0
    } else {
        first as u64
    };
    let names: Vec<String> = marks.iter().map(|m| m.name.clone()).collect();
    let clean =
        |s: &str| s.chars().map(|c| if c.is_control() { ' ' } else { c }).collect::<String>();
    let file_names: Vec<String> = files
        .iter()
        .map(|p| {
            clean(
                &p.file_name()
                    .map_or(p.display().to_string(), |n| n.to_string_lossy().into_owned()),
            )
        })
        .collect();
    let header = Header {
        fps,
        px_per_mm,
        shape: body.shape,
        outer_radius_mm: body.outer_radius_mm,
        width_mm: body.width_mm,
        thickness_mm: body.thickness_mm,
        image_width_px: None,
        image_height_px: None,
        camera_distance_mm: None,
        camera_tilt_deg: None,
        extra: vec![
            ("imported_from".into(), format!("{}: {}", source.name(), file_names.join(" "))),
            ("imported_marks".into(), clean(&names.join(" | "))),
        ],
    };
    header
        .body_mm()
        .map_err(|e| err(ImportErrorKind::BadOption(format!("the body is impossible: {e}"))))?;
    let report = ImportReport {
        source,
        files: files.to_vec(),
        marks: names,
        low_likelihood: t.low_likelihood,
        blank: t.blank,
        notes,
    };
    Ok(Imported { recording: Recording { header, first_frame, frames }, report })
}

/// Indices of the four tracks taken as marks 1 to 4.
fn pick_marks(
    t: &PointTracks,
    opts: &ImportOptions,
    notes: &mut Vec<String>,
) -> Result<Vec<usize>, ImportErrorKind> {
    let available = || t.tracks.iter().map(|t| t.name.as_str()).collect::<Vec<_>>().join(", ");
    match &opts.marks {
        Some(names) => {
            if names.len() != MARKS {
                return Err(ImportErrorKind::BadMarks(format!(
                    "give four names in cyclic order, got {}",
                    names.len()
                )));
            }
            let mut out = Vec::with_capacity(MARKS);
            for name in names {
                let i = t.tracks.iter().position(|t| &t.name == name).ok_or_else(|| {
                    ImportErrorKind::UnknownMark { name: name.clone(), available: available() }
                })?;
                if out.contains(&i) {
                    return Err(ImportErrorKind::BadMarks(format!("'{name}' is named twice")));
                }
                out.push(i);
            }
            Ok(out)
        }
        None => {
            if t.tracks.len() < MARKS {
                return Err(ImportErrorKind::TooFewPoints {
                    found: t.tracks.len(),
                    names: available(),
                });
            }
            if t.tracks.len() > MARKS {
                notes.push(format!(
                    "{} points in the file ({}): the first four taken as marks (--marks to choose)",
                    t.tracks.len(),
                    available()
                ));
            }
            Ok((0..MARKS).collect())
        }
    }
}

/// Marks in cyclic order make a quadrilateral whose diagonals 1-3 and 2-4 cross; in any other
/// order they do not. Judged on frames where the quadrilateral is not seen edge-on.
fn check_cyclic(
    frames: &[FrameMarks],
    t: &PointTracks,
    picked: &[usize],
) -> Result<(), ImportErrorKind> {
    const ORDERS: [[usize; 4]; 3] = [[0, 1, 2, 3], [0, 2, 1, 3], [0, 1, 3, 2]];
    let mut crossing = [0usize; 3];
    let mut judged = 0usize;
    for f in frames {
        let Some(p) = f.iter().copied().collect::<Option<Vec<[f64; 2]>>>() else { continue };
        let scale = (0..4)
            .flat_map(|i| (0..4).map(move |j| (i, j)))
            .map(|(i, j)| dist2(p[i], p[j]))
            .fold(0.0, f64::max);
        if scale <= 0.0 {
            continue;
        }
        let flat = ORDERS.iter().any(|o| {
            let d = |a: usize, b: usize, c: usize| orient(p[o[a]], p[o[b]], p[o[c]]).abs() / scale;
            d(0, 2, 1).min(d(0, 2, 3)).min(d(1, 3, 0)).min(d(1, 3, 2)) < 0.02
        });
        if flat {
            continue;
        }
        judged += 1;
        for (k, o) in ORDERS.iter().enumerate() {
            crossing[k] += diagonals_cross(p[o[0]], p[o[1]], p[o[2]], p[o[3]]) as usize;
        }
    }
    const MIN_JUDGED: usize = 10;
    if judged < MIN_JUDGED || 2 * crossing[0] >= judged {
        return Ok(());
    }
    let best = (0..3).max_by_key(|&k| crossing[k]).unwrap_or(0);
    let name = |k: usize| t.tracks[picked[k]].name.clone();
    Err(ImportErrorKind::NotCyclic {
        order: (0..4).map(name).collect::<Vec<_>>().join(","),
        bad: judged - crossing[0],
        frames: judged,
        suggestion: ORDERS[best].iter().map(|&k| name(k)).collect::<Vec<_>>().join(","),
    })
}

fn dist2(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
}

fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Whether segment 1-3 crosses segment 2-4.
fn diagonals_cross(p1: [f64; 2], p2: [f64; 2], p3: [f64; 2], p4: [f64; 2]) -> bool {
    orient(p1, p3, p2).signum() != orient(p1, p3, p4).signum()
        && orient(p2, p4, p1).signum() != orient(p2, p4, p3).signum()
}
