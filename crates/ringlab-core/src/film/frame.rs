//! One decoded frame as the codec stores it: brightness (luma) at full resolution, colour
//! (two chroma planes) at half resolution in each direction (4:2:0), as H.264 keeps them.
//! Marks are positioned on whichever plane carries them and named by the chroma's hue.

/// A frame's planes. Luma `width x height`; chroma `width/2 x height/2` (both even).
#[derive(Clone, Debug, Default)]
pub struct Frame {
    pub width: usize,
    pub height: usize,
    pub luma: Vec<u8>,
    /// Cb (blue difference), 128 = no colour.
    pub cb: Vec<u8>,
    /// Cr (red difference), 128 = no colour.
    pub cr: Vec<u8>,
}

/// Where chroma sample `(i, j)` sits in luma pixels: the centre of its 2x2 block, as ffmpeg's
/// own RGB to 4:2:0 conversion averages it (measured unbiased on the shared films, whose
/// streams are tagged "left" siting all the same).
pub const CHROMA_OFFSET: f64 = 0.5;

impl Frame {
    pub fn chroma_width(&self) -> usize {
        self.width / 2
    }
    pub fn chroma_height(&self) -> usize {
        self.height / 2
    }

    /// A frame from 8-bit RGB (a PNG, JPEG or TIFF frame): BT.601 limited-range YCbCr, the
    /// chroma averaged over 2x2 blocks as an encoder would. An odd last row or column is
    /// dropped.
    pub fn from_rgb(width: usize, height: usize, rgb: &[u8]) -> Frame {
        let (w, h) = (width & !1, height & !1);
        let mut luma = vec![0u8; w * h];
        let (cw, ch) = (w / 2, h / 2);
        let mut cb = vec![0u8; cw * ch];
        let mut cr = vec![0u8; cw * ch];
        let px = |x: usize, y: usize| {
            let i = 3 * (y * width + x);
            (rgb[i] as f64, rgb[i + 1] as f64, rgb[i + 2] as f64)
        };
        for y in 0..h {
            for x in 0..w {
                let (r, g, b) = px(x, y);
                luma[y * w + x] = (16.0 + 0.2568 * r + 0.5041 * g + 0.0979 * b).round() as u8;
            }
        }
        for j in 0..ch {
            for i in 0..cw {
                let (mut u, mut v) = (0.0, 0.0);
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let (r, g, b) = px(2 * i + dx, 2 * j + dy);
                    u += -0.1482 * r - 0.2910 * g + 0.4392 * b;
                    v += 0.4392 * r - 0.3678 * g - 0.0714 * b;
                }
                cb[j * cw + i] = (128.0 + u / 4.0).round().clamp(0.0, 255.0) as u8;
                cr[j * cw + i] = (128.0 + v / 4.0).round().clamp(0.0, 255.0) as u8;
            }
        }
        Frame { width: w, height: h, luma, cb, cr }
    }

    /// The frame as RGBA (for pictures and the overlay), chroma taken from its block.
    pub fn to_rgba(&self) -> Vec<u8> {
        let mut out = vec![255u8; self.width * self.height * 4];
        let cw = self.chroma_width();
        for y in 0..self.height {
            for x in 0..self.width {
                let l = 1.164 * (self.luma[y * self.width + x] as f64 - 16.0);
                let ci = (y / 2) * cw + x / 2;
                let u = self.cb[ci] as f64 - 128.0;
                let v = self.cr[ci] as f64 - 128.0;
                let o = 4 * (y * self.width + x);
                out[o] = (l + 1.596 * v).round().clamp(0.0, 255.0) as u8;
                out[o + 1] = (l - 0.392 * u - 0.813 * v).round().clamp(0.0, 255.0) as u8;
                out[o + 2] = (l + 2.017 * u).round().clamp(0.0, 255.0) as u8;
            }
        }
        out
    }
}

/// A plane of samples as floats, with a window reader that says when it leaves the plane.
pub struct Plane<'a> {
    pub data: &'a [u8],
    pub width: usize,
    pub height: usize,
}

impl Plane<'_> {
    #[inline]
    pub fn at(&self, x: usize, y: usize) -> f64 {
        self.data[y * self.width + x] as f64
    }
    /// Whether the square of half-size `r` around `(x, y)` lies inside.
    pub fn holds(&self, x: i64, y: i64, r: i64) -> bool {
        x - r >= 0 && y - r >= 0 && x + r < self.width as i64 && y + r < self.height as i64
    }
    /// The plane interpolated between its four nearest samples; `None` off the plane.
    pub fn bilinear(&self, x: f64, y: f64) -> Option<f64> {
        let (x0, y0) = (x.floor(), y.floor());
        if !(x0 >= 0.0
            && y0 >= 0.0
            && x0 + 1.0 < self.width as f64
            && y0 + 1.0 < self.height as f64)
        {
            return None;
        }
        let (fx, fy) = (x - x0, y - y0);
        let (i, j) = (x0 as usize, y0 as usize);
        Some(
            self.at(i, j) * (1.0 - fx) * (1.0 - fy)
                + self.at(i + 1, j) * fx * (1.0 - fy)
                + self.at(i, j + 1) * (1.0 - fx) * fy
                + self.at(i + 1, j + 1) * fx * fy,
        )
    }
}

impl Frame {
    pub fn luma_plane(&self) -> Plane<'_> {
        Plane { data: &self.luma, width: self.width, height: self.height }
    }
    pub fn cb_plane(&self) -> Plane<'_> {
        Plane { data: &self.cb, width: self.chroma_width(), height: self.chroma_height() }
    }
    pub fn cr_plane(&self) -> Plane<'_> {
        Plane { data: &self.cr, width: self.chroma_width(), height: self.chroma_height() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgb_round_trips_through_the_planes() {
        let (w, h) = (4, 2);
        let rgb: Vec<u8> = [200u8, 30, 40].repeat(w * h);
        let f = Frame::from_rgb(w, h, &rgb);
        let back = f.to_rgba();
        for (a, b) in back.chunks(4).zip(rgb.chunks(3)) {
            for c in 0..3 {
                assert!((a[c] as i32 - b[c] as i32).abs() <= 3, "{a:?} vs {b:?}");
            }
        }
        // A red patch: Cr well above 128, Cb below.
        assert!(f.cr[0] > 180 && f.cb[0] < 128);
    }
}
