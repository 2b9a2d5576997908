//! What a diagnosis found: one plain struct with everything the report and a window show
//! (plain data, cloneable, no references into the recording).

use super::noise_correlation::NoiseCorrelation;
use crate::physics::effects::EffectKind;
use crate::physics::{Initial, Model, Units};
use crate::recording::Camera;
use crate::recording::glitches::Glitch;

/// A model fitted over the whole run from one start state (the diagnosis's misfit).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct ModelFit {
    /// The effect it includes (`None`: the baseline, the paper's model).
    pub effect: EffectKind,
    /// RMS of model minus recording over every tracked mark coordinate of the span (px).
    pub rms_px: f64,
    /// Sum of squared residuals (px^2), their number, and the free parameters.
    pub cost: f64,
    pub residual_count: usize,
    pub parameter_count: usize,
    /// BIC: `N ln(cost / N) + k ln N` (lower is better).
    pub score: f64,
    pub c: [f64; 3],
    pub c_sigma: [f64; 3],
    /// The effect's strength and its one-sigma uncertainty (infinite where unconstrained).
    pub strength: Option<(f64, f64)>,
    /// The effects' extra numbers as fitted, with their sigmas (a pinhole's tilt in degrees,
    /// the rim's share of `reynolds_drag`'s speed, ...: each effect's `Descriptor::extras`).
    pub extras: Vec<ExtraFit>,
    /// Two of `extras` by name, for the readers that name them: the camera's tilt (degrees)
    /// and the rim's share of the speed of `reynolds_drag`'s Reynolds number (0: the centre's
    /// speed, the paper's law), with their sigmas, where they were fitted.
    pub tilt_deg: Option<(f64, f64)>,
    pub rim_share: Option<(f64, f64)>,
    /// Effects fitted beside `effect` (a pair's first), with their strengths and sigmas.
    pub also: Vec<(EffectKind, (f64, f64))>,
    /// The body's outer radius and width as fitted (mm), with their sigmas.
    pub body_mm: [(f64, f64); 2],
    /// The start state at the first fitted frame and its time (s).
    pub start: Initial,
    pub start_s: f64,
    /// The fitted model (its effect switched on), camera and units: what a simulator can adopt.
    pub model: Model,
    pub camera: Camera,
    pub units: Units,
    /// When this model's motion ends (s), if within twice the recording's length.
    pub end_s: Option<f64>,
}

/// One extra number of an effect as fitted (`Descriptor::extras[index]` of `kind`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ExtraFit {
    pub kind: EffectKind,
    pub index: usize,
    /// Its value and one-sigma uncertainty.
    pub value: (f64, f64),
}

impl ExtraFit {
    /// Its key among a JSON report's fitted parameters, if it has one.
    pub fn json(&self) -> Option<&'static str> {
        self.kind.descriptor().extras[self.index].json
    }

    /// In the fit's words.
    pub fn name(&self) -> &'static str {
        self.kind.descriptor().extras[self.index].name
    }
}
/// A candidate's path ends where a stage fits this many times worse than the baseline's stage
/// with as many segments (`whole::fit_path`'s ceiling). A candidate nests the baseline, so on its
/// right path it never fits worse: on twenty concealed recordings the named effects' stages
/// stayed within 1.1 times the baseline's, while those of the paths that ended worse than the
/// baseline rose to 3 to 1,600 times it, and went on for seconds (to be refitted from the
/// baseline's solution in the end).
pub const STAGE_CEILING: f64 = 4.0;

/// The extra numbers of `kind` among `extras`, in its descriptor's order.
pub fn extras_of(extras: &[ExtraFit], kind: EffectKind) -> Vec<(f64, f64)> {
    extras.iter().filter(|x| x.kind == kind).map(|x| x.value).collect()
}

/// The two extras that some readers name ([`ModelFit::tilt_deg`], [`ModelFit::rim_share`]),
/// where fitted.
pub(super) struct NamedExtras {
    pub(super) tilt_deg: Option<(f64, f64)>,
    pub(super) rim_share: Option<(f64, f64)>,
}

/// The camera's tilt and the rim's share of the Reynolds drag's speed among `extras`.
pub(super) fn named_extras(extras: &[ExtraFit]) -> NamedExtras {
    NamedExtras {
        tilt_deg: extras_of(extras, EffectKind::CameraPerspective).first().copied(),
        rim_share: extras_of(extras, EffectKind::ReynoldsDrag).first().copied(),
    }
}

impl ModelFit {
    /// The fitted model's slip velocity at its first frame (mm/s, along the heading and across
    /// it), where it slides from there (`Effects::slip_start_velocity`).
    pub fn slip_start_mm_s(&self) -> Option<[f64; 2]> {
        let e = &self.model.effects;
        let k = self.units.length_mm / self.units.time_s;
        (e.slip_mu.is_some() && e.slip_start == crate::physics::SlipStart::Cone)
            .then(|| e.slip_start_velocity.map(|v| v * k))
    }

    /// Its effects in the order fitted, joined by " + " (`none` for the baseline).
    pub fn effects_label(&self) -> String {
        let names: Vec<&str> =
            self.also.iter().map(|(k, _)| k.name()).chain([self.effect.name()]).collect();
        names.join(" + ")
    }
}

/// One candidate of the ranking (`none` is the baseline).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Candidate {
    pub effect: EffectKind,
    pub rms_px: f64,
    pub score: f64,
    /// Score minus the baseline's (negative: better than the baseline).
    pub delta_score: f64,
    pub strength: Option<(f64, f64)>,
    /// Why the candidate could not be fitted, if it could not.
    pub error: Option<String>,
    /// Time its fit took (s; candidates run in parallel).
    pub seconds: f64,
    /// Its path over the whole run stopped at a stage of this many segments, where it fitted
    /// [`STAGE_CEILING`] times worse than the baseline (its misfit is that stage's model run
    /// over the whole span, and its strength has no uncertainty).
    pub stopped_at_segments: Option<usize>,
}

impl Candidate {
    /// Where its fit stopped and why, in words, if it stopped early.
    pub fn stopped_note(&self) -> Option<String> {
        self.stopped_at_segments
            .map(|n| format!("its fit over the whole run stopped at {n} segments, {STAGE_CEILING}x worse than the baseline there"))
    }
}

/// A pair of effects tried together after one was named (the forward selection).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PairCandidate {
    pub first: EffectKind,
    pub second: EffectKind,
    pub rms_px: f64,
    /// Score minus the baseline's.
    pub delta_score: f64,
    pub strengths: [(f64, f64); 2],
    pub error: Option<String>,
    pub seconds: f64,
}

/// A named effect's part in the named model's improvement on the baseline.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct NamedShare {
    pub effect: EffectKind,
    /// The share (0 to 1) of the cost the named model removes from the baseline's that comes
    /// back without this effect (1 for one effect named; for several the shares need not sum
    /// to 1: effects can stand in for part of each other).
    pub share: f64,
    /// The misfit without this effect: the best model fitted with the named model's other
    /// effects and not it (px rms; the baseline's for one effect).
    pub rms_without_px: f64,
}

/// A stretch of the recording where the baseline departs from the data beyond its noise.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MismatchWindow {
    pub start_s: f64,
    pub end_s: f64,
    /// The whole-run baseline's RMS residual inside it (px).
    pub rms_px: f64,
    /// Its share of the squared residual beyond the noise, after the departure, of the
    /// baseline fitted up to the departure.
    pub share: f64,
}

/// The residual against time, frame by frame and in test windows.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct ResidualSeries {
    /// Times of the fitted frames (s).
    pub t_s: Vec<f64>,
    /// Per-frame RMS over its tracked coordinates (px; NaN where none were tracked).
    pub before_px: Vec<f64>,
    pub after_px: Vec<f64>,
    /// The test windows: `[start, end)` in s, RMS before and after, and the threshold.
    pub window_s: Vec<(f64, f64)>,
    pub window_before_px: Vec<f64>,
    pub window_after_px: Vec<f64>,
    pub window_threshold_px: Vec<f64>,
    /// The baseline fitted only to the stretch it follows (up to the departure) and run on:
    /// per frame and per window (px).
    pub followed_px: Vec<f64>,
    pub window_followed_px: Vec<f64>,
}

/// Point A (the centroid of the marks) in image pixels, frame by frame over the fitted span.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Trace {
    pub t_s: Vec<f64>,
    /// From the recording, where all four marks were tracked.
    pub data_px: Vec<Option<[f64; 2]>>,
    pub before_px: Vec<[f64; 2]>,
    pub after_px: Vec<[f64; 2]>,
    /// The image's size (px), for plotting.
    pub image_px: [f64; 2],
}

/// Measured features of the mismatch that tell the effects apart.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Signature {
    /// Where the baseline, fitted to a growing stretch from the start, stops following the
    /// recording within its noise (s; none if it follows the whole run), and that stretch's
    /// share of the run.
    pub departure_s: Option<f64>,
    pub followed_share: f64,
    /// The baseline's RMS residual in the first, middle and last third of the span (px).
    pub thirds_rms_px: [f64; 3],
    /// Share of the baseline's squared residual beyond the noise that lies in the last third.
    pub late_share: f64,
    /// When the motion ends (s): in the recording (where it comes to rest within it), and in
    /// the baseline and improved models.
    pub end_data_s: Option<f64>,
    pub end_before_s: Option<f64>,
    pub end_after_s: Option<f64>,
    /// Share of the baseline's squared residual that points along the radius from the image
    /// centre (0.5 for no preference): a lens moves marks radially.
    pub radial_share: f64,
    /// Share of the change from the baseline's prediction to the improved one that is radial.
    pub change_radial_share: f64,
    /// Where the improved model's contact slides (s), when it can.
    pub slides_s: Vec<(f64, f64)>,
}

/// What a diagnosis concludes.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Finding {
    /// The baseline is consistent with the noise: nothing this recording can show is missing.
    Nothing,
    /// These effects were left out, in the order they were named (each earned its BIC and
    /// explained most of the misfit beyond the noise that was left).
    Named(Vec<EffectKind>),
    /// The baseline misses by more than the noise and no candidate explains most of it; the
    /// candidate that explains the largest share of the excess (over `before^2 - noise^2`),
    /// where one explains any.
    Unexplained { partial: Option<Partial> },
}

/// The candidate (one effect, or a pair) that explains the largest share of an unexplained
/// misfit beyond the noise, that share (of `before^2 - noise^2`) and the misfit it leaves.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Partial {
    pub effects: Vec<EffectKind>,
    pub share: f64,
    /// The model's misfit with these effects (px rms over the coordinates kept).
    pub rms_px: f64,
}

impl std::fmt::Display for Partial {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let names: Vec<&str> = self.effects.iter().map(|k| k.name()).collect();
        f.write_str(&names.join(" + "))
    }
}

impl Finding {
    /// `none`, `unexplained`, or the first effect named.
    pub fn name(&self) -> &'static str {
        match self {
            Finding::Nothing => "none",
            Finding::Unexplained { .. } => "unexplained",
            Finding::Named(k) => k.first().map_or("none", |k| k.name()),
        }
    }

    /// The effects named, in order (empty unless some were).
    pub fn named(&self) -> &[EffectKind] {
        match self {
            Finding::Named(k) => k,
            _ => &[],
        }
    }

    /// The first effect named, `EffectKind::None` otherwise.
    pub fn first(&self) -> EffectKind {
        self.named().first().copied().unwrap_or(EffectKind::None)
    }
}

/// Everything a diagnosis found.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Diagnosis {
    /// What the baseline left out: nothing, some effects, or something no candidate explains.
    pub finding: Finding,
    /// The mismatch: from where the baseline stops following the recording within its noise
    /// (fitted to the stretch before) to the last window where it departs; None if it never does.
    pub mismatch: Option<MismatchWindow>,
    /// The windows where that baseline departs beyond the noise (joined where close).
    pub windows: Vec<MismatchWindow>,
    /// The recording's pixel noise per coordinate, estimated from each mark's track alone
    /// (`recording::noise`; failing that, the baseline's multiple-shooting misfit:
    /// `noise_from_marks` false).
    pub noise_px: f64,
    pub noise_from_marks: bool,
    /// The tracker's noise correlated in time, where the baseline's residual shows it: then
    /// `noise_px` is the tracks' reading corrected for it (`noise_correlation`).
    pub noise_correlation: Option<NoiseCorrelation>,
    /// The tracker's glitches left out of every fit (`recording::glitches`).
    pub glitches: Vec<Glitch>,
    /// The baseline and the chosen model on the same misfit (the same unless effects were named).
    pub before: ModelFit,
    pub after: ModelFit,
    /// Every candidate and the baseline, best score first.
    pub candidates: Vec<Candidate>,
    /// The pairs tried after an effect was named (best score first; empty when none were).
    pub pairs: Vec<PairCandidate>,
    /// Each named effect's share of the improvement, in the order of `after`'s effects (empty
    /// unless effects were named).
    #[serde(default)]
    pub shares: Vec<NamedShare>,
    /// The BIC drop an effect needed to be named.
    pub evidence: f64,
    /// The body's outer radius and width as the recording's header gives them (mm).
    pub header_body_mm: [f64; 2],
    pub residuals: ResidualSeries,
    pub trace: Trace,
    pub signature: Signature,
    /// In plain words: what was left out, how the mismatch points to it, the parameter.
    pub explanation: String,
    /// The baseline's multiple-shooting misfit (segments re-anchored; px) and its segments.
    pub segments_rms_px: f64,
    pub segments: usize,
    pub frames: usize,
    /// The frame number (as in the file) of the first frame; `glitches` index from it.
    pub first_frame: u64,
    pub frames_fitted: usize,
    pub fps: f64,
    /// Wall-clock time of each stage (s): the multiple-shooting fit, the baseline's path with
    /// the departure beside it, the candidates, the rest. (Not carried from a web page's
    /// worker: the names are the diagnosis's own strings.)
    #[serde(skip)]
    pub stage_seconds: Vec<(&'static str, f64)>,
    pub compute_seconds: f64,
}

impl Diagnosis {
    /// The part of a misfit beyond this recording's noise (px): `sqrt(max(rms^2 - noise^2, 0))`.
    pub fn excess_px(&self, rms_px: f64) -> f64 {
        super::rules::excess_px(rms_px, self.noise_px)
    }
}
