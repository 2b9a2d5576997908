//! The residual against time, the noise floor and the windows where a model departs from the
//! recording beyond its noise.
//!
//! Frame by frame the residual is the RMS of model minus recording over the frame's tracked
//! mark coordinates. Single frames are noisy (8 numbers), so the test runs on windows of
//! [`WINDOW_S`] (15 frames at 300 fps, about 120 coordinates): a window departs when its mean
//! squared residual exceeds the noise variance by more than chance allows, `1 + z sqrt(2/n)`
//! times it for `n` coordinates (the chi-square's spread), with `z` = [`Z_WINDOW`]. The noise
//! itself is the recording's own, estimated from the marks alone (`recording::recover`), not
//! from any model; that estimate is good to a few percent (the sample's: 0.485 px for 0.5 px),
//! and 3% low in the noise is 6% in the variance, half a chi-square sigma at 15 frames: so
//! `z` = 5, which leaves a recording that the model explains without a flagged window (about
//! one chance in a thousand per window at 15 frames, 6% low) while a model that misses by a
//! third of the noise in a 50 ms window is still caught.

use crate::recording::FrameMarks;
use std::ops::Range;

/// Width of a test window (s); at least [`MIN_WINDOW_FRAMES`] frames.
pub const WINDOW_S: f64 = 0.05;
pub const MIN_WINDOW_FRAMES: usize = 5;
/// The window test's threshold in standard deviations of its chi-square.
pub const Z_WINDOW: f64 = 5.0;
/// Departing windows closer than this many windows join into one mismatch window.
pub const JOIN_GAP_WINDOWS: usize = 2;

/// The noise a residual is judged against: its level per coordinate, and how much wider a
/// window's sum of squares spreads than under white noise (1: white; a tracker's correlated
/// noise spreads it wider, `noise_correlation`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseLevel {
    pub px: f64,
    pub spread: f64,
}

impl NoiseLevel {
    pub fn white(px: f64) -> NoiseLevel {
        NoiseLevel { px, spread: 1.0 }
    }
}

/// Squared residual sum and coordinate count of every frame of `span`; `pred[i]` is frame
/// `span.start + i`.
pub fn frame_sums(
    observed: &[FrameMarks],
    span: Range<usize>,
    pred: &[[[f64; 2]; 4]],
) -> Vec<(f64, usize)> {
    observed[span]
        .iter()
        .zip(pred)
        .map(|(obs, p)| {
            let mut sum = 0.0;
            let mut n = 0;
            for (o, p) in obs.iter().zip(p) {
                if let Some(o) = o {
                    sum += (p[0] - o[0]).powi(2) + (p[1] - o[1]).powi(2);
                    n += 2;
                }
            }
            (sum, n)
        })
        .collect()
}

/// Per-frame RMS (NaN where nothing was tracked).
pub fn frame_rms(sums: &[(f64, usize)]) -> Vec<f64> {
    sums.iter().map(|&(s, n)| if n > 0 { (s / n as f64).sqrt() } else { f64::NAN }).collect()
}

/// One test window: frames (relative to the span), RMS, and whether it departs.
#[derive(Clone, Debug, PartialEq)]
pub struct Window {
    pub frames: Range<usize>,
    pub rms_px: f64,
    /// The RMS above which it departs.
    pub threshold_px: f64,
    pub departs: bool,
    /// Squared residual beyond the noise (px^2, summed over its coordinates; may be negative).
    pub excess: f64,
}

/// The test windows over `sums` for `noise` and `width` frames each.
pub fn windows(sums: &[(f64, usize)], noise: NoiseLevel, width: usize) -> Vec<Window> {
    let width = width.max(1);
    let (noise_px, spread) = (noise.px, noise.spread.max(1.0));
    let var = noise_px * noise_px;
    (0..sums.len())
        .step_by(width)
        .map(|a| {
            let b = (a + width).min(sums.len());
            let (s, n) = sums[a..b].iter().fold((0.0, 0usize), |acc, x| (acc.0 + x.0, acc.1 + x.1));
            let limit = 1.0 + Z_WINDOW * (2.0 * spread / n.max(1) as f64).sqrt();
            let rms = if n > 0 { (s / n as f64).sqrt() } else { f64::NAN };
            Window {
                frames: a..b,
                rms_px: rms,
                threshold_px: noise_px * limit.sqrt(),
                departs: n > 0 && s > limit * var * n as f64,
                excess: s - var * n as f64,
            }
        })
        .collect()
}

/// Frame ranges (relative to the span) where windows depart, neighbours within
/// [`JOIN_GAP_WINDOWS`] joined; with the excess squared residual of each.
pub fn departures(windows: &[Window]) -> Vec<(Range<usize>, f64)> {
    let mut out: Vec<(Range<usize>, f64, usize)> = Vec::new();
    for (i, w) in windows.iter().enumerate() {
        if !w.departs {
            continue;
        }
        match out.last_mut() {
            Some(last) if i - last.2 <= JOIN_GAP_WINDOWS + 1 => {
                let between: f64 = windows[last.2 + 1..=i].iter().map(|w| w.excess).sum();
                last.0.end = w.frames.end;
                last.1 += between;
                last.2 = i;
            }
            _ => out.push((w.frames.clone(), w.excess, i)),
        }
    }
    out.into_iter().map(|(r, e, _)| (r, e)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recording::rng::Rng;

    #[test]
    fn pure_noise_departs_nowhere_and_an_offset_is_found() {
        let mut rng = Rng::new(5);
        let sigma = 0.5;
        let n = 3000;
        let mut sums: Vec<(f64, usize)> =
            (0..n).map(|_| ((0..8).map(|_| (sigma * rng.normal()).powi(2)).sum(), 8)).collect();
        let w = windows(&sums, NoiseLevel::white(sigma), 15);
        assert!(departures(&w).is_empty(), "{:?}", departures(&w));
        // A 1 px drift over frames 2000..2300.
        for s in &mut sums[2000..2300] {
            s.0 += 8.0;
        }
        let d = departures(&windows(&sums, NoiseLevel::white(sigma), 15));
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].0, 1995..2310);
        assert!((d[0].1 - 8.0 * 300.0).abs() < 300.0, "excess {}", d[0].1);
    }

    #[test]
    fn frames_without_marks_count_nothing() {
        let obs: Vec<FrameMarks> = vec![[None; 4], [Some([1.0, 1.0]); 4]];
        let pred = vec![[[0.0, 0.0]; 4]; 2];
        let s = frame_sums(&obs, 0..2, &pred);
        assert_eq!(s, vec![(0.0, 0), (8.0, 8)]);
        let r = frame_rms(&s);
        assert!(r[0].is_nan() && r[1] == 1.0);
    }
}
