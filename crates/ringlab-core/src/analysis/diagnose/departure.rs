//! Where the baseline departs: the longest stretch from the start that the baseline, fitted
//! to that stretch alone, follows to the noise. Fitted to the whole run a model that lacks
//! something spreads its error over the whole run (the least squares trade the start against
//! the end), which hides where the recording first parts from it; fitted to a growing prefix
//! it follows the recording until the missing physics has acted enough to show, and no
//! further. The prefix doubles from the first segment while the fit stays within the noise,
//! then bisection narrows the point down to an eighth of the last doubling.
//!
//! "Within the noise": no test window of [`super::residual`] departs, at the test width and
//! at four times it (a slow, small deviation shows in the wider windows first).

use super::residual::{NoiseLevel, departures, frame_sums, windows};
use super::whole::{WholeFit, fit_whole, with_effect};
use crate::analysis::fit::lm::LmError;
use crate::analysis::fit::shooting::Shooting;
use crate::physics::StateVec;
use crate::physics::effects::EffectKind;
use std::ops::Range;

/// Bisection steps after the first failing doubling.
const BISECTIONS: usize = 3;

/// The baseline's longest well-followed prefix.
#[derive(Clone, Debug)]
pub struct Departure {
    /// Frames the baseline follows within the noise, from the start (the whole span when it
    /// never departs).
    pub followed: Range<usize>,
    /// Whether it departs at all before the span's end.
    pub departs: bool,
    /// The baseline fitted to `followed` (its prediction runs on over the rest of the span).
    pub fit: WholeFit,
}

impl Departure {
    /// No departure: `fit` follows its whole span.
    pub fn none(fit: &WholeFit) -> Departure {
        Departure { followed: fit.span.clone(), departs: false, fit: fit.clone() }
    }
}

/// Whether a prediction from `fit` stays within the noise over `frames`.
pub fn follows(
    sh: &Shooting,
    fit: &WholeFit,
    frames: Range<usize>,
    noise: NoiseLevel,
    width: usize,
) -> bool {
    let Some(pred) = fit.marks(sh) else { return false };
    let sums = frame_sums(sh.observed, frames.clone(), &pred[..frames.len().min(pred.len())]);
    departures(&windows(&sums, noise, width)).is_empty()
        && departures(&windows(&sums, noise, 4 * width)).is_empty()
}

/// Finds the departure. `ms` is the baseline's multiple-shooting problem (drag free) with its
/// fitted drag as the base, `states` its segments' start states.
pub fn find(
    ms: &Shooting,
    states: &[StateVec],
    noise: NoiseLevel,
    width: usize,
) -> Result<Departure, LmError> {
    let span = ms.segments.first().map(|s| s.start).unwrap_or(0)
        ..ms.segments.last().map(|s| s.end).unwrap_or(0);
    let first = ms.segments.first().cloned().ok_or(LmError::BadStart)?;
    // The baseline as every whole-run fit has it (the body's dimensions free).
    let base = with_effect(ms, EffectKind::None);
    let g0 = base.spec.to_internal(&base.spec.initial_values());
    let y0 = *states.first().ok_or(LmError::BadStart)?;
    let prefix = |end: usize| Shooting { segments: vec![span.start..end], ..base.clone() };
    let fit_prefix = |end: usize, g: &[f64], y: StateVec| {
        fit_whole(&prefix(end), g.to_vec(), &[y], &mut |_, _| {})
    };
    let mut good = fit_prefix(first.end, &g0, y0)?;
    if !follows(&prefix(first.end), &good, span.start..first.end, noise, width) {
        return Ok(Departure { followed: span.start..span.start, departs: true, fit: good });
    }
    let mut bad = None;
    while good.span.end < span.end {
        let end = (span.start + 2 * good.span.len()).min(span.end);
        let trial = fit_prefix(end, &good.internal, good.start)?;
        if follows(&prefix(end), &trial, span.start..end, noise, width) {
            good = trial;
        } else {
            bad = Some(end);
            break;
        }
    }
    let Some(mut bad_end) = bad else {
        return Ok(Departure { followed: span.clone(), departs: false, fit: good });
    };
    for _ in 0..BISECTIONS {
        let mid = (good.span.end + bad_end) / 2;
        if mid <= good.span.end || mid >= bad_end {
            break;
        }
        let trial = fit_prefix(mid, &good.internal, good.start)?;
        if follows(&prefix(mid), &trial, span.start..mid, noise, width) {
            good = trial;
        } else {
            bad_end = mid;
        }
    }
    // The prediction of the last good fit over the whole span.
    let followed = span.start..good.span.end;
    good.span = span;
    Ok(Departure { followed, departs: true, fit: good })
}
