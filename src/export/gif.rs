//! GIF through the `gif` crate: a palette of 256 colours per frame (NeuQuant, no dithering:
//! flat areas stay flat and compress), looping for ever. After the first frame only the
//! pixels that changed are written: the rectangle round them, the rest of it transparent over
//! the frame before (a still table and panels then cost almost nothing). A pixel whose shown
//! colour is far from the truth (a rare colour the first palette had no room for, such as a
//! small swatch of the retrograde red) is written again too, in a later frame's palette made
//! for fewer pixels. Sizes measured are in docs/classroom.md.

use super::ExportError;
use super::sink::FrameSink;
use image::RgbaImage;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// NeuQuant's sampling (1 best, 30 fastest): 10 is the gif crate's advice.
const QUANTIZE_SPEED: i32 = 10;
/// A pixel is written again when a channel moved by more than this (of 255) since it was last
/// written: below what the eye tells apart, above the shimmer of a moving camera's shading.
const CHANGE_TOLERANCE: u8 = 3;
/// ... or when what is shown is off from it by more than this (a colour the palette missed).
const SHOWN_TOLERANCE: u8 = 24;

pub struct GifWriter {
    encoder: gif::Encoder<BufWriter<File>>,
    path: PathBuf,
    size: [u16; 2],
    fps: f64,
    frames: u64,
    /// What each pixel should show and does show (RGBA; empty before the first frame).
    screen: Screen,
}

/// The GIF's picture so far.
#[derive(Default)]
struct Screen {
    /// Every pixel's true colour when it was last written: compared with this, not with the
    /// frame before, a slow drift is written once it adds up.
    reference: Vec<u8>,
    /// Its colour as the palette gave it.
    shown: Vec<u8>,
}

impl GifWriter {
    pub fn create(path: &Path, size: [u32; 2], fps: f64) -> Result<GifWriter, ExportError> {
        let (Ok(w), Ok(h)) = (u16::try_from(size[0]), u16::try_from(size[1])) else {
            return Err(ExportError::Invalid(format!(
                "{}x{} is not a GIF size (at most 65535 pixels a side)",
                size[0], size[1]
            )));
        };
        let file = File::create(path).map_err(ExportError::io(path))?;
        let encode = |e: gif::EncodingError| ExportError::Encode {
            path: path.to_path_buf(),
            message: e.to_string(),
        };
        let mut encoder = gif::Encoder::new(BufWriter::new(file), w, h, &[]).map_err(encode)?;
        encoder.set_repeat(gif::Repeat::Infinite).map_err(encode)?;
        Ok(GifWriter {
            encoder,
            path: path.to_path_buf(),
            size: [w, h],
            fps,
            frames: 0,
            screen: Screen::default(),
        })
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
            return Err(self.encode_error(format!(
                "a frame of {:?} pixels in a GIF of {:?}",
                frame.dimensions(),
                self.size
            )));
        }
        let mut f = self.screen.update(frame);
        f.dispose = gif::DisposalMethod::Keep;
        f.delay = delay_cs(self.frames, self.fps);
        self.frames += 1;
        self.encoder.write_frame(&f).map_err(|e| self.encode_error(e))
    }

    fn finish(self: Box<Self>) -> Result<(), ExportError> {
        let path = self.path.clone();
        let writer = self
            .encoder
            .into_inner()
            .map_err(|e| ExportError::Encode { path: path.clone(), message: e.to_string() })?;
        let mut file = writer.into_inner().map_err(|e| ExportError::io(&path)(e.into_error()))?;
        file.flush().map_err(ExportError::io(&path))
    }

    fn abandon(self: Box<Self>) {
        let path = self.path.clone();
        drop(self);
        std::fs::remove_file(path).ok();
    }
}

impl Screen {
    /// The GIF frame that brings the screen to `frame`: the rectangle round the pixels to
    /// write, the others in it transparent (the whole frame the first time; a transparent
    /// pixel where nothing is to be written).
    fn update(&mut self, frame: &RgbaImage) -> gif::Frame<'static> {
        let (w, h) = frame.dimensions();
        let new = frame.as_raw();
        let first = self.reference.is_empty();
        let off = |a: &[u8], b: &[u8], tol: u8| (0..3).any(|c| a[c].abs_diff(b[c]) > tol);
        let write: Vec<bool> = if first {
            vec![true; (w * h) as usize]
        } else {
            new.chunks_exact(4)
                .zip(self.reference.chunks_exact(4).zip(self.shown.chunks_exact(4)))
                .map(|(n, (r, s))| off(n, r, CHANGE_TOLERANCE) || off(n, s, SHOWN_TOLERANCE))
                .collect()
        };
        if first {
            self.reference = new.clone();
            self.shown = new.clone();
        }
        let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
        for y in 0..h {
            for x in 0..w {
                if write[(y * w + x) as usize] {
                    (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
                }
            }
        }
        if x0 > x1 {
            let mut one = [0u8; 4];
            return gif::Frame::from_rgba_speed(1, 1, &mut one, QUANTIZE_SPEED);
        }
        let (bw, bh) = (x1 - x0 + 1, y1 - y0 + 1);
        let at = |x: u32, y: u32| (y * w + x) as usize;
        let mut pixels = vec![0u8; (4 * bw * bh) as usize];
        for y in y0..=y1 {
            for x in x0..=x1 {
                let i = at(x, y);
                if write[i] {
                    let o = (4 * ((y - y0) * bw + (x - x0))) as usize;
                    pixels[o..o + 3].copy_from_slice(&new[4 * i..4 * i + 3]);
                    pixels[o + 3] = 255;
                }
            }
        }
        // Sizes fit in u16: the whole frame does (checked when the writer was made).
        let mut f = gif::Frame::from_rgba_speed(bw as u16, bh as u16, &mut pixels, QUANTIZE_SPEED);
        (f.left, f.top) = (x0 as u16, y0 as u16);
        let palette = f.palette.clone().unwrap_or_default();
        for y in y0..=y1 {
            for x in x0..=x1 {
                let i = at(x, y);
                if write[i] {
                    let k = 3 * f.buffer[((y - y0) * bw + (x - x0)) as usize] as usize;
                    self.reference[4 * i..4 * i + 3].copy_from_slice(&new[4 * i..4 * i + 3]);
                    if let Some(rgb) = palette.get(k..k + 3) {
                        self.shown[4 * i..4 * i + 3].copy_from_slice(rgb);
                    }
                }
            }
        }
        f
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Rgba;

    #[test]
    fn a_still_picture_settles_then_costs_a_transparent_pixel() {
        // Thousands of colours and a few pixels of the retrograde red: more than one palette holds.
        let img = RgbaImage::from_fn(300, 120, |x, y| {
            if x < 3 && y < 3 {
                Rgba([205, 35, 95, 255])
            } else {
                Rgba([(x % 256) as u8, (2 * y) as u8, ((x + y) % 256) as u8, 255])
            }
        });
        let mut screen = Screen::default();
        let first = screen.update(&img);
        assert_eq!(
            (first.width, first.height, first.transparent),
            (300, 120, None),
            "the whole first frame"
        );
        let mut sizes = Vec::new();
        for _ in 0..4 {
            let f = screen.update(&img);
            sizes.push((f.width, f.height));
        }
        assert_eq!(sizes.last(), Some(&(1, 1)), "nothing left to write: {sizes:?}");
        for (t, s) in img.as_raw().chunks_exact(4).zip(screen.shown.chunks_exact(4)) {
            assert!((0..3).all(|c| t[c].abs_diff(s[c]) <= SHOWN_TOLERANCE), "{t:?} shown as {s:?}");
        }
    }

    #[test]
    fn a_moved_pixel_is_written_alone() {
        let mut img = RgbaImage::from_pixel(50, 40, Rgba([200, 200, 190, 255]));
        let mut screen = Screen::default();
        screen.update(&img);
        img.put_pixel(20, 10, Rgba([10, 10, 10, 255]));
        img.put_pixel(22, 12, Rgba([203, 200, 190, 255]));
        let f = screen.update(&img);
        assert_eq!(
            (f.left, f.top, f.width, f.height),
            (20, 10, 1, 1),
            "a change of 3 levels is not written"
        );
    }

    #[test]
    fn delays_add_up_to_the_length() {
        assert!((0..25).all(|k| delay_cs(k, 25.0) == 4));
        let total: u32 = (0..30).map(|k| delay_cs(k, 30.0) as u32).sum();
        assert_eq!(total, 100);
        assert!((0..30).all(|k| (3..=4).contains(&delay_cs(k, 30.0))));
    }
}
