//! `ringlab.Recording`'s Rust half: a recording read from any file `ringlab import` reads, or
//! made from a numpy array of the marks through the same assembly as a tracker's file (the
//! four marks' cyclic order checked, the frames framed, the header written).

use crate::errors::{RecordingError, import_error};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use ringlab_core::config::load_preset;
use ringlab_core::physics::Shape;
use ringlab_core::recording::import::{
    BodyMm, Format, ImportError, ImportErrorKind, ImportOptions, LengthUnit, PointTracks, Source,
    import, import_bytes, points::assemble,
};
use ringlab_core::recording::read::MAX_TILT_DEG;
use ringlab_core::recording::{MARKS, Recording, write_recording, write_recording_exact};
use serde::Serialize;
use std::io::Write;
use std::path::PathBuf;

/// A recording held by Python (the `ringlab.Recording` object wraps one).
#[pyclass(frozen, module = "ringlab._core", name = "Recording")]
pub struct PyRecording {
    pub rec: Recording,
    /// What it is called in messages: the file, or "arrays".
    pub name: String,
    pub source: &'static str,
    /// The names taken as marks 1 to 4, and what the import said.
    pub marks: Vec<String>,
    pub notes: Vec<String>,
}

/// The header and what the import said, as `Recording`'s Python properties read them.
#[derive(Serialize)]
struct HeaderJson<'a> {
    name: &'a str,
    source: &'static str,
    fps: f64,
    px_per_mm: f64,
    shape: &'static str,
    outer_radius_mm: f64,
    width_mm: f64,
    thickness_mm: Option<f64>,
    image_width_px: Option<f64>,
    image_height_px: Option<f64>,
    camera_distance_mm: Option<f64>,
    camera_tilt_deg: Option<f64>,
    extra: &'a [(String, String)],
    first_frame: u64,
    frames: usize,
    marks_tracked: usize,
    mark_names: &'a [String],
    notes: &'a [String],
}

/// The body from `body='preset'` or its dimensions (`None`: not given).
pub fn body_mm(
    preset: Option<String>,
    shape: Option<String>,
    outer_radius_mm: Option<f64>,
    width_mm: Option<f64>,
    thickness_mm: Option<f64>,
) -> PyResult<Option<BodyMm>> {
    let bad = |m: String| PyValueError::new_err(format!("body: {m}"));
    if let Some(name) = preset {
        let file = load_preset(&name).map_err(|e| bad(e.to_string()))?;
        return BodyMm::of_case(&file).map(Some).map_err(bad);
    }
    if shape.is_none() && outer_radius_mm.is_none() && width_mm.is_none() && thickness_mm.is_none()
    {
        return Ok(None);
    }
    let shape = shape.ok_or_else(|| bad("needs 'shape': 'ring' or 'disk'".into()))?;
    let shape =
        Shape::parse(&shape).ok_or_else(|| bad(format!("shape '{shape}': not ring or disk")))?;
    let r = outer_radius_mm.ok_or_else(|| bad("needs 'outer_radius_mm'".into()))?;
    let h = width_mm.ok_or_else(|| bad("needs 'width_mm'".into()))?;
    if shape == Shape::Ring && thickness_mm.is_none() {
        return Err(bad("a ring needs 'thickness_mm' (its wall)".into()));
    }
    Ok(Some(BodyMm { shape, outer_radius_mm: r, width_mm: h, thickness_mm }))
}

fn positive(v: Option<f64>, name: &str) -> PyResult<Option<f64>> {
    match v {
        Some(x) if !(x.is_finite() && x > 0.0) => {
            Err(PyValueError::new_err(format!("{name} = {x}: must be a positive number")))
        }
        v => Ok(v),
    }
}

/// A camera the header may name: a distance > 0 (mm), a tilt within the format's range.
fn check_camera(distance_mm: Option<f64>, tilt_deg: Option<f64>) -> PyResult<()> {
    positive(distance_mm, "camera_distance_mm")?;
    if let Some(t) = tilt_deg
        && !(t.abs() < MAX_TILT_DEG)
    {
        return Err(PyValueError::new_err(format!(
            "camera_tilt_deg = {t}: must lie between -{MAX_TILT_DEG} and {MAX_TILT_DEG} (exclusive)"
        )));
    }
    Ok(())
}

/// An error of a table written as CSV, at its table's row rather than the CSV's line (the
/// rows after the header's; the header's are the column names, no line of the HDF5 file).
fn table_row(mut e: ImportError, header_rows: usize) -> ImportError {
    if let Some(line) = e.line.take() {
        let at = match line.checked_sub(header_rows + 1) {
            Some(row) => format!("row {row} of its table"),
            None => "its table's columns".to_string(),
        };
        e.path = PathBuf::from(format!("{} ({at})", e.path.display()));
    }
    e
}

impl PyRecording {
    pub fn new(rec: Recording, name: String, source: &'static str) -> PyRecording {
        PyRecording { rec, name, source, marks: Vec::new(), notes: Vec::new() }
    }
}

#[pymethods]
impl PyRecording {
    /// Reads a recording: format v1, or a tracker's file(s) as `ringlab import` reads them.
    /// `table`: DeepLabCut's table read from `paths[0]` (an HDF5 file) by pandas, written as
    /// its CSV (`table_header_rows` rows of column names): read by the core's DeepLabCut
    /// reader as the CSV would be, with the HDF5 file named.
    #[staticmethod]
    #[pyo3(signature = (paths, format=None, fps=None, px_per_mm=None, marks=None, min_likelihood=None, body_preset=None, shape=None, outer_radius_mm=None, width_mm=None, thickness_mm=None, columns=None, unit=None, y_up=false, table=None, table_header_rows=0))]
    #[allow(clippy::too_many_arguments)]
    fn read(
        paths: Vec<PathBuf>,
        format: Option<String>,
        fps: Option<f64>,
        px_per_mm: Option<f64>,
        marks: Option<Vec<String>>,
        min_likelihood: Option<f64>,
        body_preset: Option<String>,
        shape: Option<String>,
        outer_radius_mm: Option<f64>,
        width_mm: Option<f64>,
        thickness_mm: Option<f64>,
        columns: Option<Vec<String>>,
        unit: Option<String>,
        y_up: bool,
        table: Option<&[u8]>,
        table_header_rows: usize,
    ) -> PyResult<PyRecording> {
        let from = format
            .as_deref()
            .map(|f| {
                Format::parse(f).ok_or_else(|| {
                    PyValueError::new_err(format!("format '{f}': not one of {}", Format::NAMES))
                })
            })
            .transpose()?;
        let defaults = ImportOptions::default();
        let min_likelihood = min_likelihood.unwrap_or(defaults.min_likelihood);
        if !(0.0..=1.0).contains(&min_likelihood) {
            return Err(PyValueError::new_err(format!(
                "min_likelihood = {min_likelihood}: must lie in [0, 1]"
            )));
        }
        let opts = ImportOptions {
            fps: positive(fps, "fps")?,
            px_per_mm: positive(px_per_mm, "px_per_mm")?,
            marks,
            min_likelihood,
            body: body_mm(body_preset, shape, outer_radius_mm, width_mm, thickness_mm)?,
            columns,
            unit: unit
                .as_deref()
                .map(|u| {
                    LengthUnit::parse(u).ok_or_else(|| {
                        PyValueError::new_err(format!(
                            "unit '{u}': not one of {}",
                            LengthUnit::NAMES
                        ))
                    })
                })
                .transpose()?,
            y_up,
        };
        let name = paths.first().map_or("-".into(), |p| p.display().to_string());
        let (imported, source) = match (table, paths.first()) {
            (Some(text), Some(path)) => {
                let files = [(path.clone(), text.to_vec())];
                let imported = import_bytes(&files, Some(Format::Dlc), &opts)
                    .map_err(|e| import_error(&table_row(e, table_header_rows)))?;
                (imported, "DeepLabCut HDF5")
            }
            _ => {
                let imported = import(&paths, from, &opts).map_err(|e| import_error(&e))?;
                let source = imported.report.source.name();
                (imported, source)
            }
        };
        let report = imported.report;
        Ok(PyRecording {
            rec: imported.recording,
            name,
            source,
            marks: report.marks,
            notes: report.notes,
        })
    }

    /// A recording from the marks' pixel positions: `marks` the bytes of a C-ordered float64
    /// array of shape (frames, 4, 2), NaN for a mark not found.
    #[staticmethod]
    #[pyo3(signature = (marks, frames, fps, px_per_mm, body_preset=None, shape=None, outer_radius_mm=None, width_mm=None, thickness_mm=None, first_frame=0, image_size=None, camera_distance_mm=None, camera_tilt_deg=None))]
    #[allow(clippy::too_many_arguments)]
    fn from_arrays(
        marks: &[u8],
        frames: usize,
        fps: f64,
        px_per_mm: f64,
        body_preset: Option<String>,
        shape: Option<String>,
        outer_radius_mm: Option<f64>,
        width_mm: Option<f64>,
        thickness_mm: Option<f64>,
        first_frame: i64,
        image_size: Option<(f64, f64)>,
        camera_distance_mm: Option<f64>,
        camera_tilt_deg: Option<f64>,
    ) -> PyResult<PyRecording> {
        let values = frames
            .checked_mul(MARKS * 2 * 8)
            .filter(|&n| n == marks.len())
            .map(|_| marks.len() / 8)
            .ok_or_else(|| {
                PyValueError::new_err(format!(
                    "marks: {} bytes are not {frames} frames x 4 marks x 2 float64",
                    marks.len()
                ))
            })?;
        let xs: Vec<f64> = marks
            .chunks_exact(8)
            .map(|b| f64::from_ne_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]))
            .collect();
        debug_assert_eq!(xs.len(), values);
        let body = body_mm(body_preset, shape, outer_radius_mm, width_mm, thickness_mm)?
            .ok_or_else(|| PyValueError::new_err("body: give a preset's name or the dimensions"))?;
        let (w, h) = match image_size {
            Some((w, h)) => (Some(w), Some(h)),
            None => (None, None),
        };
        positive(w, "image width")?;
        positive(h, "image height")?;
        check_camera(camera_distance_mm, camera_tilt_deg)?;
        // Frame numbers are i64 in the import; far below their end.
        if !(0..=i64::from(u32::MAX)).contains(&first_frame) {
            return Err(PyValueError::new_err(format!(
                "first_frame = {first_frame}: must lie in [0, {}]",
                u32::MAX
            )));
        }

        // The four marks as a tracker's named points (pixels, y down): `assemble` then does
        // what it does for every tracker's file.
        let mut tracks = PointTracks::new(Some(LengthUnit::Px), Some(LengthUnit::Px), false);
        for k in 0..MARKS {
            tracks.track_mut(&(k + 1).to_string());
        }
        for i in 0..frames {
            for k in 0..MARKS {
                let (x, y) = (xs[(i * MARKS + k) * 2], xs[(i * MARKS + k) * 2 + 1]);
                let at = format!("marks[{i}, {k}]");
                match (x.is_nan(), y.is_nan()) {
                    (true, true) => continue,
                    (false, false) => {}
                    _ => {
                        return Err(RecordingError::new_err(format!(
                            "{at} = ({x}, {y}): x and y are both NaN (mark not found) or neither"
                        )));
                    }
                }
                if !(x.is_finite() && y.is_finite()) {
                    return Err(RecordingError::new_err(format!(
                        "{at} = ({x}, {y}) is not finite (NaN, not inf, marks a mark not found)"
                    )));
                }
                tracks.tracks[k].points.insert(first_frame + i as i64, [x, y]);
            }
        }
        let opts = ImportOptions {
            fps: positive(Some(fps), "fps")?,
            px_per_mm: positive(Some(px_per_mm), "px_per_mm")?,
            body: Some(body),
            ..ImportOptions::default()
        };
        let imported = assemble(tracks, Source::Plain, &[], &opts).map_err(|e| match &e.kind {
            // The CLI's advice names --marks; an array's marks are reordered by index.
            ImportErrorKind::NotCyclic { order, bad, frames, suggestion } => {
                let idx: Vec<String> = suggestion
                    .split(',')
                    .map(|n| n.parse::<usize>().map_or("?".into(), |n| n.saturating_sub(1).to_string()))
                    .collect();
                RecordingError::new_err(format!(
                    "marks {order} are not in cyclic order around the rim in {bad} of {frames} frames with all four (the diagonals do not cross); reorder them, e.g. marks[:, [{}]]",
                    idx.join(", ")
                ))
            }
            kind => RecordingError::new_err(format!("marks: {kind}")),
        })?;
        let mut rec = imported.recording;
        // Not a file: the header says no source; the image and camera as given.
        rec.header.extra.clear();
        rec.header.image_width_px = w;
        rec.header.image_height_px = h;
        rec.header.camera_distance_mm = camera_distance_mm;
        rec.header.camera_tilt_deg = camera_tilt_deg;
        Ok(PyRecording {
            rec,
            name: "arrays".into(),
            source: "numpy arrays",
            marks: vec!["1".into(), "2".into(), "3".into(), "4".into()],
            notes: imported.report.notes,
        })
    }

    /// The header and the import's notes as JSON (the Python properties read it).
    fn header_json(&self) -> PyResult<String> {
        let h = &self.rec.header;
        let j = HeaderJson {
            name: &self.name,
            source: self.source,
            fps: h.fps,
            px_per_mm: h.px_per_mm,
            shape: h.shape.name(),
            outer_radius_mm: h.outer_radius_mm,
            width_mm: h.width_mm,
            thickness_mm: h.thickness_mm,
            image_width_px: h.image_width_px,
            image_height_px: h.image_height_px,
            camera_distance_mm: h.camera_distance_mm,
            camera_tilt_deg: h.camera_tilt_deg,
            extra: &h.extra,
            first_frame: self.rec.first_frame,
            frames: self.rec.frames.len(),
            marks_tracked: self.rec.mark_count(),
            mark_names: &self.marks,
            notes: &self.notes,
        };
        serde_json::to_string(&j).map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// The marks as the bytes of a float64 array (frames, 4, 2), NaN where not tracked.
    fn marks_bytes<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        let mut out = Vec::with_capacity(self.rec.frames.len() * MARKS * 2 * 8);
        for f in &self.rec.frames {
            for m in f {
                let [x, y] = m.unwrap_or([f64::NAN; 2]);
                out.extend_from_slice(&x.to_ne_bytes());
                out.extend_from_slice(&y.to_ne_bytes());
            }
        }
        PyBytes::new(py, &out)
    }

    /// Writes it as format v1 (`exact`: pixel coordinates that read back bit for bit).
    fn write(&self, path: PathBuf, exact: bool) -> PyResult<()> {
        let mut text = Vec::new();
        let written = if exact {
            write_recording_exact(&mut text, &self.rec)
        } else {
            write_recording(&mut text, &self.rec)
        };
        written
            .and_then(|_| std::fs::File::create(&path)?.write_all(&text))
            .map_err(|e| RecordingError::new_err(format!("cannot write {}: {e}", path.display())))
    }

    /// Same header numbers, frames and marks (what the header says beyond the format's keys,
    /// such as where an import came from, is not compared).
    fn same_as(&self, other: &PyRecording) -> bool {
        let (a, b) = (&self.rec, &other.rec);
        let mut ha = a.header.clone();
        ha.extra.clear();
        let mut hb = b.header.clone();
        hb.extra.clear();
        ha == hb && a.first_frame == b.first_frame && a.frames == b.frames
    }
}
