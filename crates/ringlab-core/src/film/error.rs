//! The error a tracked film's centres leave, beyond the pixels' noise.
//!
//! Each centre's standard error from its pixels' noise (`centre`) misses the error that
//! stays from frame to frame: a mark's neighbourhood (the rim's edges, its inner wall, the
//! codec's blocks) pulls its centre the same way for as long as the ring shows the mark the
//! same way, so that error turns with the ring, and the tracks' own differences
//! (`recording::noise`) read it low. The four marks hold a check on it: seen from far away
//! they are four points 90 degrees apart on one circle, a parallelogram, so the midpoints of
//! the two opposite pairs coincide. Their gap `(p1 + p3)/2 - (p2 + p4)/2` holds a quarter of
//! each mark's error variance, four marks' worth: its RMS per coordinate is the error of one
//! centre. A near camera breaks the parallelogram (lines stay lines, midpoints do not), so
//! there the check says nothing and none is claimed.

use crate::recording::FrameMarks;

/// The RMS per coordinate of the opposite pairs' midpoints' gap, over the frames with all four
/// marks, outliers beyond five robust spreads left out; `None` with fewer than 10 frames.
pub fn closure_sigma(frames: &[FrameMarks]) -> Option<f64> {
    let mut gaps: Vec<f64> = Vec::new();
    for f in frames {
        let [Some(p1), Some(p2), Some(p3), Some(p4)] = *f else { continue };
        for c in 0..2 {
            gaps.push((p1[c] + p3[c]) / 2.0 - (p2[c] + p4[c]) / 2.0);
        }
    }
    if gaps.len() < 20 {
        return None;
    }
    let mut abs: Vec<f64> = gaps.iter().map(|g| g.abs()).collect();
    abs.sort_by(|a, b| a.total_cmp(b));
    let spread = 1.4826 * abs[abs.len() / 2];
    let kept: Vec<f64> =
        gaps.iter().copied().filter(|g| g.abs() <= 5.0 * spread.max(1e-6)).collect();
    Some((kept.iter().map(|g| g * g).sum::<f64>() / kept.len() as f64).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recording::rng::Rng;

    #[test]
    fn the_midpoints_gap_reads_each_centres_error() {
        let mut rng = Rng::new(7);
        let frames: Vec<FrameMarks> = (0..3000)
            .map(|i| {
                let phase = i as f64 * 0.2;
                std::array::from_fn(|k| {
                    let a = phase + k as f64 * std::f64::consts::FRAC_PI_2;
                    Some([
                        400.0 + 60.0 * a.cos() + 0.3 * rng.normal(),
                        300.0 + 30.0 * a.sin() + 0.3 * rng.normal(),
                    ])
                })
            })
            .collect();
        let s = closure_sigma(&frames).expect("enough frames");
        assert!((s - 0.3).abs() < 0.015, "{s}");
    }
}
