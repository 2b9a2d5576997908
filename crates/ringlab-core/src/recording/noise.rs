//! The pixel noise of a recording, from each mark's track alone: no model, no camera.
//!
//! Over a few frames a mark's coordinate is a smooth function of time, so its `k`-th finite
//! difference `sum_j (-1)^j C(k, j) x_{i+j}` (the residual of a degree `k-1` polynomial through
//! `k+1` frames) is nearly all noise: white noise of standard deviation `s` gives differences
//! of standard deviation `s sqrt(C(2k, k))`. The scale is robust (the median of `|d|`, so a
//! tracker's outliers and swapped labels move it little), and taken at several orders: the
//! motion only adds to a difference, so the smallest estimate is the least contaminated (at
//! 300 frames/s a mark turns by about a third of a radian a frame, and its 4th difference
//! holds a few hundredths of a pixel of motion).
//!
//! Anything the geometry of the marks does not expect (perspective, a tilted camera, a lens,
//! a tracker's glitches) is smooth in time or rare, so none of it counts as noise here: that is
//! why the diagnosis tests its misfits against this estimate and not against the scatter of
//! the marks about a circle.

use super::FrameMarks;

/// Orders of difference tried; the smallest estimate wins.
const ORDERS: [usize; 4] = [3, 4, 5, 6];

/// Fewest differences an order needs to give an estimate.
const MIN_DIFFERENCES: usize = 20;

/// The Gaussian consistency factor of the median absolute value (`1 / Phi^-1(3/4)`).
const MAD_TO_SIGMA: f64 = 1.482_602_218_505_602;

/// The noise per pixel coordinate (px), and what it came from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseEstimate {
    pub px: f64,
    /// The order of difference that gave it and how many differences it had.
    pub order: usize,
    pub differences: usize,
}

/// Differences beyond this many scales are left out of the second moment (a glitch's lie tens
/// of scales off).
const CLIP_SCALES: f64 = 3.0;

/// The variance of a standard normal variable kept within `+-CLIP_SCALES`:
/// `1 - 2 c phi(c) / (2 Phi(c) - 1)` at `c = 3`.
const CLIPPED_VARIANCE: f64 = 0.973_336_924;

/// The standard deviation of the Gaussian bulk of `|d|`, robust to outliers. The median of
/// `|d|` alone starts it; but a tracker that writes whole pixels makes every difference an
/// integer and the median jumps between integers (0.3 px of noise rounded to pixels read as
/// 0.33 px instead of 0.42 px). So the second moment of the differences within
/// [`CLIP_SCALES`] of the current scale, corrected for the clipping, refines it until it
/// settles: it varies smoothly with the data whatever their rounding.
fn robust_scale(abs_diffs: &mut [f64]) -> f64 {
    let mid = abs_diffs.len() / 2;
    let median = *abs_diffs.select_nth_unstable_by(mid, f64::total_cmp).1;
    let mut scale = MAD_TO_SIGMA * median;
    if !(scale > 0.0) {
        // More than half the differences are zero: start from their overall size instead.
        let mean = abs_diffs.iter().sum::<f64>() / abs_diffs.len() as f64;
        scale = mean * (std::f64::consts::PI / 2.0).sqrt();
    }
    for _ in 0..20 {
        let clip = CLIP_SCALES * scale;
        let (sum, count) = abs_diffs
            .iter()
            .filter(|d| **d <= clip)
            .fold((0.0, 0usize), |(s, c), d| (s + d * d, c + 1));
        if count == 0 {
            break;
        }
        let next = (sum / count as f64 / CLIPPED_VARIANCE).sqrt();
        let settled = (next - scale).abs() <= 1e-6 * scale;
        scale = next;
        if settled {
            break;
        }
    }
    scale
}

/// `C(n, k)` as a float.
pub(crate) fn binomial(n: usize, k: usize) -> f64 {
    (0..k).fold(1.0, |acc, j| acc * (n - j) as f64 / (j + 1) as f64)
}

/// The noise per pixel coordinate from the marks' tracks; `skip(frame, mark)` leaves a mark
/// out (a glitch). None when no order has [`MIN_DIFFERENCES`] differences (too few frames
/// where a mark is tracked `k + 1` times in a row) or all differences are zero.
pub fn track_noise(
    frames: &[FrameMarks],
    skip: &dyn Fn(usize, usize) -> bool,
) -> Option<NoiseEstimate> {
    let mut best: Option<NoiseEstimate> = None;
    for order in ORDERS {
        let weights: Vec<f64> =
            (0..=order).map(|j| if j % 2 == 0 { 1.0 } else { -1.0 } * binomial(order, j)).collect();
        let mut diffs: Vec<f64> = Vec::with_capacity(8 * frames.len());
        for mark in 0..frames.first().map_or(0, |f| f.len()) {
            for i in 0..frames.len().saturating_sub(order) {
                let window = i..=i + order;
                let points: Option<Vec<[f64; 2]>> =
                    window.map(|f| if skip(f, mark) { None } else { frames[f][mark] }).collect();
                let Some(points) = points else { continue };
                for c in 0..2 {
                    diffs.push(
                        points.iter().zip(&weights).map(|(p, w)| w * p[c]).sum::<f64>().abs(),
                    );
                }
            }
        }
        if diffs.len() < MIN_DIFFERENCES {
            continue;
        }
        let px = robust_scale(&mut diffs) / binomial(2 * order, order).sqrt();
        if px > 0.0 && best.is_none_or(|b| px < b.px) {
            best = Some(NoiseEstimate { px, order, differences: diffs.len() });
        }
    }
    best
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::recording::rng::Rng;

    /// Four marks in cyclic order on a circle turning at `rate` rad per frame, drifting, with
    /// noise `s` (also the glitch finder's test tracks).
    pub(crate) fn spinning(frames: usize, rate: f64, s: f64, seed: u64) -> Vec<FrameMarks> {
        let mut rng = Rng::new(seed);
        (0..frames)
            .map(|i| {
                let t = i as f64;
                std::array::from_fn(|k| {
                    let a = rate * t - k as f64 * std::f64::consts::FRAC_PI_2;
                    Some([
                        600.0 + 0.8 * t + 67.0 * a.cos() + s * rng.normal(),
                        400.0 - 0.3 * t + 40.0 * a.sin() + s * rng.normal(),
                    ])
                })
            })
            .collect()
    }

    #[test]
    fn finds_white_noise_under_fast_motion() {
        for (rate, s) in [(0.33, 0.5), (0.6, 0.5), (0.33, 2.0), (0.1, 0.1)] {
            let est = track_noise(&spinning(2000, rate, s, 7), &|_, _| false).unwrap();
            assert!((est.px / s - 1.0).abs() < 0.06, "rate {rate}, noise {s}: {est:?}");
        }
    }

    #[test]
    fn outliers_and_gaps_move_it_little() {
        let mut frames = spinning(2000, 0.33, 0.5, 3);
        let mut rng = Rng::new(11);
        for i in (0..2000).step_by(97) {
            frames[i][i % 4] =
                frames[i][i % 4].map(|p| [p[0] + 10.0 + 50.0 * rng.uniform(), p[1] - 30.0]);
            frames[i + 1][(i + 2) % 4] = None;
        }
        let est = track_noise(&frames, &|_, _| false).unwrap();
        assert!((est.px / 0.5 - 1.0).abs() < 0.1, "{est:?}");
    }

    #[test]
    fn whole_pixel_tracks_count_their_rounding_as_noise() {
        // 0.3 px of noise rounded to whole pixels: sqrt(0.3^2 + 1/12) = 0.416 px a coordinate.
        let frames: Vec<FrameMarks> = spinning(2000, 0.33, 0.3, 5)
            .into_iter()
            .map(|f| f.map(|m| m.map(|p| [p[0].round(), p[1].round()])))
            .collect();
        let est = track_noise(&frames, &|_, _| false).unwrap();
        let truth = (0.3f64.powi(2) + 1.0 / 12.0).sqrt();
        assert!((est.px / truth - 1.0).abs() < 0.06, "{est:?} against {truth}");
    }

    #[test]
    fn too_few_frames_give_none() {
        assert!(track_noise(&spinning(3, 0.3, 0.5, 1), &|_, _| false).is_none());
        let exact = spinning(100, 0.0, 0.0, 1);
        assert!(track_noise(&exact, &|_, _| false).is_none_or(|n| n.px < 1e-9));
    }
}
