//! A film of a simulated ring as a lab films one, and its truth: what `ringlab render --view
//! film` plans before drawing. The camera looks straight down, orthographic, at a known scale;
//! the marks are discs centred where the recording format puts a mark
//! (`render::mark_discs`), so the truth is the format's mark points through that camera.
//! Frame `n` is the model at time `(first + n) / fps` from the start, drawn at that instant:
//! no motion blur, so the frame's time is its mid-exposure.

use super::ExportError;
use crate::config::Case;
use crate::physics::{Body, Conversion, RunOptions, Sample, Shape, Simulation, Units};
use crate::recording::marks::{MarkGeometry, MarkOrder, mark_radius};
use crate::recording::{Camera, FrameMarks, Header, MARKS, Recording};

/// What the marks look like: the tracker's styles (`film::MarkStyle`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilmMarks {
    /// Red, green, blue, yellow: marks 1 to 4.
    Colours,
    /// Four identical dark dots.
    Dark,
    /// Four identical bright dots.
    Bright,
}

impl FilmMarks {
    pub fn name(self) -> &'static str {
        match self {
            FilmMarks::Colours => "colours",
            FilmMarks::Dark => "dark",
            FilmMarks::Bright => "bright",
        }
    }

    /// Paint of marks 1 to 4 (linear RGB, multiplied by [`FILM_METAL`]).
    pub fn paint(self) -> [[f32; 3]; MARKS] {
        match self {
            FilmMarks::Colours => {
                [[1.25, 0.02, 0.02], [0.02, 0.9, 0.04], [0.03, 0.1, 1.3], [1.2, 1.05, 0.02]]
            }
            FilmMarks::Dark => [[0.02; 3]; MARKS],
            FilmMarks::Bright => [[1.4; 3]; MARKS],
        }
    }
}

/// Linear RGB of the film's ring: pale steel.
pub const FILM_METAL: [f32; 3] = [0.72, 0.73, 0.75];
/// Share of the picture's width and height left round the ring's reach when the scale is
/// chosen.
const MARGIN: f64 = 0.04;

/// What film to make.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilmSpec {
    /// The first and last time (the case's unit): the frames of the grid `k / fps` between.
    pub from: f64,
    pub to: f64,
    /// Frames per second of the camera.
    pub fps: f64,
    pub size: [u32; 2],
    /// None: the largest scale, to 3 significant digits, that keeps the ring in the picture.
    pub px_per_mm: Option<f64>,
    pub marks: FilmMarks,
    pub mark_diameter_mm: f64,
    /// Drawn at this many times the size, then averaged down (anti-aliasing).
    pub supersample: u32,
}

impl FilmSpec {
    /// What is wrong with the numbers, named as the command line names them.
    pub fn check(&self, body_mm: &Body) -> Result<(), String> {
        super::check_span(self.from, self.to)?;
        if !(self.fps.is_finite() && self.fps > 0.0 && self.fps <= 1e5) {
            return Err(format!("--fps = {}: must be above 0 and at most 100000", self.fps));
        }
        if let Some(k) = self.px_per_mm
            && !(k.is_finite() && k > 0.0)
        {
            return Err(format!("--px-per-mm = {k}: must be a positive number"));
        }
        // Discs wider than the gap between two marks would overlap.
        let widest = mark_radius(body_mm) * std::f64::consts::SQRT_2;
        if !(self.mark_diameter_mm > 0.0 && self.mark_diameter_mm < widest) {
            return Err(format!(
                "--mark-mm = {}: must be above 0 and below {widest:.2} mm (the marks would overlap)",
                self.mark_diameter_mm
            ));
        }
        if !(1..=8).contains(&self.supersample) {
            return Err(format!("--supersample = {}: must be 1 to 8", self.supersample));
        }
        Ok(())
    }
}

/// A film ready to draw: the model at each frame, the camera, and the truth.
#[derive(Clone, Debug)]
pub struct FilmPlan {
    pub spec: FilmSpec,
    /// The model at each frame (the case's units).
    pub samples: Vec<Sample>,
    /// The body in the case's units.
    pub body: Body,
    /// The case's unit of length in mm.
    pub length_mm: f64,
    /// The camera in mm (the truth's).
    pub camera: Camera,
    /// The point of the table under the picture's centre (mm).
    pub centre_mm: [f64; 2],
    /// The marks' true centres (empty where a disc is not wholly in the picture).
    pub truth: Recording,
}

impl FilmPlan {
    /// Pixels per unit of the case's length.
    pub fn px_per_unit(&self) -> f64 {
        self.camera.px_per_mm * self.length_mm
    }
}

/// Runs `case` and plans the film `spec` asks for.
pub fn plan_film(case: &Case, spec: &FilmSpec) -> Result<FilmPlan, ExportError> {
    let to_mm = Conversion::between(case.units, Units::MM_S);
    let body = case.model.body.clone();
    let body_mm =
        Body::new(body.shape, body.r * to_mm.length, body.h * to_mm.length, body.w * to_mm.length)
            .map_err(|e| ExportError::Invalid(e.to_string()))?;
    spec.check(&body_mm).map_err(ExportError::Invalid)?;
    let (first, samples) = frames(case, spec, to_mm.time)?;
    // The ring reaches no farther from A than this, in any pose.
    let reach = body_mm.r.hypot(body_mm.h);
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for s in &samples {
        for (k, v) in [s.x_a, s.y_a].into_iter().enumerate() {
            lo[k] = lo[k].min(v * to_mm.length - reach);
            hi[k] = hi[k].max(v * to_mm.length + reach);
        }
    }
    let [w, h] = spec.size.map(f64::from);
    let px_per_mm = match spec.px_per_mm {
        Some(k) => k,
        None => {
            let fit = ((1.0 - 2.0 * MARGIN) * w / (hi[0] - lo[0]))
                .min((1.0 - 2.0 * MARGIN) * h / (hi[1] - lo[1]));
            round_down(fit)
        }
    };
    let centre_mm = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    // Pixel x is the centre of column x: the picture's middle is at (w - 1) / 2.
    let origin_px =
        [0.5 * (w - 1.0) - px_per_mm * centre_mm[0], 0.5 * (h - 1.0) + px_per_mm * centre_mm[1]];
    let camera = Camera { origin_px, ..Camera::centred(px_per_mm, w, h) };
    let truth = truth(case, spec, &body_mm, &samples, to_mm.length, &camera, first);
    Ok(FilmPlan { spec: *spec, samples, body, length_mm: to_mm.length, camera, centre_mm, truth })
}

/// `x` rounded down to 3 significant digits.
fn round_down(x: f64) -> f64 {
    let p = 10f64.powf(x.log10().floor() - 2.0);
    (x / p).floor() * p
}

/// The model on the frame grid between `spec.from` and `spec.to`: the first frame's number
/// and the samples.
fn frames(case: &Case, spec: &FilmSpec, time_s: f64) -> Result<(u64, Vec<Sample>), ExportError> {
    let dt = 1.0 / spec.fps / time_s;
    let opts = RunOptions { sample_dt: Some(dt), ..case.opts.clone() };
    let mut sim = Simulation::new(case.model.clone(), &case.initial, opts)
        .map_err(|e| ExportError::Invalid(format!("the model cannot run: {e}")))?;
    let mut samples = Vec::new();
    let mut first = None;
    sim.advance(spec.to + dt, &mut |s| {
        let k = (s.t / dt).round();
        // The run's end point is off the grid.
        let on_grid = (s.t / dt - k).abs() < 1e-6;
        if on_grid && s.t >= spec.from - 1e-9 * dt && s.t <= spec.to + 1e-9 * dt {
            first.get_or_insert(k as u64);
            samples.push(*s);
        }
    });
    match first {
        Some(first) if !samples.is_empty() => Ok((first, samples)),
        _ => Err(ExportError::Invalid(format!(
            "no frame between --from {} and --to {}: the run ends at {:.6}",
            spec.from,
            spec.to,
            sim.t()
        ))),
    }
}

/// The truth: each mark through `camera`, or empty where its disc is not wholly in the picture.
fn truth(
    case: &Case,
    spec: &FilmSpec,
    body_mm: &Body,
    samples: &[Sample],
    length_mm: f64,
    camera: &Camera,
    first: u64,
) -> Recording {
    let geometry = MarkGeometry::of_body(body_mm, MarkOrder::Forward);
    let [w, h] = spec.size.map(f64::from);
    let edge = 0.5 * spec.mark_diameter_mm * camera.px_per_mm + 1.0;
    let inside = |p: [f64; 2]| {
        p[0] >= edge - 0.5 && p[0] <= w - 0.5 - edge && p[1] >= edge - 0.5 && p[1] <= h - 0.5 - edge
    };
    let frames = samples
        .iter()
        .map(|s| {
            let a = [s.x_a * length_mm, s.y_a * length_mm];
            let marks = geometry.marks(a, s.phi(), s.theta(), s.psi());
            let out: FrameMarks =
                marks.map(|m| Some(camera.to_px(m[0], m[1])).filter(|&p| inside(p)));
            out
        })
        .collect();
    let extra = [
        ("generator", format!("ringlab {} render --view film", env!("CARGO_PKG_VERSION"))),
        ("case", case.name.clone()),
        ("film_marks", spec.marks.name().to_string()),
        ("film_mark_diameter_mm", format!("{:?}", spec.mark_diameter_mm)),
        ("film_camera", "orthographic, straight down".to_string()),
        ("film_exposure", "instant: frame n is the model at n / fps".to_string()),
    ];
    let header = Header {
        fps: spec.fps,
        px_per_mm: camera.px_per_mm,
        shape: body_mm.shape,
        outer_radius_mm: nm(body_mm.r),
        width_mm: nm(body_mm.h),
        thickness_mm: (body_mm.shape == Shape::Ring).then_some(nm(body_mm.w)),
        image_width_px: Some(w),
        image_height_px: Some(h),
        camera_distance_mm: None,
        camera_tilt_deg: None,
        extra: extra.into_iter().map(|(k, v)| (k.to_string(), v)).collect(),
    };
    Recording { header, first_frame: first, frames }
}

/// Millimetres to the nanometre: a unit conversion's last bits are not information.
fn nm(v: f64) -> f64 {
    (v * 1e6).round() / 1e6
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> FilmSpec {
        FilmSpec {
            from: 1.0,
            to: 1.1,
            fps: 300.0,
            size: [320, 256],
            px_per_mm: None,
            marks: FilmMarks::Colours,
            mark_diameter_mm: 2.0,
            supersample: 1,
        }
    }

    #[test]
    fn the_plan_keeps_the_ring_in_the_picture_and_numbers_frames_from_the_start() {
        let case = crate::config::load_preset("steel-ring").unwrap().build().unwrap();
        let plan = plan_film(&case, &spec()).unwrap();
        // 1.0 s to 1.1 s at 300 frames/s: frames 300 to 330.
        assert_eq!(plan.truth.first_frame, 300);
        assert_eq!(plan.truth.frames.len(), 31);
        assert!((plan.samples[0].t - 1.0).abs() < 1e-9);
        assert!(plan.truth.frames.iter().all(|f| f.iter().all(|m| m.is_some())));
        let k = plan.camera.px_per_mm;
        assert_eq!(k, round_down(k));
        // A's centroid of the marks lies at A through the camera.
        let s = &plan.samples[5];
        let a = plan.camera.to_px(s.x_a * plan.length_mm, s.y_a * plan.length_mm);
        let f = plan.truth.frames[5].map(|m| m.unwrap());
        let mean = [0, 1].map(|j| f.iter().map(|m| m[j]).sum::<f64>() / 4.0);
        assert!((mean[0] - a[0]).abs() < 1e-9 && (mean[1] - a[1]).abs() < 1e-9);
    }

    #[test]
    fn bad_numbers_are_named() {
        let case = crate::config::load_preset("steel-ring").unwrap().build().unwrap();
        for (s, needle) in [
            (FilmSpec { to: 0.5, ..spec() }, "--to"),
            (FilmSpec { fps: 0.0, ..spec() }, "--fps"),
            (FilmSpec { px_per_mm: Some(-1.0), ..spec() }, "--px-per-mm"),
            (FilmSpec { mark_diameter_mm: 40.0, ..spec() }, "--mark-mm"),
            (FilmSpec { supersample: 9, ..spec() }, "--supersample"),
            (FilmSpec { from: 100.0, to: 101.0, ..spec() }, "no frame"),
        ] {
            let e = plan_film(&case, &s).unwrap_err().to_string();
            assert!(e.contains(needle), "{e}");
        }
    }
}
