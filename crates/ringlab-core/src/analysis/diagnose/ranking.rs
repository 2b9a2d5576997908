//! The candidates ranked by their score, and which of them are fitted through a camera found:
//! what the decision, the selection and the fits made again all read (a leaf below them).

use super::result::Candidate;
use super::rules::bic;
use super::whole::WholeFit;
use crate::analysis::fit::lm::LmError;
use crate::physics::effects::EffectKind;

/// Candidate fits, each effect in turn.
pub(super) type Fits = Vec<(EffectKind, Result<WholeFit, LmError>)>;

/// The baseline and every candidate, best BIC first.
pub(super) fn rank<'a>(
    baseline: &'a WholeFit,
    fits: &'a Fits,
    dependence: f64,
) -> Vec<(Candidate, Option<&'a WholeFit>)> {
    let n = baseline.residual_count;
    let score = |w: &WholeFit| bic(w.cost, n, w.parameter_count, dependence);
    let none_score = score(baseline);
    let mut ranked: Vec<(Candidate, Option<&WholeFit>)> = vec![(
        Candidate {
            effect: EffectKind::BASELINE,
            rms_px: baseline.rms_px(),
            score: none_score,
            delta_score: 0.0,
            strength: None,
            error: None,
            seconds: baseline.seconds,
            stopped_at_segments: baseline.stopped_at,
        },
        Some(baseline),
    )];
    for (kind, r) in fits {
        ranked.push(match r {
            Ok(w) => {
                let c = Candidate {
                    effect: *kind,
                    rms_px: w.rms_px(),
                    score: score(w),
                    delta_score: score(w) - none_score,
                    strength: w.strength,
                    error: None,
                    seconds: w.seconds,
                    stopped_at_segments: w.stopped_at,
                };
                (c, Some(w))
            }
            Err(e) => {
                let c = Candidate {
                    effect: *kind,
                    rms_px: f64::NAN,
                    score: f64::INFINITY,
                    delta_score: f64::INFINITY,
                    strength: None,
                    error: Some(e.to_string()),
                    seconds: 0.0,
                    stopped_at_segments: None,
                };
                (c, None)
            }
        });
    }
    ranked.sort_by(|a, b| a.0.score.total_cmp(&b.0.score));
    ranked
}

/// The effects fitted through the camera the segments see, most promising first: by their
/// score alone, but a costly effect that did not improve alone second. Through the wrong camera
/// it cannot improve (`again.rs::effect_through_camera`), so its score says nothing; its runs take
/// longest, so begun early they run beside the others' (the pairs, where nothing settles, wait
/// for the last of them), and where it settles the recording the others are not fitted.
pub(super) fn through_seen_kinds(ranked: &[(Candidate, Option<&WholeFit>)]) -> Vec<EffectKind> {
    let mut kinds = others_through_camera(ranked, true);
    for (c, _) in ranked.iter().filter(|(c, _)| c.effect.in_plan().costly) {
        if !kinds.contains(&c.effect) {
            kinds.insert(kinds.len().min(1), c.effect);
        }
    }
    kinds
}

/// The candidates fitted through a camera found: every effect but a costly one, which has its
/// own pass (`select.rs::costly_through_lead`) where it did not improve alone; where it did, and the
/// segments see a camera (`camera_seen`), it is one of the others.
pub(super) fn others_through_camera(
    ranked: &[(Candidate, Option<&WholeFit>)],
    camera_seen: bool,
) -> Vec<EffectKind> {
    ranked
        .iter()
        .filter(|(c, _)| !c.effect.is_baseline())
        .filter(|(c, _)| !c.effect.in_plan().costly || (camera_seen && c.delta_score < 0.0))
        .map(|(c, _)| c.effect)
        .collect()
}
