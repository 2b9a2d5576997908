//! An RGB raster with antialiased lines, filled rectangles and bitmap text, written as PNG.

use super::font::{GLYPH_H, GLYPH_W, glyph};
use std::io::Write;
use thiserror::Error;

pub type Rgb = [u8; 3];

pub const WHITE: Rgb = [255, 255, 255];
pub const BLACK: Rgb = [0, 0, 0];
pub const GREY: Rgb = [120, 120, 120];
pub const LIGHT_GREY: Rgb = [215, 215, 215];

#[derive(Debug, Error)]
pub enum PlotError {
    #[error("cannot write the image: {0}")]
    Io(#[from] std::io::Error),
    #[error("cannot encode the PNG: {0}")]
    Encode(#[from] png::EncodingError),
}

#[derive(Clone, Debug)]
pub struct Canvas {
    pub width: usize,
    pub height: usize,
    pixels: Vec<Rgb>,
}

impl Canvas {
    pub fn new(width: usize, height: usize, background: Rgb) -> Canvas {
        Canvas { width, height, pixels: vec![background; width * height] }
    }

    pub fn pixel(&self, x: usize, y: usize) -> Option<Rgb> {
        (x < self.width && y < self.height).then(|| self.pixels[y * self.width + x])
    }

    /// Blends `color` into pixel `(x, y)` with opacity `alpha` (0..1); outside: nothing.
    pub fn blend(&mut self, x: i64, y: i64, color: Rgb, alpha: f64) {
        if x < 0 || y < 0 || x as usize >= self.width || y as usize >= self.height || alpha <= 0.0 {
            return;
        }
        let a = alpha.min(1.0);
        let p = &mut self.pixels[y as usize * self.width + x as usize];
        for (c, &n) in p.iter_mut().zip(&color) {
            *c = (f64::from(*c) * (1.0 - a) + f64::from(n) * a).round() as u8;
        }
    }

    /// Fills `[x0, x1) x [y0, y1)` (pixel coordinates, clipped) with `color` at `alpha`.
    pub fn fill_rect(&mut self, x0: f64, y0: f64, x1: f64, y1: f64, color: Rgb, alpha: f64) {
        let (xa, xb) =
            (x0.min(x1).round().max(0.0) as i64, x0.max(x1).round().min(self.width as f64) as i64);
        let (ya, yb) =
            (y0.min(y1).round().max(0.0) as i64, y0.max(y1).round().min(self.height as f64) as i64);
        for y in ya..yb {
            for x in xa..xb {
                self.blend(x, y, color, alpha);
            }
        }
    }

    /// An antialiased line of `width` pixels from `a` to `b` (pixel centres at integer + 0.5).
    pub fn line(&mut self, a: (f64, f64), b: (f64, f64), width: f64, color: Rgb) {
        if !(a.0.is_finite() && a.1.is_finite() && b.0.is_finite() && b.1.is_finite()) {
            return;
        }
        let r = 0.5 * width.max(0.5);
        let (lo_x, hi_x) = (a.0.min(b.0) - r - 1.0, a.0.max(b.0) + r + 1.0);
        let (lo_y, hi_y) = (a.1.min(b.1) - r - 1.0, a.1.max(b.1) + r + 1.0);
        let (lo_x, hi_x) = (lo_x.max(-1.0) as i64, hi_x.min(self.width as f64 + 1.0) as i64);
        let (lo_y, hi_y) = (lo_y.max(-1.0) as i64, hi_y.min(self.height as f64 + 1.0) as i64);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len2 = dx * dx + dy * dy;
        for y in lo_y..=hi_y {
            for x in lo_x..=hi_x {
                let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                let t = if len2 > 0.0 {
                    (((px - a.0) * dx + (py - a.1) * dy) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let d = (px - a.0 - t * dx).hypot(py - a.1 - t * dy);
                let cover = (r + 0.5 - d).clamp(0.0, 1.0);
                if cover > 0.0 {
                    self.blend(x, y, color, cover);
                }
            }
        }
    }

    /// A filled, antialiased disc.
    pub fn disc(&mut self, c: (f64, f64), radius: f64, color: Rgb, alpha: f64) {
        let r = radius.max(0.5);
        for y in (c.1 - r - 1.0).floor() as i64..=(c.1 + r + 1.0).ceil() as i64 {
            for x in (c.0 - r - 1.0).floor() as i64..=(c.0 + r + 1.0).ceil() as i64 {
                let d = (x as f64 + 0.5 - c.0).hypot(y as f64 + 0.5 - c.1);
                self.blend(x, y, color, alpha * (r + 0.5 - d).clamp(0.0, 1.0));
            }
        }
    }

    /// Width in pixels of `text` at `scale`.
    pub fn text_width(text: &str, scale: usize) -> usize {
        text.chars().count() * (GLYPH_W + 1) * scale
    }

    /// Text height (cap height plus descenders) at `scale`.
    pub fn text_height(scale: usize) -> usize {
        GLYPH_H * scale
    }

    /// Draws `text` with its top-left corner at `(x, y)`.
    pub fn text(&mut self, x: f64, y: f64, text: &str, scale: usize, color: Rgb) {
        let (x0, y0) = (x.round() as i64, y.round() as i64);
        let s = scale.max(1) as i64;
        for (i, c) in text.chars().enumerate() {
            let gx = x0 + i as i64 * (GLYPH_W as i64 + 1) * s;
            for (row, bits) in glyph(c).iter().enumerate() {
                for col in 0..GLYPH_W {
                    if bits & (1 << (GLYPH_W - 1 - col)) != 0 {
                        for dy in 0..s {
                            for dx in 0..s {
                                self.blend(
                                    gx + col as i64 * s + dx,
                                    y0 + row as i64 * s + dy,
                                    color,
                                    1.0,
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    /// Draws `text` turned a quarter to the left (reading upward), its box's top-left at `(x, y)`.
    pub fn text_up(&mut self, x: f64, y: f64, text: &str, scale: usize, color: Rgb) {
        let w = Canvas::text_width(text, scale);
        let h = Canvas::text_height(scale);
        let mut tmp = Canvas::new(w, h, WHITE);
        tmp.text(0.0, 0.0, text, scale, color);
        for ty in 0..h {
            for tx in 0..w {
                if let Some(p) = tmp.pixel(tx, ty)
                    && p != WHITE
                {
                    self.blend(
                        x.round() as i64 + ty as i64,
                        y.round() as i64 + (w - 1 - tx) as i64,
                        p,
                        1.0,
                    );
                }
            }
        }
    }

    /// The image as PNG (8-bit RGB).
    pub fn write_png(&self, out: impl Write) -> Result<(), PlotError> {
        let mut enc = png::Encoder::new(out, self.width as u32, self.height as u32);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header()?;
        let data: Vec<u8> = self.pixels.iter().flatten().copied().collect();
        writer.write_image_data(&data)?;
        writer.finish()?;
        Ok(())
    }

    /// Writes the PNG to `path`.
    pub fn save(&self, path: &std::path::Path) -> Result<(), PlotError> {
        let file = std::fs::File::create(path)?;
        self.write_png(std::io::BufWriter::new(file))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_text_and_png_round_trip() {
        let mut c = Canvas::new(60, 30, WHITE);
        c.line((2.0, 2.0), (50.0, 2.0), 2.0, BLACK);
        assert_eq!(c.pixel(20, 2), Some(BLACK));
        assert_eq!(c.pixel(20, 10), Some(WHITE));
        c.text(2.0, 10.0, "Hi", 1, BLACK);
        // 'H' has its left column set from the top.
        assert_eq!(c.pixel(2, 10), Some(BLACK));
        let mut bytes = Vec::new();
        c.write_png(&mut bytes).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        let dec = png::Decoder::new(std::io::Cursor::new(bytes));
        let reader = dec.read_info().unwrap();
        assert_eq!((reader.info().width, reader.info().height), (60, 30));
    }
}
