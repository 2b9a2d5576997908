//! What the window draws, as numpy arrays: the fit's predicted marks and its residuals frame
//! by frame; the diagnosis's residual series, test windows and trace. Each array crosses to
//! Python as (name, shape, the bytes of a C-ordered float64 array); `ringlab/_results.py`
//! turns them into numpy arrays on the result objects.

use pyo3::prelude::*;
use pyo3::types::PyBytes;
use ringlab_core::analysis::diagnose::Diagnosis;
use ringlab_core::analysis::fit::FitResult;
use ringlab_core::recording::glitches::without_glitches;
use ringlab_core::recording::{MARKS, Recording};

/// Named float64 arrays: (name, shape, bytes).
pub type Arrays<'py> = Vec<(&'static str, Vec<usize>, Bound<'py, PyBytes>)>;

/// Collects [`Arrays`], checking each array's length against its shape.
struct Builder<'py> {
    py: Python<'py>,
    out: Arrays<'py>,
}

impl<'py> Builder<'py> {
    fn new(py: Python<'py>) -> Self {
        Builder { py, out: Vec::new() }
    }

    fn add(&mut self, name: &'static str, shape: &[usize], values: &[f64]) {
        debug_assert_eq!(shape.iter().product::<usize>(), values.len(), "{name}");
        let mut bytes = Vec::with_capacity(values.len() * 8);
        for v in values {
            bytes.extend_from_slice(&v.to_ne_bytes());
        }
        self.out.push((name, shape.to_vec(), PyBytes::new(self.py, &bytes)));
    }

    /// Pairs (x, y or start, end) as an (n, 2) array.
    fn pairs(&mut self, name: &'static str, pairs: impl Iterator<Item = [f64; 2]>) {
        let flat: Vec<f64> = pairs.flatten().collect();
        self.add(name, &[flat.len() / 2, 2], &flat);
    }
}

/// The fit's model over the recording: `predicted_marks` (frames, 4, 2), each mark's distance
/// from its tracked position `mark_residual_px` (frames, 4) and the RMS over each frame's
/// coordinates `residual_px` (frames), NaN where the model gives no marks (outside the fitted
/// segments) or the mark was not tracked or was left out as a glitch: the coordinates the
/// fit's `rms_px` is taken over, and no others.
pub fn fit_arrays<'py>(py: Python<'py>, fit: &FitResult, rec: &Recording) -> Arrays<'py> {
    let observed = without_glitches(&rec.frames, &fit.glitches);
    let predicted = fit.predicted_marks(&observed);
    let n = observed.len();
    let (mut marks, mut per_mark, mut per_frame) =
        (Vec::with_capacity(n * MARKS * 2), Vec::with_capacity(n * MARKS), Vec::with_capacity(n));
    for (obs, pred) in observed.iter().zip(&predicted) {
        let (mut sum, mut count) = (0.0, 0usize);
        for (k, o) in obs.iter().enumerate() {
            let p = pred.map(|p| p[k]);
            marks.extend(p.unwrap_or([f64::NAN; 2]));
            per_mark.push(match (o, p) {
                (Some(o), Some(p)) => {
                    let d2 = (p[0] - o[0]).powi(2) + (p[1] - o[1]).powi(2);
                    sum += d2;
                    count += 2;
                    d2.sqrt()
                }
                _ => f64::NAN,
            });
        }
        per_frame.push(if count > 0 { (sum / count as f64).sqrt() } else { f64::NAN });
    }
    let mut b = Builder::new(py);
    b.add("predicted_marks", &[n, MARKS, 2], &marks);
    b.add("mark_residual_px", &[n, MARKS], &per_mark);
    b.add("residual_px", &[n], &per_frame);
    b.out
}

/// The diagnosis's series as its plots show them: the fitted frames (indices into the
/// recording) and their times, the residual per frame before, after and of the baseline fitted
/// to the stretch it follows, the test windows, and point A's trace.
pub fn diagnosis_arrays<'py>(py: Python<'py>, d: &Diagnosis) -> Arrays<'py> {
    let r = &d.residuals;
    let t = &d.trace;
    let n = r.t_s.len();
    // The series start at the span's first frame: its time is (first_frame + start) / fps.
    let start = r.t_s.first().map_or(0.0, |t0| (t0 * d.fps).round() - d.first_frame as f64);
    let fitted: Vec<f64> = (0..n).map(|i| start + i as f64).collect();
    let mut b = Builder::new(py);
    b.add("fitted_frames", &[n], &fitted);
    b.add("time_s", &[n], &r.t_s);
    b.add("residual_before_px", &[r.before_px.len()], &r.before_px);
    b.add("residual_after_px", &[r.after_px.len()], &r.after_px);
    b.add("residual_followed_px", &[r.followed_px.len()], &r.followed_px);
    b.pairs("window_s", r.window_s.iter().map(|&(a, e)| [a, e]));
    b.add("window_before_px", &[r.window_before_px.len()], &r.window_before_px);
    b.add("window_after_px", &[r.window_after_px.len()], &r.window_after_px);
    b.add("window_followed_px", &[r.window_followed_px.len()], &r.window_followed_px);
    b.add("window_threshold_px", &[r.window_threshold_px.len()], &r.window_threshold_px);
    b.pairs("trace_data_px", t.data_px.iter().map(|p| p.unwrap_or([f64::NAN; 2])));
    b.pairs("trace_before_px", t.before_px.iter().copied());
    b.pairs("trace_after_px", t.after_px.iter().copied());
    b.add("image_px", &[2], &t.image_px);
    b.out
}
