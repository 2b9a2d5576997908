//! What the marks' tracks say on their own, before any model: the pixel noise ([`noise`]) and
//! the tracker's glitches ([`glitches`]), and the recording with the glitches left out, which
//! is what every fit works on.

use super::Recording;
use super::glitches::{Glitch, find_glitches, without_glitches};
use super::noise::{NoiseEstimate, track_noise};

/// A recording with its glitches left out, the glitches, and the noise of what is left.
#[derive(Clone, Debug)]
pub struct CheckedTracks {
    pub recording: Recording,
    pub glitches: Vec<Glitch>,
    pub noise: Option<NoiseEstimate>,
}

/// Finds the glitches (with the noise of all the positions; it is robust to them), leaves them
/// out, and estimates the noise again without them.
pub fn check_tracks(rec: &Recording) -> CheckedTracks {
    let first = with_tracker_floor(track_noise(&rec.frames, &|_, _| false), rec);
    let glitches = first.map_or_else(Vec::new, |n| find_glitches(&rec.frames, n.px));
    if glitches.is_empty() {
        return CheckedTracks { recording: rec.clone(), glitches, noise: first };
    }
    let frames = without_glitches(&rec.frames, &glitches);
    let noise = with_tracker_floor(track_noise(&frames, &|_, _| false), rec).or(first);
    CheckedTracks { recording: Recording { frames, ..rec.clone() }, glitches, noise }
}

/// The header key of a tracker's own estimate of a centre's error (px per coordinate), written
/// by the film tracker (`film`): the noise estimate of the tracks takes it where it is larger.
pub const TRACKER_SIGMA_KEY: &str = "tracker_sigma_px";

/// The tracker's own estimate of a centre's error (the header's [`TRACKER_SIGMA_KEY`], written
/// by `ringlab track`), where it is larger than what the tracks' differences read: an error
/// that turns with the ring is smooth in time, and the differences miss it.
fn with_tracker_floor(noise: Option<NoiseEstimate>, rec: &Recording) -> Option<NoiseEstimate> {
    let floor = rec
        .header
        .extra
        .iter()
        .find(|(k, _)| k == TRACKER_SIGMA_KEY)
        .and_then(|(_, v)| v.parse::<f64>().ok())
        .filter(|v| v.is_finite() && *v > 0.0);
    match (noise, floor) {
        (Some(n), Some(f)) if f > n.px => Some(NoiseEstimate { px: f, ..n }),
        (n, _) => n,
    }
}

/// `tracks` with `more` glitches left out too, and the noise estimated again without them.
pub fn with_more_glitches(tracks: &CheckedTracks, more: &[Glitch]) -> CheckedTracks {
    if more.is_empty() {
        return tracks.clone();
    }
    let frames = without_glitches(&tracks.recording.frames, more);
    let noise =
        with_tracker_floor(track_noise(&frames, &|_, _| false), &tracks.recording).or(tracks.noise);
    let mut glitches: Vec<Glitch> = tracks.glitches.iter().chain(more).copied().collect();
    glitches.sort_by_key(|g| (g.frame, g.mark));
    CheckedTracks { recording: Recording { frames, ..tracks.recording.clone() }, glitches, noise }
}

/// The recording as it is, with the noise of its tracks (no glitch search).
pub fn as_tracked(rec: &Recording) -> CheckedTracks {
    CheckedTracks {
        recording: rec.clone(),
        glitches: Vec::new(),
        noise: with_tracker_floor(track_noise(&rec.frames, &|_, _| false), rec),
    }
}
