//! GIF through the `gif` crate: a palette of 256 colours per frame (NeuQuant, no dithering:
//! flat areas stay flat and compress), looping for ever. After the first frame only the
//! pixels that changed are written: the rectangle round them, the rest of it transparent over
//! the frame before (a still table and panels then cost almost nothing). Sizes measured are in
//! docs/classroom.md.

use super::ExportError;
use super::video::FrameSink;
use image::RgbaImage;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// NeuQuant's sampling (1 best, 30 fastest): 10 is the gif crate's advice.
const QUANTIZE_SPEED: i32 = 10;
/// A pixel is written again when a channel moved by more than this (of 255) since it was last
/// written: below what the eye tells apart, above the shimmer of a moving camera's shading.
const CHANGE_TOLERANCE: u8 = 3;

pub struct GifWriter {
    encoder: gif::Encoder<BufWriter<File>>,
    path: PathBuf,
    size: [u16; 2],
    fps: f64,
    frames: u64,
    /// Every pixel's colour when it was last written (empty before the first frame): compared
    /// with this, not with the frame before, a slow drift is written once it adds up.
    reference: Vec<u8>,
}

impl GifWriter {
    pub fn create(path: &Path, size: [u32; 2], fps: f64) -> Result<GifWriter, ExportError> {
        let (Ok(w), Ok(h)) = (u16::try_from(size[0]), u16::try_from(size[1])) else {
            return Err(ExportError::Invalid(format!("{}x{} is not a GIF size (at most 65535 pixels a side)", size[0], size[1])));
        };
        let file = File::create(path).map_err(ExportError::io(path))?;
        let encode = |e: gif::EncodingError| ExportError::Encode { path: path.to_path_buf(), message: e.to_string() };
        let mut encoder = gif::Encoder::new(BufWriter::new(file), w, h, &[]).map_err(encode)?;
        encoder.set_repeat(gif::Repeat::Infinite).map_err(encode)?;
        Ok(GifWriter { encoder, path: path.to_path_buf(), size: [w, h], fps, frames: 0, reference: Vec::new() })
    }

    fn encode_error(&self, e: impl std::fmt::Display) -> ExportError {
        ExportError::Encode { path: self.path.clone(), message: e.to_string() }
    }
}

/// The delay of frame `k` in hundredths of a second (GIF's unit): rounded so that the frames'
/// delays add up to the video's length at any frame rate (30 frames/s: 3, 4, 3, 3, 4, 3, ...).
pub fn delay_cs(k: u64, fps: f64) -> u16 {
    let at = |k: u64| (k as f64 * 100.0 / fps).round() as u64;
    (at(k + 1) - at(k)).min(u16::MAX as u64) as u16
}

impl FrameSink for GifWriter {
    fn push(&mut self, frame: &RgbaImage) -> Result<(), ExportError> {
        if frame.dimensions() != (self.size[0] as u32, self.size[1] as u32) {
            return Err(self.encode_error(format!("a frame of {:?} pixels in a GIF of {:?}", frame.dimensions(), self.size)));
        }
        let mut f = if self.reference.is_empty() {
            self.reference = frame.as_raw().clone();
            let mut pixels = frame.as_raw().clone();
            gif::Frame::from_rgba_speed(self.size[0], self.size[1], &mut pixels, QUANTIZE_SPEED)
        } else {
            changes(&mut self.reference, frame)
        };
        f.dispose = gif::DisposalMethod::Keep;
        f.delay = delay_cs(self.frames, self.fps);
        self.frames += 1;
        self.encoder.write_frame(&f).map_err(|e| self.encode_error(e))
    }

    fn finish(self: Box<Self>) -> Result<(), ExportError> {
        let path = self.path.clone();
        let writer = self.encoder.into_inner().map_err(|e| ExportError::Encode { path: path.clone(), message: e.to_string() })?;
        let mut file = writer.into_inner().map_err(|e| ExportError::io(&path)(e.into_error()))?;
        file.flush().map_err(ExportError::io(&path))
    }

    fn abandon(self: Box<Self>) {
        let path = self.path.clone();
        drop(self);
        std::fs::remove_file(path).ok();
    }
}

/// The pixels of `frame` that moved away from `reference` (updated to them): the rectangle
/// round them, the others in it transparent (a transparent pixel where nothing moved).
fn changes(reference: &mut [u8], frame: &RgbaImage) -> gif::Frame<'static> {
    let (w, h) = frame.dimensions();
    let new = frame.as_raw();
    let moved: Vec<bool> = new
        .chunks_exact(4)
        .zip(reference.chunks_exact(4))
        .map(|(n, r)| (0..3).any(|c| n[c].abs_diff(r[c]) > CHANGE_TOLERANCE))
        .collect();
    let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
    for y in 0..h {
        for x in 0..w {
            if moved[(y * w + x) as usize] {
                (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
            }
        }
    }
    if x0 > x1 {
        let mut one = [0u8; 4];
        return gif::Frame::from_rgba_speed(1, 1, &mut one, QUANTIZE_SPEED);
    }
    let (bw, bh) = (x1 - x0 + 1, y1 - y0 + 1);
    let mut pixels = vec![0u8; (4 * bw * bh) as usize];
    for y in y0..=y1 {
        for x in x0..=x1 {
            let i = (y * w + x) as usize;
            if moved[i] {
                let o = (4 * ((y - y0) * bw + (x - x0))) as usize;
                pixels[o..o + 3].copy_from_slice(&new[4 * i..4 * i + 3]);
                pixels[o + 3] = 255;
                reference[4 * i..4 * i + 3].copy_from_slice(&new[4 * i..4 * i + 3]);
            }
        }
    }
    // Sizes fit in u16: the whole frame does (checked when the writer was made).
    let mut f = gif::Frame::from_rgba_speed(bw as u16, bh as u16, &mut pixels, QUANTIZE_SPEED);
    (f.left, f.top) = (x0 as u16, y0 as u16);
    f
}

#[cfg(test)]
mod tests {
    use super::delay_cs;

    #[test]
    fn delays_add_up_to_the_length() {
        assert!((0..25).all(|k| delay_cs(k, 25.0) == 4));
        let total: u32 = (0..30).map(|k| delay_cs(k, 30.0) as u32).sum();
        assert_eq!(total, 100);
        assert!((0..30).all(|k| (3..=4).contains(&delay_cs(k, 30.0))));
    }
}
