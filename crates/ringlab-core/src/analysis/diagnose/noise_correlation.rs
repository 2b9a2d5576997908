//! A tracker whose noise is correlated from frame to frame (a template tracker that smooths,
//! a filter on the tracks): told from a model that misses by the residual's correlation in time.
//!
//! The noise estimate (`recording::noise`) reads the high differences of each track: for
//! white noise they are the noise itself, but noise correlated over a few frames has little
//! power at the highest frequencies, so the tracks read it low (AR(1) noise of 0.6 frame to
//! frame: half the true level), and a right model would then miss "by twice the noise". The
//! tracks alone cannot tell the two apart: at the orders of difference that the motion allows,
//! the differences' own correlation moves by 0.02 between white and such noise.
//!
//! A whole-run prediction can: where the model is right, its residual is the noise, and a
//! tracker's correlation dies out within a few frames; where it misses, the residual holds
//! the missing motion, correlated over tens of frames (a drag's trend, a camera's error turning
//! with the ring). So the correlation is accepted as the noise's only when, over the baseline's
//! residual, it has died out by [`MAX_RANGE_FRAMES`] and stays at zero, block by block, over the
//! next [`LONG_LAGS`] lags. The level is then still the tracks': their estimate divided by what
//! that correlation does to the differences they read, which must agree with the residual.

use crate::analysis::fit::shooting::PredictedMarks;
use crate::recording::noise::{NoiseEstimate, binomial};
use crate::recording::{FrameMarks, MARKS};

/// Lag-1 correlation below which the noise counts as white (the tracks read such noise at
/// least 95% of its level; white noise gives 0 +- 0.01 over a few thousand frames).
pub const MIN_LAG1: f64 = 0.05;
/// The correlation has died out at the first lag where it is below this.
pub const DECAYED: f64 = 0.05;
/// A tracker's correlation must die out within this many frames.
pub const MAX_RANGE_FRAMES: usize = 16;
/// Lags past the range where the correlation must stay at zero: more than a turn of the ring
/// at the start (about 19 frames at 300 frames/s), so an error that turns with it shows.
pub const LONG_LAGS: usize = 32;
/// Frames of a block: the ring's turning rate changes little over one, so an error that turns
/// with it keeps its period inside the block and cannot average away over the run.
pub const BLOCK_FRAMES: usize = 200;
/// The mean over blocks and long lags of `count rho^2 / spread` (1 for noise) must stay below
/// this: a model missing by 1.25 times the noise gives hundreds.
pub const MAX_LONG_LAG_STAT: f64 = 3.0;
/// The tracks' corrected level and the residual's must agree within this share.
pub const MAX_DISAGREEMENT: f64 = 0.2;

/// The noise's correlation in time, measured on a whole-run residual.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct NoiseCorrelation {
    /// The correlation at lags `0..range_frames` (`rho[0] = 1`).
    pub rho: Vec<f64>,
    /// The first lag where it has died out.
    pub range_frames: usize,
    /// The long-lag statistic ([`MAX_LONG_LAG_STAT`]).
    pub long_lag_stat: f64,
    /// The tracks' own reading (px), before the correction.
    pub tracks_px: f64,
    /// The tracks' reading corrected for the correlation (px).
    pub px: f64,
    /// The residual's RMS (px).
    pub residual_px: f64,
}

impl NoiseCorrelation {
    /// How many coordinates count as one independent one for a slow change (a fitted
    /// parameter): the noise's spectrum at zero frequency over its variance, `1 + 2 sum rho`.
    pub fn dependence(&self) -> f64 {
        (1.0 + 2.0 * self.rho[1..].iter().sum::<f64>()).max(1.0)
    }

    /// How much wider a window's sum of squares spreads than for white noise:
    /// `1 + 2 sum rho^2` (for Gaussian noise).
    pub fn spread(&self) -> f64 {
        1.0 + 2.0 * self.rho[1..].iter().map(|r| r * r).sum::<f64>()
    }
}

/// Model minus observed, frame by frame over the span that `pred` covers (from `start`).
fn residuals(observed: &[FrameMarks], start: usize, pred: &PredictedMarks) -> Vec<FrameMarks> {
    observed[start..]
        .iter()
        .zip(pred)
        .map(|(obs, p)| std::array::from_fn(|m| obs[m].map(|o| [p[m][0] - o[0], p[m][1] - o[1]])))
        .collect()
}

/// The lag products `sum r(t) r(t+k)` and their counts, lags `0..lags`, every coordinate of
/// every mark pooled.
fn lag_products(res: &[FrameMarks], lags: usize) -> Vec<(f64, usize)> {
    let mut out = vec![(0.0, 0usize); lags];
    for (t, frame) in res.iter().enumerate() {
        for m in 0..MARKS {
            let Some(a) = frame[m] else { continue };
            for (k, slot) in out.iter_mut().enumerate() {
                let Some(b) = res.get(t + k).and_then(|f| f[m]) else { continue };
                slot.0 += a[0] * b[0] + a[1] * b[1];
                slot.1 += 2;
            }
        }
    }
    out
}

/// Correlations from lag products (`rho[0] = 1`; 0 where a lag has no pair).
fn correlations(products: &[(f64, usize)]) -> Vec<f64> {
    let var = products[0].0 / products[0].1.max(1) as f64;
    products
        .iter()
        .map(|&(s, c)| if c > 0 && var > 0.0 { s / c as f64 / var } else { 0.0 })
        .collect()
}

/// What the correlation `rho` does to the variance of the order-`order` differences the
/// tracks read, against white noise: `sum_ab w_a w_b rho(|a-b|) / sum w^2`.
pub fn difference_factor(order: usize, rho: &[f64]) -> f64 {
    let w: Vec<f64> =
        (0..=order).map(|j| if j % 2 == 0 { 1.0 } else { -1.0 } * binomial(order, j)).collect();
    let at = |k: usize| rho.get(k).copied().unwrap_or(0.0);
    let white: f64 = w.iter().map(|x| x * x).sum();
    let mut sum = 0.0;
    for (a, wa) in w.iter().enumerate() {
        for (b, wb) in w.iter().enumerate() {
            sum += wa * wb * at(a.abs_diff(b));
        }
    }
    sum / white
}

/// The noise's correlation, if the residual of the whole-run prediction `pred` (frames from
/// `start`) shows a tracker's correlation and nothing else; `tracks` is the tracks' reading.
/// None where the residual is white (nothing to correct), where its correlation lasts (a model
/// that misses), or where the corrected level disagrees with the residual.
pub fn measure(
    observed: &[FrameMarks],
    start: usize,
    pred: &PredictedMarks,
    tracks: &NoiseEstimate,
) -> Option<NoiseCorrelation> {
    let res = residuals(observed, start, pred);
    let whole = lag_products(&res, MAX_RANGE_FRAMES + 1);
    let rho = correlations(&whole);
    if !(rho.get(1).copied().unwrap_or(0.0) >= MIN_LAG1) {
        return None;
    }
    let range = (2..=MAX_RANGE_FRAMES).find(|&k| rho[k].abs() < DECAYED)?;
    let rho = rho[..range].to_vec();
    let noise = NoiseCorrelation {
        long_lag_stat: 0.0,
        range_frames: range,
        tracks_px: tracks.px,
        px: tracks.px / difference_factor(tracks.order, &rho).max(1e-6).sqrt(),
        residual_px: (whole[0].0 / whole[0].1.max(1) as f64).sqrt(),
        rho,
    };
    let long_lag_stat = long_lag_stat(&res, range, noise.spread());
    let agrees = (noise.px / noise.residual_px - 1.0).abs() <= MAX_DISAGREEMENT;
    (long_lag_stat <= MAX_LONG_LAG_STAT && agrees)
        .then_some(NoiseCorrelation { long_lag_stat, ..noise })
}

/// Lags over which [`residual_dependence`] sums the correlation at most: a block's frames.
pub const MAX_DEPENDENCE_LAGS: usize = BLOCK_FRAMES;

/// How many coordinates of the residual of the whole-run prediction `pred` (frames from
/// `start`) count as one independent one for a fitted number: `1 + 2 sum rho` over the lags up
/// to the first where the correlation has died out (below [`DECAYED`]; at most
/// [`MAX_DEPENDENCE_LAGS`]), and at least 1. Where the model is right that is the noise's own
/// dependence, whether or not [`measure`] takes it for a tracker's; where the model misses, the
/// missing motion's correlation counts too. Either way a number that takes up a little of such
/// a residual is worth no more than it would be on that many fewer independent residuals.
pub fn residual_dependence(observed: &[FrameMarks], start: usize, pred: &PredictedMarks) -> f64 {
    let res = residuals(observed, start, pred);
    let sum_until_decayed = |lags: usize| {
        let rho = correlations(&lag_products(&res, lags));
        let sum: f64 = rho.iter().skip(1).take_while(|r| **r >= DECAYED).sum();
        let decayed = rho.iter().skip(1).any(|r| *r < DECAYED);
        (sum, decayed)
    };
    // Most residuals decay within a tracker's range; only those that do not pay for every lag.
    let (sum, decayed) = sum_until_decayed(MAX_RANGE_FRAMES + 1);
    let sum = if decayed { sum } else { sum_until_decayed(MAX_DEPENDENCE_LAGS + 1).0 };
    (1.0 + 2.0 * sum).max(1.0)
}

/// The mean over blocks of [`BLOCK_FRAMES`] and lags `range..range + LONG_LAGS` of
/// `count rho_block(k)^2 / spread`: about 1 where the correlation has died out by `range`.
fn long_lag_stat(res: &[FrameMarks], range: usize, spread: f64) -> f64 {
    let blocks = (res.len() / BLOCK_FRAMES).max(1);
    let width = res.len() / blocks;
    let (mut sum, mut terms) = (0.0, 0usize);
    for b in 0..blocks {
        let end = if b + 1 == blocks { res.len() } else { (b + 1) * width };
        let block = &res[b * width..end];
        let products = lag_products(block, range + LONG_LAGS);
        let rho = correlations(&products);
        for k in range..range + LONG_LAGS {
            if products[k].1 > 0 {
                sum += products[k].1 as f64 * rho[k] * rho[k] / spread;
                terms += 1;
            }
        }
    }
    if terms == 0 { f64::INFINITY } else { sum / terms as f64 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recording::rng::Rng;

    /// Marks at rest at the origin (the model predicts zero) with AR(1) noise of 0.5 px,
    /// `phi` from frame to frame, plus `extra(frame)` (scaled a little per mark) on every
    /// coordinate: a model that misses by it.
    fn recording(
        frames: usize,
        phi: f64,
        extra: &dyn Fn(usize) -> f64,
        seed: u64,
    ) -> (Vec<FrameMarks>, PredictedMarks) {
        let mut rng = Rng::new(seed);
        let innovation = (1.0 - phi * phi).sqrt();
        let mut state = [[0.0; 2]; MARKS];
        for s in state.iter_mut().flatten() {
            *s = rng.normal();
        }
        let obs = (0..frames)
            .map(|t| {
                std::array::from_fn(|m| {
                    let mut p = [0.0; 2];
                    for c in 0..2 {
                        state[m][c] = phi * state[m][c] + innovation * rng.normal();
                        p[c] = 0.5 * state[m][c] + extra(t) * (1.0 + m as f64 * 0.3);
                    }
                    Some(p)
                })
            })
            .collect();
        (obs, vec![[[0.0; 2]; MARKS]; frames])
    }

    fn reading(px: f64) -> NoiseEstimate {
        NoiseEstimate { px, order: 6, differences: 10_000 }
    }

    #[test]
    fn white_differences_read_white_noise_whole() {
        assert!((difference_factor(4, &[1.0]) - 1.0).abs() < 1e-12);
        // AR(1) 0.6: the 6th differences see about a quarter of the variance.
        let rho: Vec<f64> = (0..12).map(|k| 0.6f64.powi(k)).collect();
        let f = difference_factor(6, &rho);
        assert!((f - 0.267).abs() < 0.01, "{f}");
    }

    #[test]
    fn a_trackers_correlation_is_accepted_and_the_level_corrected() {
        let (obs, pred) = recording(2000, 0.6, &|_| 0.0, 3);
        // The tracks read about half the level (0.5 px true).
        let c = measure(&obs, 0, &pred, &reading(0.258)).expect("accepted");
        assert!((c.rho[1] - 0.6).abs() < 0.03, "{c:?}");
        assert!((c.px - 0.5).abs() < 0.03, "{c:?}");
        assert!(c.long_lag_stat < 2.0, "{c:?}");
        assert!((c.dependence() - 4.0).abs() < 0.4, "{}", c.dependence());
    }

    #[test]
    fn white_noise_needs_no_correction() {
        let (obs, pred) = recording(2000, 0.0, &|_| 0.0, 4);
        assert_eq!(measure(&obs, 0, &pred, &reading(0.5)), None);
    }

    #[test]
    fn a_model_that_misses_is_no_correlated_noise() {
        // White noise with an error that turns with the ring (period 19 frames, 0.45 px: the
        // baseline 1.2 times the noise) or drifts slowly.
        let turning = |t: usize| 0.45 * (t as f64 * std::f64::consts::TAU / 19.0).sin();
        let drifting = |t: usize| 0.4 * (t as f64 / 300.0).sin();
        for extra in [&turning as &dyn Fn(usize) -> f64, &drifting] {
            let (obs, pred) = recording(2000, 0.0, extra, 5);
            assert_eq!(measure(&obs, 0, &pred, &reading(0.5)), None);
        }
        // Correlated noise beside such an error: still refused (the level stays the tracks').
        let (obs, pred) = recording(2000, 0.6, &drifting, 6);
        assert_eq!(measure(&obs, 0, &pred, &reading(0.258)), None);
    }

    #[test]
    fn the_residuals_dependence_counts_whatever_is_correlated() {
        let white = recording(2000, 0.0, &|_| 0.0, 8);
        assert!(residual_dependence(&white.0, 0, &white.1) < 1.2);
        // AR(1) 0.6 summed to where it dies out (0.6^6 < 0.05): 1 + 2 (0.6 + ... + 0.6^5).
        let ar = recording(2000, 0.6, &|_| 0.0, 9);
        let d = residual_dependence(&ar.0, 0, &ar.1);
        assert!((d - 3.8).abs() < 0.5, "{d}");
        // Correlated far beyond a tracker's range (AR(1) 0.97, which `measure` refuses): counted.
        let long = recording(3000, 0.97, &|_| 0.0, 10);
        let d = residual_dependence(&long.0, 0, &long.1);
        assert!(d > 25.0, "{d}");
        // A model that misses by a slow drift: its residual counts as few independent ones.
        let drift = recording(2000, 0.0, &|t| 0.6 * (t as f64 / 300.0).sin(), 11);
        assert!(residual_dependence(&drift.0, 0, &drift.1) > 20.0);
    }

    #[test]
    fn a_level_that_disagrees_is_refused() {
        let (obs, pred) = recording(2000, 0.6, &|_| 0.0, 7);
        assert_eq!(measure(&obs, 0, &pred, &reading(0.15)), None);
    }
}
