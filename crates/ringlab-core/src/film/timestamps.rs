//! A film whose frame rate varies (a phone drops frames in poor light): where each frame
//! falls at the film's own rate, from its timestamps, so that a frame never taken is an empty
//! row at its time and not a frame the others slide into (the physics is timed by the frame
//! numbers). The film's own rate is that of its commonest interval, the median: a
//! container's nominal rate can be any rate all its timestamps fit, several times the film's.

use std::path::Path;
use std::process::{Command, Stdio};

/// The rates differ by more than this share where the film's rate varies.
const VARIES: f64 = 0.005;

/// Whether the average rate says frames are missing at the nominal one.
pub fn rate_varies(nominal: f64, average: f64) -> bool {
    (average / nominal - 1.0).abs() > VARIES
}

/// The film's own rate (frames/s) and each frame's number at it, in the order ffmpeg gives
/// them, from the video packets' timestamps as `ffprobe` reads them; `None` where they cannot
/// be had or do not rise frame by frame.
pub fn frame_slots(ffprobe: &Path, path: &Path) -> Option<(f64, Vec<u64>)> {
    let out = Command::new(ffprobe)
        .args(["-v", "error", "-select_streams", "v:0", "-show_entries", "packet=pts_time"])
        .args(["-of", "csv=p=0"])
        .arg(path)
        .stdin(Stdio::null())
        .output()
        .ok()?;
    let text = String::from_utf8_lossy(&out.stdout);
    let mut times: Vec<f64> = text
        .lines()
        .map(|l| l.trim().trim_end_matches(',').parse::<f64>().ok())
        .collect::<Option<_>>()?;
    times.sort_by(|a, b| a.total_cmp(b));
    let rate = own_rate(&times)?;
    let slots = slots(&times, rate)?;
    Some((refined(&times, &slots).unwrap_or(rate), slots))
}

/// The rate the first and last frames' times and numbers give (timestamps are printed to a
/// microsecond: one interval's rate is off by up to 0.03% at 240 frames/s), a whole number
/// where it is within a hundred-thousandth of one.
fn refined(times: &[f64], slots: &[u64]) -> Option<f64> {
    let (t0, t1, n) = (*times.first()?, *times.last()?, *slots.last()? as f64);
    let rate = n / (t1 - t0);
    if !(rate.is_finite() && rate > 0.0) {
        return None;
    }
    Some(if (rate / rate.round() - 1.0).abs() < 1e-5 { rate.round() } else { rate })
}

/// The rate of the median interval between frames shown at `times` (s, ascending).
fn own_rate(times: &[f64]) -> Option<f64> {
    let mut intervals: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    intervals.sort_by(|a, b| a.total_cmp(b));
    let median = *intervals.get(intervals.len() / 2)?;
    (median > 0.0).then(|| 1.0 / median)
}

/// Frame numbers at `nominal` frames/s of frames shown at `times` (s, ascending).
fn slots(times: &[f64], nominal: f64) -> Option<Vec<u64>> {
    let first = *times.first()?;
    let slots: Vec<u64> = times.iter().map(|t| ((t - first) * nominal).round() as u64).collect();
    slots.windows(2).all(|w| w[1] > w[0]).then_some(slots)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_dropped_leave_their_slots_and_a_steady_film_none() {
        let times: Vec<f64> =
            (0..10).filter(|i| !(4..7).contains(i)).map(|i| 1.0 + i as f64 / 240.0).collect();
        assert_eq!(slots(&times, 240.0), Some(vec![0, 1, 2, 3, 7, 8, 9]));
        assert!((own_rate(&times).expect("a rate") - 240.0).abs() < 1e-6);
        let printed: Vec<f64> = times.iter().map(|t| (t * 1e6).round() / 1e6).collect();
        assert_eq!(refined(&printed, &[0, 1, 2, 3, 7, 8, 9]), Some(240.0));
        assert!(rate_varies(240.0, 220.0));
        assert!(!rate_varies(240.0, 239.9));
        // Two frames in one slot: the nominal rate is not the film's.
        assert_eq!(slots(&[0.0, 0.001, 0.01], 240.0), None);
    }
}
