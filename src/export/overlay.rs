//! The film with its overlay (`session::overlay`) drawn over each frame, as an MP4 for a
//! report or a class (`ringlab track --overlay`).

use super::ExportError;
use super::mp4::Mp4Writer;
use super::video::FrameSink;
use crate::film::{FilmSource, Frame, TrackOptions};
use crate::session::overlay::{Overlay, frame_image};
use std::path::Path;

/// Writes the film from `opts.from_frame` over the tracked frames with the overlay, as MP4
/// at the film's own frame rate; `progress(done, total)` after each frame, `false` to cancel.
/// A cancelled or failed export leaves no file.
pub fn write_overlay(
    film: &Path,
    opts: &TrackOptions,
    overlay: &Overlay<'_>,
    out: &Path,
    progress: &mut dyn FnMut(usize, usize) -> bool,
) -> Result<(), ExportError> {
    let mut source = FilmSource::open(film).map_err(|e| ExportError::Invalid(e.to_string()))?;
    source.skip(opts.from_frame).map_err(|e| ExportError::Invalid(e.to_string()))?;
    let info = source.info().clone();
    let fps = overlay.tracked.header.fps;
    let mut sink: Box<dyn FrameSink> =
        Box::new(Mp4Writer::spawn(out, [info.width as u32, info.height as u32], fps)?);
    let mut frame = Frame::default();
    let n = overlay.tracked.frames.len();
    for i in 0..n {
        match source.next_frame(&mut frame) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => {
                sink.abandon();
                return Err(ExportError::Invalid(e.to_string()));
            }
        }
        let mut img = frame_image(&frame);
        overlay.draw(&mut img, i);
        if let Err(e) = sink.push(&img) {
            sink.abandon();
            return Err(e);
        }
        if !progress(i + 1, n) {
            sink.abandon();
            return Err(ExportError::Cancelled);
        }
    }
    sink.finish()
}
