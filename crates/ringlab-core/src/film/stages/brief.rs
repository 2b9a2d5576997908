//! Glimpses: marks seen in fewer than `least_run` frames in a row, with none seen in the frames
//! either side (a film's first and last frames are not such sides). The ring found anew in a frame or two of a stretch where it is otherwise lost
//! (a flicker's dark frames, an opening on edge) has nothing to confirm it, as four dots
//! found at the start need a second frame that agrees (`acquire`); and what a strongly
//! compressed film shows there is most often a look-alike. Such marks are left out, and counted.

use super::{Stage, StageContext, StageReport, Track};
use crate::film::tuning::BriefTuning;
use crate::recording::FrameMarks;

/// The stage: glimpses left out.
pub struct Brief;

impl Stage for Brief {
    fn name(&self) -> &'static str {
        "brief"
    }
    fn run(&self, track: &mut Track, ctx: &StageContext) -> StageReport {
        let t = &ctx.tuning.brief;
        let left_out = leave_out_glimpses(&mut track.frames, &mut track.sigma, t);
        StageReport::left_out(self.name(), left_out, || {
            format!(
                "{left_out} marks left out, seen in fewer than {} frames in a row between frames where the ring was lost: nothing confirms them",
                t.least_run
            )
        })
    }
}

/// Leaves out the marks of glimpses; returns how many.
pub fn leave_out_glimpses(
    frames: &mut [FrameMarks],
    sigma: &mut [[Option<f64>; 4]],
    tuning: &BriefTuning,
) -> usize {
    let seen = |f: &FrameMarks| f.iter().any(|m| m.is_some());
    let mut left_out = 0;
    let mut i = 0;
    while i < frames.len() {
        if !seen(&frames[i]) {
            i += 1;
            continue;
        }
        let end = (i..frames.len()).find(|&j| !seen(&frames[j])).unwrap_or(frames.len());
        // At the film's ends nothing says the ring was lost before or after.
        if end - i < tuning.least_run && i > 0 && end < frames.len() {
            for j in i..end {
                left_out += frames[j].iter().flatten().count();
                frames[j] = [None; 4];
                sigma[j] = [None; 4];
            }
        }
        i = end;
    }
    left_out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::tuning::BriefTuning;

    #[test]
    fn marks_of_a_frame_or_two_alone_are_left_out_and_longer_stretches_stay() {
        let mark = Some([1.0, 1.0]);
        let row =
            |n: usize| -> FrameMarks { std::array::from_fn(|k| (k < n).then_some(mark).flatten()) };
        // 3 frames seen, 2 unseen, 1 seen (3 marks), 1 unseen, 2 seen, 1 unseen, 4 seen.
        let counts = [4, 4, 2, 0, 0, 3, 0, 1, 4, 0, 4, 4, 4, 4];
        // One frame at either end stands: nothing says the ring was lost beyond it.
        for ends in [vec![4, 0, 4, 4, 4], vec![4, 4, 4, 0, 2]] {
            let mut frames: Vec<FrameMarks> = ends.iter().map(|&n| row(n)).collect();
            let mut sigma = vec![[None; 4]; frames.len()];
            assert_eq!(leave_out_glimpses(&mut frames, &mut sigma, &BriefTuning::default()), 0);
        }
        let mut frames: Vec<FrameMarks> = counts.iter().map(|&n| row(n)).collect();
        let mut sigma = vec![[Some(0.1); 4]; frames.len()];
        assert_eq!(leave_out_glimpses(&mut frames, &mut sigma, &BriefTuning::default()), 3 + 5);
        let left: Vec<usize> = frames.iter().map(|f| f.iter().flatten().count()).collect();
        assert_eq!(left, [4, 4, 2, 0, 0, 0, 0, 0, 0, 0, 4, 4, 4, 4]);
        assert!(sigma[5].iter().all(|s| s.is_none()));
    }
}
