//! The marks' style told from the first frames, before tracking. Every finder is fooled now
//! and then: four blobs of four hues can sit as marks do for a frame on a plain ring (a rim's
//! sheen on a textured table), and the dot finders find some four in every frame of any film
//! (a rim's shade, the gaps between marks). So colours are told by four hues in
//! [`COLOUR_FRAMES`] frames of the first [`ACQUIRE_FRAMES`] (a ring on edge can hide them in
//! most: a phone's flickering film shows them in 5 of its first 60); dots, dark or bright, by
//! the marks' strength summed over the frames of the first [`DOT_FRAMES`] whose four agree
//! with the frame before's (the same size in the same place: `acquire`), where the true dots
//! stand out more and stay put.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use super::frame::Frame;
use super::source::FilmSource;
use super::{
    ACQUIRE_FRAMES, FilmError, FilmErrorKind, MarkStyle, Roi, TrackOptions, acquire, find,
};

/// Frames with four distinct hues as marks sit that tell colours.
const COLOUR_FRAMES: usize = 3;
/// Frames the dot finders look at (each takes several times a colour finder's time).
const DOT_FRAMES: usize = 10;

/// What one dot finder showed so far.
#[derive(Default)]
struct Tally {
    last: Option<find::Found>,
    agreeing: usize,
    strength: f64,
}

impl Tally {
    fn add(&mut self, found: Option<find::Found>) {
        if let (Some(now), Some(before)) = (&found, &self.last)
            && acquire::agree(before, now)
        {
            self.agreeing += 1;
            self.strength += now.marks.iter().map(|m| m.strength).sum::<f64>();
        }
        self.last = found;
    }
}

/// The style told from the first [`ACQUIRE_FRAMES`] frames; `None`: none showed (the
/// tracking then says so).
pub fn tell_style(
    path: &Path,
    opts: &TrackOptions,
    roi: &Roi,
    range: (f64, f64),
    cancel: &AtomicBool,
) -> Result<Option<MarkStyle>, FilmError> {
    let mut source = FilmSource::open(path)?;
    source.skip(opts.from_frame)?;
    let mut frame = Frame::default();
    let (mut frames, mut colours) = (0, 0);
    let (mut dark, mut bright) = (Tally::default(), Tally::default());
    for _ in 0..ACQUIRE_FRAMES {
        if cancel.load(Ordering::Relaxed) {
            return Err(FilmError::new(path, FilmErrorKind::Cancelled));
        }
        if !source.next_frame(&mut frame)? {
            break;
        }
        frames += 1;
        if find::find_marks(&frame, roi, MarkStyle::Colours, range).is_some() {
            colours += 1;
            if colours >= COLOUR_FRAMES {
                return Ok(Some(MarkStyle::Colours));
            }
        }
        if frames <= DOT_FRAMES {
            dark.add(find::find_marks(&frame, roi, MarkStyle::Dark, range).map(|(_, f)| f));
            bright.add(find::find_marks(&frame, roi, MarkStyle::Bright, range).map(|(_, f)| f));
        }
    }
    // A film too short to show colours thrice: colours in every frame it has.
    if colours > 0 && colours == frames {
        return Ok(Some(MarkStyle::Colours));
    }
    Ok(match (dark.agreeing, bright.agreeing) {
        (0, 0) => None,
        _ if bright.strength > dark.strength => Some(MarkStyle::Bright),
        _ => Some(MarkStyle::Dark),
    })
}
