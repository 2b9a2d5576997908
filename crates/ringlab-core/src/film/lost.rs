//! Where the ring was lost: the longest stretch of frames without a single mark, said in the
//! report where it is a large part of the film, so that a recording that is mostly empty is
//! never taken for a tracked one.

use crate::recording::FrameMarks;

/// A stretch without marks is told where it is at least this many frames...
const MIN_FRAMES: usize = 30;
/// ...and at least this share of the film.
const MIN_SHARE: f64 = 0.1;

/// The note on the longest stretch of `frames` (numbered from `first_frame`) without a mark,
/// where it is long enough to tell; `None` otherwise.
pub fn lost_note(frames: &[FrameMarks], first_frame: u64) -> Option<String> {
    let (mut best, mut run_start) = (0..0, None);
    for (i, f) in frames.iter().enumerate() {
        let empty = f.iter().all(Option::is_none);
        match (empty, run_start) {
            (true, None) => run_start = Some(i),
            (false, Some(s)) => {
                if i - s > best.len() {
                    best = s..i;
                }
                run_start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = run_start
        && frames.len() - s > best.len()
    {
        best = s..frames.len();
    }
    let share = best.len() as f64 / frames.len().max(1) as f64;
    if best.len() < MIN_FRAMES || share < MIN_SHARE {
        return None;
    }
    let (a, b) = (first_frame + best.start as u64, first_frame + best.end as u64 - 1);
    let until = if best.end == frames.len() { "to the end".to_string() } else { format!("to {b}") };
    Some(format!(
        "no mark found from frame {a} {until} ({} frames, {:.0}% of the film): the ring was lost there",
        best.len(),
        100.0 * share
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn film(found: impl Fn(usize) -> bool, n: usize) -> Vec<FrameMarks> {
        (0..n).map(|i| if found(i) { [Some([1.0, 2.0]); 4] } else { [None; 4] }).collect()
    }

    #[test]
    fn a_ring_lost_for_good_is_told_and_a_short_loss_is_not() {
        let lost = film(|i| i < 15, 200);
        let note = lost_note(&lost, 100).expect("told");
        assert!(note.contains("from frame 115 to the end (185 frames, 92%"), "{note}");
        let gap = film(|i| !(50..90).contains(&i), 200);
        let note = lost_note(&gap, 0).expect("told");
        assert!(note.contains("from frame 50 to 89 (40 frames, 20%"), "{note}");
        assert_eq!(lost_note(&film(|i| !(50..70).contains(&i), 200), 0), None);
        assert_eq!(lost_note(&film(|i| !(50..90).contains(&i), 1000), 0), None);
    }
}
