//! Coloured marks whose hue strays from the mark's: a look-alike, or the blur of a ring on edge
//! that the four were acquired on (its hues then carry the marks that follow from it). A
//! mark's hue over many frames is known far better than in any one, so after the tracking
//! each mark found is set against the mean hue of that mark over the frames near it (a
//! phone's white balance drifts slowly), and left out where it is farther off than a quarter
//! of the way to the next mark's hue (four distinct hues lie about a quarter turn apart).

use super::{Stage, StageContext, StageReport, Track};
use crate::film::tuning::StrayHueTuning;
use crate::recording::FrameMarks;

/// The stage: coloured marks of a stray hue left out.
pub struct StrayHue;

impl Stage for StrayHue {
    fn name(&self) -> &'static str {
        "stray_hue"
    }
    fn run(&self, track: &mut Track, ctx: &StageContext) -> StageReport {
        let t = &ctx.tuning.stray_hue;
        let left_out = leave_out_stray_hues(&mut track.frames, &mut track.sigma, ctx.hues, t);
        StageReport::left_out(self.name(), left_out, || {
            format!(
                "{left_out} marks left out whose hue strayed more than {} rad from the mark's over the frames near (a look-alike, or the blur of a ring on edge)",
                t.stray
            )
        })
    }
}

/// Leaves out marks whose hue strays; returns how many. `hues`: by frame, each mark's hue
/// where found (colours; `None` otherwise, and then nothing is left out).
pub fn leave_out_stray_hues(
    frames: &mut [FrameMarks],
    sigma: &mut [[Option<f64>; 4]],
    hues: &[[Option<f64>; 4]],
    tuning: &StrayHueTuning,
) -> usize {
    let StrayHueTuning { window, least_hues, stray } = *tuning;
    let mut left_out = 0;
    for k in 0..4 {
        // Running sums of the unit vectors of the hues found, for means over a window.
        let seen: Vec<(usize, f64)> = (0..frames.len().min(hues.len()))
            .filter(|&i| frames[i][k].is_some())
            .filter_map(|i| hues[i][k].map(|h| (i, h)))
            .collect();
        let mut sums = vec![(0.0, 0.0, 0usize)];
        for &(_, h) in &seen {
            let &(c, s, n) = sums.last().expect("started");
            sums.push((c + h.cos(), s + h.sin(), n + 1));
        }
        for (j, &(i, h)) in seen.iter().enumerate() {
            let lo = seen[..j].partition_point(|p| p.0 + window < i);
            let hi = j + seen[j..].partition_point(|p| p.0 <= i + window);
            let (c, s, n) =
                (sums[hi].0 - sums[lo].0, sums[hi].1 - sums[lo].1, sums[hi].2 - sums[lo].2);
            if n < least_hues {
                continue;
            }
            let d = (h - s.atan2(c) + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            if d.abs() > stray {
                frames[i][k] = None;
                sigma[i][k] = None;
                left_out += 1;
            }
        }
    }
    left_out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::tuning::StrayHueTuning;

    #[test]
    fn a_hue_astray_is_left_out_and_a_slow_drift_is_followed() {
        let n = 1000;
        let mut frames: Vec<FrameMarks> = vec![[Some([1.0, 1.0]); 4]; n];
        let mut sigma = vec![[Some(0.1); 4]; n];
        // Mark 0's hue drifts a whole radian over the film, with noise of 0.1 rad; mark 2 shows
        // another hue in frames 10-14; dots (no hue) are never judged.
        let mut hues: Vec<[Option<f64>; 4]> = (0..n)
            .map(|i| {
                let noise = 0.1 * ((i * 7919) % 13) as f64 / 6.0 - 0.1;
                [Some(1.0 + i as f64 / n as f64 + noise), Some(-1.5), Some(0.0), None]
            })
            .collect();
        for h in &mut hues[10..15] {
            h[2] = Some(0.6);
        }
        let left_out =
            leave_out_stray_hues(&mut frames, &mut sigma, &hues, &StrayHueTuning::default());
        assert_eq!(left_out, 5);
        assert!((10..15).all(|i| frames[i][2].is_none() && sigma[i][2].is_none()));
        assert!(frames.iter().all(|f| f[0].is_some() && f[1].is_some() && f[3].is_some()));
    }
}
