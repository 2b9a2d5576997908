//! Frames whose marks spread wider or narrower than the ring: a look-alike taken for a mark.
//! The ellipse through four marks a quarter turn apart (or three) has the ring's size for its
//! semi-major axis in every pose, and two marks never lie farther apart than the ring allows
//! (`follow::least_semi_major`); the size is the median of the frames with all four near by
//! (a near camera's size changes slowly as the ring rolls). Which mark of such a frame is the
//! look-alike the frame cannot tell: its marks are all left out, and counted.

use super::{Stage, StageContext, StageReport, Track};
use crate::film::follow::least_semi_major;
use crate::film::tuning::SpreadTuning;
use crate::recording::FrameMarks;

/// The stage: the marks of frames off the ring's size left out.
pub struct Spread;

impl Stage for Spread {
    fn name(&self) -> &'static str {
        "spread"
    }
    fn run(&self, track: &mut Track, ctx: &StageContext) -> StageReport {
        let t = &ctx.tuning.spread;
        let left_out = leave_out_off_size(&mut track.frames, &mut track.sigma, t);
        StageReport::left_out(self.name(), left_out, || {
            format!(
                "{left_out} marks left out in frames whose marks spread wider or narrower than the ring (a look-alike among them)"
            )
        })
    }
}

/// Leaves out the marks of frames not of the ring's size; returns how many were left out.
pub fn leave_out_off_size(
    frames: &mut [FrameMarks],
    sigma: &mut [[Option<f64>; 4]],
    tuning: &SpreadTuning,
) -> usize {
    let fours: Vec<(usize, f64)> = frames
        .iter()
        .enumerate()
        .filter(|(_, f)| f.iter().all(|m| m.is_some()))
        .filter_map(|(i, f)| least_semi_major(f).map(|a| (i, a)))
        .collect();
    let mut left_out = 0;
    for i in 0..frames.len() {
        let seen = frames[i].iter().filter(|m| m.is_some()).count();
        let Some(a) = least_semi_major(&frames[i]) else { continue };
        let Some(size) = size_near(&fours, i, tuning) else { continue };
        let tolerance = tuning.tolerance * size + tuning.tolerance_px;
        let off = if seen >= 3 { (a - size).abs() > tolerance } else { a > size + tolerance };
        if off {
            left_out += seen;
            frames[i] = [None; 4];
            sigma[i] = [None; 4];
        }
    }
    left_out
}

/// The median size of the frames with four marks within `tuning.window` of frame `i`.
fn size_near(fours: &[(usize, f64)], i: usize, tuning: &SpreadTuning) -> Option<f64> {
    let lo = fours.partition_point(|f| f.0 + tuning.window < i);
    let hi = fours.partition_point(|f| f.0 <= i + tuning.window);
    let mut near: Vec<f64> = fours[lo..hi].iter().map(|f| f.1).collect();
    if near.len() < tuning.least_fours {
        return None;
    }
    near.sort_by(|a, b| a.total_cmp(b));
    Some(near[near.len() / 2])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::tuning::SpreadTuning;

    /// Four marks on a circle of radius `r` seen tilted (`squash` of its height), turned by
    /// `turn`.
    fn ring(r: f64, squash: f64, turn: f64) -> FrameMarks {
        std::array::from_fn(|k| {
            let t = turn + k as f64 * std::f64::consts::FRAC_PI_2;
            Some([100.0 + r * t.cos(), 100.0 + squash * r * t.sin()])
        })
    }

    #[test]
    fn a_look_alike_that_widens_the_figure_is_left_out_and_tilted_rings_stay() {
        let mut frames: Vec<FrameMarks> =
            (0..40).map(|i| ring(40.0, 1.0 - i as f64 / 45.0, 0.1 * i as f64)).collect();
        // Frame 20: mark 2 taken on something 30 px off, the others right (three found).
        frames[20][3] = None;
        frames[20][1] = frames[20][1].map(|p| [p[0] + 30.0, p[1]]);
        // Frame 25: mark 2 stuck 20 degrees behind its place (10.5 px), three found: the
        // figure 16% wide.
        frames[25][3] = None;
        let behind = 0.1 * 25.0 + std::f64::consts::FRAC_PI_2 - 20f64.to_radians();
        frames[25][1] =
            Some([100.0 + 40.0 * behind.cos(), 100.0 + 20.0 / 45.0 * 40.0 * behind.sin()]);
        // Frame 30: two opposite marks farther apart than the ring's diameter.
        frames[30] = [Some([50.0, 100.0]), None, Some([150.0, 100.0]), None];
        // Frame 35: two adjacent marks as the ring allows them, on edge.
        frames[35] = [Some([60.0, 100.0]), Some([100.0, 101.0]), None, None];
        let mut sigma = vec![[Some(0.1); 4]; frames.len()];
        let left_out = leave_out_off_size(&mut frames, &mut sigma, &SpreadTuning::default());
        assert_eq!(left_out, 8);
        assert!(frames[20].iter().all(|m| m.is_none()) && sigma[20][0].is_none());
        assert!(frames[25].iter().all(|m| m.is_none()));
        assert!(frames[30].iter().all(|m| m.is_none()));
        assert!(frames[35][0].is_some());
        assert_eq!(frames.iter().flatten().filter(|m| m.is_some()).count(), 146);
    }

    #[test]
    fn too_few_fours_decide_nothing() {
        let mut frames: Vec<FrameMarks> = (0..5).map(|i| ring(40.0, 0.5, i as f64)).collect();
        frames[2][0] = frames[2][0].map(|p| [p[0] + 50.0, p[1]]);
        let mut sigma = vec![[None; 4]; 5];
        assert_eq!(leave_out_off_size(&mut frames, &mut sigma, &SpreadTuning::default()), 0);
    }
}
