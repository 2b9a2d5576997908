//! Frames with one or two marks where the ring is mostly lost. Three or four marks a quarter
//! turn apart must spread as the ring does (`spread`); any two points fit some pose, and two
//! marks give no pose (`recording::pose` needs an opposite pair and a third). Between frames
//! of three or more (a fast mark missed at a cusp) the frames near vouch for them; in a
//! stretch where the ring is mostly lost (a compressed film's ring on edge, its other marks
//! blurred away) one of the two is as often a spot of stale colour or a look-alike that the
//! follower took. Such frames' marks are left out, and counted.

use super::{Stage, StageContext, StageReport, Track};
use crate::film::tuning::FewTuning;
use crate::recording::FrameMarks;

/// The stage: the marks of frames of one or two that nothing checks left out.
pub struct Few;

impl Stage for Few {
    fn name(&self) -> &'static str {
        "few"
    }
    fn run(&self, track: &mut Track, ctx: &StageContext) -> StageReport {
        let t = &ctx.tuning.few;
        let left_out = leave_out_unchecked(&mut track.frames, &mut track.sigma, t);
        StageReport::left_out(self.name(), left_out, || {
            format!(
                "{left_out} marks left out in frames of fewer than {} marks where the ring was mostly lost: nothing checks them against the ring's figure",
                t.least_marks
            )
        })
    }
}

/// Leaves out the marks of frames with fewer than `least_marks` that the frames near do not
/// vouch for; returns how many.
pub fn leave_out_unchecked(
    frames: &mut [FrameMarks],
    sigma: &mut [[Option<f64>; 4]],
    tuning: &FewTuning,
) -> usize {
    let FewTuning { least_marks, window, least_share } = *tuning;
    let checked: Vec<bool> =
        frames.iter().map(|f| f.iter().flatten().count() >= least_marks).collect();
    let mut left_out = 0;
    for (i, (marks, s)) in frames.iter_mut().zip(sigma.iter_mut()).enumerate() {
        let seen = marks.iter().flatten().count();
        if seen == 0 || seen >= least_marks {
            continue;
        }
        let (lo, hi) = (i.saturating_sub(window), (i + window + 1).min(checked.len()));
        let vouching = checked[lo..hi].iter().filter(|&&c| c).count();
        if (vouching as f64) < least_share * (hi - lo - 1) as f64 {
            left_out += seen;
            *marks = [None; 4];
            *s = [None; 4];
        }
    }
    left_out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::tuning::FewTuning;

    fn row(n: usize) -> FrameMarks {
        std::array::from_fn(|k| (k < n).then_some([k as f64, 1.0]))
    }

    #[test]
    fn two_marks_where_the_ring_is_mostly_lost_are_left_out() {
        // 20 frames lost, then 2, 1, 2 marks, then 20 lost, then 20 frames of four.
        let mut counts = vec![0; 20];
        counts.extend([2, 1, 2]);
        counts.extend([0; 20]);
        counts.extend([4; 20]);
        let mut frames: Vec<FrameMarks> = counts.iter().map(|&n| row(n)).collect();
        let mut sigma = vec![[Some(0.1); 4]; frames.len()];
        assert_eq!(leave_out_unchecked(&mut frames, &mut sigma, &FewTuning::default()), 5);
        assert!(frames[20..23].iter().flatten().all(|m| m.is_none()));
        assert!(sigma[21].iter().all(|s| s.is_none()));
        assert_eq!(frames.iter().flatten().flatten().count(), 80);
    }

    #[test]
    fn two_marks_among_frames_of_three_or_four_stay() {
        // A fast mark missed at the cusps: frames of two and one between frames of three and four.
        let counts = [4, 3, 2, 4, 4, 1, 3, 2, 2, 4, 3, 4];
        let mut frames: Vec<FrameMarks> = counts.iter().map(|&n| row(n)).collect();
        let mut sigma = vec![[Some(0.1); 4]; frames.len()];
        assert_eq!(leave_out_unchecked(&mut frames, &mut sigma, &FewTuning::default()), 0);
        assert_eq!(frames.iter().flatten().flatten().count(), counts.iter().sum::<usize>());
    }
}
