//! The JSON objects of `ringlab diagnose --json` and `ringlab fit --json`, field for field: the
//! CLI prints them and the Python package's results are them (`to_dict()`), so a script that
//! parses the CLI's output and a notebook read the same names and numbers from one definition.

use crate::analysis::diagnose::{CONSISTENT_RATIO, Diagnosis, Finding};
use crate::analysis::fit::FitResult;
use crate::physics::SlipStart;
use crate::recording::glitches::GlitchKind;
use serde::Serialize;
use std::collections::BTreeMap;

/// The JSON object of `ringlab diagnose --json`.
#[derive(Serialize, Debug)]
pub struct DiagnoseJson {
    /// `none`, `unexplained`, or the first effect named.
    pub left_out: &'static str,
    /// Every effect named, in order (empty for `none` and `unexplained`).
    pub left_out_all: Vec<&'static str>,
    /// For `unexplained`: the candidate that explains the largest share of the excess.
    pub partial: Option<PartialJson>,
    /// Tracked mark positions left out as the tracker's glitches.
    pub glitches: usize,
    /// Each of them: the frame number (as in the file), the mark (1 to 4) and what it was.
    pub glitch_marks: Vec<GlitchJson>,
    /// The baseline is `none` only within this many times the noise.
    pub consistent_ratio: f64,
    pub mismatch: Option<WindowJson>,
    pub before: FitJson,
    pub after: FitJson,
    pub candidates: Vec<CandidateJson>,
    /// The pairs of the forward selection, best first (empty when none were tried).
    pub pairs: Vec<PairJson>,
    /// Each named effect's share of the improvement on the baseline (empty unless named).
    pub shares: Vec<ShareJson>,
    pub explanation: String,
    pub compute_seconds: f64,
    pub noise_px: f64,
    /// Where the tracker's noise is correlated in time (the baseline's residual shows it and
    /// nothing else): what the tracks read, the correlation, and `noise_px` corrected for it.
    pub noise_correlation: Option<NoiseCorrelationJson>,
    pub windows: Vec<WindowJson>,
    pub frames: usize,
    pub frames_fitted: usize,
    pub segments_rms_px: f64,
}

#[derive(Serialize, Debug)]
pub struct NoiseCorrelationJson {
    /// The tracks' own reading (px), before the correction.
    pub tracks_px: f64,
    /// The correlation from one frame to the next, and the lag (frames) where it has died out.
    pub lag1: f64,
    pub range_frames: usize,
    /// The baseline's RMS that the corrected level agreed with (px).
    pub residual_px: f64,
}

#[derive(Serialize, Debug)]
pub struct GlitchJson {
    pub frame: u64,
    pub mark: usize,
    /// `outlier` (off its own track) or `swapped` (a label exchanged with another mark's).
    pub kind: &'static str,
}

#[derive(Serialize, Debug)]
pub struct PairJson {
    pub names: [&'static str; 2],
    pub rms_px: Option<f64>,
    pub delta_score: Option<f64>,
    pub strengths: [Option<f64>; 2],
    pub error: Option<String>,
}

/// A named effect's share: the part of the cost the named model removes that comes back
/// without it, and the misfit without it (px rms).
#[derive(Serialize, Debug)]
pub struct ShareJson {
    pub name: &'static str,
    pub share: Option<f64>,
    pub rms_without_px: Option<f64>,
}

#[derive(Serialize, Debug)]
pub struct PartialJson {
    /// One effect, or a pair.
    pub names: Vec<&'static str>,
    /// Share of the baseline's squared misfit beyond the noise that it removes.
    pub explained_share: f64,
    /// Its misfit, and the part of it beyond the noise (px).
    pub rms_px: f64,
    pub excess_px: f64,
}

#[derive(Serialize, Debug)]
pub struct WindowJson {
    pub start_s: f64,
    pub end_s: f64,
    pub rms_px: f64,
    pub share: f64,
}

#[derive(Serialize, Debug)]
pub struct FitJson {
    pub rms_px: f64,
    /// `sqrt(max(rms^2 - noise^2, 0))`: the misfit beyond the noise.
    pub excess_px: f64,
    pub score: f64,
    pub effect: &'static str,
    /// `C1..C3`, their sigmas, and the effect's strength with its sigma, by name.
    pub params: BTreeMap<String, Option<f64>>,
    pub end_s: Option<f64>,
    /// With slip: how its run begins, `cone` (sliding at once where the start needs more
    /// friction than `mu F_N`) or `held_rolling` (rolling until it first needs no more).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slip_start: Option<&'static str>,
}

#[derive(Serialize, Debug)]
pub struct CandidateJson {
    pub name: &'static str,
    pub rms_px: Option<f64>,
    pub score: Option<f64>,
    pub delta_score: Option<f64>,
    pub strength: Option<f64>,
    pub strength_sigma: Option<f64>,
    pub error: Option<String>,
    /// Where its whole-run path stopped (the segments of that stage), if it did.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stopped_at_segments: Option<usize>,
}

fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

impl FitJson {
    /// A model fitted by the diagnosis `d`: its misfit, BIC and numbers by name.
    fn of(f: &crate::analysis::diagnose::ModelFit, d: &Diagnosis) -> FitJson {
        let mut params = BTreeMap::new();
        for i in 0..3 {
            params.insert(format!("C{}", i + 1), finite(f.c[i]));
            params.insert(format!("C{}_sigma", i + 1), finite(f.c_sigma[i]));
        }
        for (i, name) in ["R_mm", "h_mm"].iter().enumerate() {
            params.insert(name.to_string(), finite(f.body_mm[i].0));
            params.insert(format!("{name}_sigma"), finite(f.body_mm[i].1));
        }
        if let Some((v, s)) = f.strength {
            params.insert(f.effect.name().to_string(), finite(v));
            params.insert(format!("{}_sigma", f.effect.name()), finite(s));
        }
        // Each effect's extra numbers under the keys its file gives them (a pinhole's
        // camera_tilt_deg, reynolds_rim_share, table_slope_direction_deg, ...).
        for x in &f.extras {
            if let Some(key) = x.json() {
                params.insert(key.into(), finite(x.value.0));
                params.insert(format!("{key}_sigma"), finite(x.value.1));
            }
        }
        if let Some([along, across]) = f.slip_start_mm_s() {
            params.insert("slip_start_along_mm_s".into(), finite(along));
            params.insert("slip_start_across_mm_s".into(), finite(across));
        }
        FitJson {
            rms_px: f.rms_px,
            excess_px: d.excess_px(f.rms_px),
            score: f.score,
            effect: f.effect.name(),
            params,
            end_s: f.end_s,
            slip_start: f.model.effects.slip_mu.map(|_| match f.model.effects.slip_start {
                SlipStart::Cone => "cone",
                SlipStart::HeldRolling => "held_rolling",
            }),
        }
    }
}

impl DiagnoseJson {
    pub fn new(d: &Diagnosis) -> DiagnoseJson {
        let window = |w: &crate::analysis::diagnose::MismatchWindow| WindowJson {
            start_s: w.start_s,
            end_s: w.end_s,
            rms_px: w.rms_px,
            share: w.share,
        };
        DiagnoseJson {
            left_out: d.finding.name(),
            left_out_all: d.finding.named().iter().map(|k| k.name()).collect(),
            partial: match &d.finding {
                Finding::Unexplained { partial: Some(p) } => Some(PartialJson {
                    names: p.effects.iter().map(|k| k.name()).collect(),
                    explained_share: p.share,
                    rms_px: p.rms_px,
                    excess_px: d.excess_px(p.rms_px),
                }),
                _ => None,
            },
            glitches: d.glitches.len(),
            glitch_marks: d
                .glitches
                .iter()
                .map(|g| GlitchJson {
                    frame: d.first_frame + g.frame as u64,
                    mark: g.mark + 1,
                    kind: match g.kind {
                        GlitchKind::Outlier => "outlier",
                        GlitchKind::Swapped => "swapped",
                    },
                })
                .collect(),
            consistent_ratio: CONSISTENT_RATIO,
            mismatch: d.mismatch.as_ref().map(window),
            before: FitJson::of(&d.before, d),
            after: FitJson::of(&d.after, d),
            candidates: d
                .candidates
                .iter()
                .map(|c| CandidateJson {
                    name: c.effect.name(),
                    rms_px: finite(c.rms_px),
                    score: finite(c.score),
                    delta_score: finite(c.delta_score),
                    strength: c.strength.and_then(|s| finite(s.0)),
                    strength_sigma: c.strength.and_then(|s| finite(s.1)),
                    error: c.error.clone(),
                    stopped_at_segments: c.stopped_at_segments,
                })
                .collect(),
            pairs: d
                .pairs
                .iter()
                .map(|p| PairJson {
                    names: [p.first.name(), p.second.name()],
                    rms_px: finite(p.rms_px),
                    delta_score: finite(p.delta_score),
                    strengths: p.strengths.map(|s| finite(s.0)),
                    error: p.error.clone(),
                })
                .collect(),
            shares: d
                .shares
                .iter()
                .map(|s| ShareJson {
                    name: s.effect.name(),
                    share: finite(s.share),
                    rms_without_px: finite(s.rms_without_px),
                })
                .collect(),
            explanation: d.explanation.clone(),
            compute_seconds: d.compute_seconds,
            noise_px: d.noise_px,
            noise_correlation: d.noise_correlation.as_ref().map(|c| NoiseCorrelationJson {
                tracks_px: c.tracks_px,
                lag1: c.rho.get(1).copied().unwrap_or(0.0),
                range_frames: c.range_frames,
                residual_px: c.residual_px,
            }),
            windows: d.windows.iter().map(window).collect(),
            frames: d.frames,
            frames_fitted: d.frames_fitted,
            segments_rms_px: d.segments_rms_px,
        }
    }
}

/// The JSON object of `ringlab fit --json`.
#[derive(Serialize, Debug)]
pub struct FitReport {
    pub c: [f64; 3],
    pub c_sigma: [Option<f64>; 3],
    pub theta0: f64,
    pub phidot0: f64,
    pub psidot0: f64,
    pub thetadot0: f64,
    pub phi0: f64,
    pub rms_px: f64,
    pub frames: usize,
    pub compute_seconds: f64,
    pub frames_fitted: usize,
    pub noise_px: Option<f64>,
    pub start_frame: f64,
    pub start_time_s: f64,
    pub time_unit_s: f64,
    pub length_unit_mm: f64,
    pub segments: usize,
    pub segment_frames: usize,
    pub iterations: usize,
    pub residuals: usize,
    pub parameters: usize,
    pub coarse_c: Option<[f64; 3]>,
    pub effect: Option<EffectReport>,
}

#[derive(Serialize, Debug)]
pub struct EffectReport {
    pub name: &'static str,
    pub strength: f64,
    pub sigma: Option<f64>,
}

fn wrap_angle(x: f64) -> f64 {
    let w = x.rem_euclid(std::f64::consts::TAU);
    if w > std::f64::consts::PI { w - std::f64::consts::TAU } else { w }
}

impl FitReport {
    pub fn new(r: &FitResult) -> FitReport {
        FitReport {
            c: r.c,
            c_sigma: r.c_sigma.map(finite),
            theta0: r.start.theta,
            phidot0: r.start.phi_dot,
            psidot0: r.start.psi_dot,
            thetadot0: r.start.theta_dot,
            phi0: wrap_angle(r.start.phi),
            rms_px: r.rms_px,
            frames: r.frames,
            compute_seconds: r.compute_seconds,
            frames_fitted: r.frames_fitted,
            noise_px: r.noise_px,
            start_frame: r.start_frame,
            start_time_s: r.start_t * r.units.time_s,
            time_unit_s: r.units.time_s,
            length_unit_mm: r.units.length_mm,
            segments: r.segments.len(),
            segment_frames: r.segments.first().map_or(0, |s| s.len()),
            iterations: r.iterations,
            residuals: r.residual_count,
            parameters: r.parameter_count,
            coarse_c: r.coarse_c,
            effect: r.effect.map(|(k, s, sd)| EffectReport {
                name: k.name(),
                strength: s,
                sigma: finite(sd),
            }),
        }
    }
}
