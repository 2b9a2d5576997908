//! A mark's sub-pixel centre near a predicted position.
//!
//! - Coloured marks: a Gaussian blob fitted to both chroma planes at once, each with its own
//!   amplitude over a sloping background (variable projection: the linear numbers solved
//!   exactly for each centre and width, Gauss-Newton on those three). The chroma carries the
//!   mark alone: in brightness a coloured mark is faint beside the rim's dark inner wall and
//!   edges, which pull a brightness centroid off by a pixel. Each chroma sample is the mean of
//!   its 2x2 block, and the model is averaged the same way.
//! - Dots (dark or bright): the brightness centroid over a disc a little larger than the dot,
//!   against the median of the ring around that disc, iterated until it stays (as trackpy
//!   does). A disc fitted to the dot keeps the rim's edges out of it.
//!
//! Blur spreads a mark symmetrically about its mid-exposure position, so both estimate that.

use super::frame::{CHROMA_OFFSET, Frame, Plane};

/// A centre found, in luma pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Centre {
    pub x: f64,
    pub y: f64,
    /// The mark's contrast (chroma amplitude, or the dot's mean depth in grey levels).
    pub strength: f64,
    /// Colour marks: the fitted chroma amplitudes (Cb, Cr); dots: zero.
    pub chroma: [f64; 2],
    /// Standard error of the centre from the pixels' noise (px, each coordinate).
    pub sigma: f64,
    /// Colour marks: the blob's fitted width (px); dots: zero.
    pub width: f64,
    /// Colour marks: placed only to the nearest chroma sample (no blob could be fitted), to be
    /// placed on the brightness or not at all.
    pub coarse: bool,
}

impl Centre {
    /// Colour marks: the hue (radians in the Cb, Cr plane).
    pub fn hue(&self) -> f64 {
        self.chroma[1].atan2(self.chroma[0])
    }
}

const MIN_WIDTH: f64 = 0.5;
pub const MAX_WIDTH: f64 = 4.0;

/// The chroma window, the sloping background and the blob, for one centre and width.
struct ChromaWindow {
    /// Sample positions (luma px) relative to the window's origin, and their Cb, Cr.
    xs: Vec<[f64; 2]>,
    cb: Vec<f64>,
    cr: Vec<f64>,
}

impl ChromaWindow {
    fn new(frame: &Frame, x: f64, y: f64, half: i64) -> Option<ChromaWindow> {
        let (cbp, crp) = (frame.cb_plane(), frame.cr_plane());
        let ci = ((x - CHROMA_OFFSET) / 2.0).round() as i64;
        let cj = ((y - CHROMA_OFFSET) / 2.0).round() as i64;
        if !cbp.holds(ci, cj, half) {
            return None;
        }
        let n = ((2 * half + 1) * (2 * half + 1)) as usize;
        let mut w = ChromaWindow {
            xs: Vec::with_capacity(n),
            cb: Vec::with_capacity(n),
            cr: Vec::with_capacity(n),
        };
        for j in cj - half..=cj + half {
            for i in ci - half..=ci + half {
                w.xs.push([2.0 * i as f64 + CHROMA_OFFSET - x, 2.0 * j as f64 + CHROMA_OFFSET - y]);
                w.cb.push(cbp.at(i as usize, j as usize));
                w.cr.push(crp.at(i as usize, j as usize));
            }
        }
        Some(w)
    }

    /// The blob of width `s` at `(x0, y0)` (relative), averaged over each sample's 2x2 block.
    fn blob(&self, x0: f64, y0: f64, s: f64, out: &mut Vec<f64>) {
        let k = -0.5 / (s * s);
        out.clear();
        for p in &self.xs {
            let mut g = 0.0;
            for (ox, oy) in [(-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5)] {
                let (dx, dy) = (p[0] + ox - x0, p[1] + oy - y0);
                g += (k * (dx * dx + dy * dy)).exp();
            }
            out.push(g / 4.0);
        }
    }

    /// Residuals of the best linear fit (background plane + amplitude per plane) for this blob;
    /// the amplitudes too.
    fn residuals(&self, g: &[f64], res: &mut Vec<f64>) -> Option<[f64; 2]> {
        // Normal equations of the design [1, x, y, g], shared by both planes.
        let mut ata = [[0.0; 4]; 4];
        let mut atb = [[0.0; 4]; 2];
        for (i, p) in self.xs.iter().enumerate() {
            let row = [1.0, p[0], p[1], g[i]];
            for a in 0..4 {
                for b in 0..4 {
                    ata[a][b] += row[a] * row[b];
                }
                atb[0][a] += row[a] * self.cb[i];
                atb[1][a] += row[a] * self.cr[i];
            }
        }
        let m = nalgebra::Matrix4::from_fn(|r, c| ata[r][c]);
        let chol = m.cholesky()?;
        let cb = chol.solve(&nalgebra::Vector4::from(atb[0]));
        let cr = chol.solve(&nalgebra::Vector4::from(atb[1]));
        res.clear();
        for (i, p) in self.xs.iter().enumerate() {
            let row = nalgebra::Vector4::new(1.0, p[0], p[1], g[i]);
            res.push(self.cb[i] - row.dot(&cb));
            res.push(self.cr[i] - row.dot(&cr));
        }
        Some([cb[3], cr[3]])
    }
}

/// A coloured mark's centre from both chroma planes, starting at `(x, y)` and the blob's
/// width `width` (px), which may grow to `widest`; `None` where the window leaves the frame or
/// the fit runs off (more than `reach` px from the start).
pub fn colour_centre(
    frame: &Frame,
    (x, y): (f64, f64),
    (width, widest): (f64, f64),
    reach: f64,
) -> Option<Centre> {
    let win = ChromaWindow::new(frame, x, y, 4)?;
    let widest = widest.clamp(MIN_WIDTH, MAX_WIDTH);
    let mut p = [0.0, 0.0, width.clamp(MIN_WIDTH, widest)];
    let (mut g, mut r0, mut r1) = (Vec::new(), Vec::new(), Vec::new());
    let eval = |p: &[f64; 3], g: &mut Vec<f64>, r: &mut Vec<f64>| {
        win.blob(p[0], p[1], p[2], g);
        win.residuals(g, r)
    };
    let mut amp = eval(&p, &mut g, &mut r0)?;
    let mut jtj = nalgebra::Matrix3::zeros();
    for _ in 0..12 {
        // Forward differences: the model is smooth and cheap.
        let h = 0.02;
        let mut jac: Vec<[f64; 3]> = vec![[0.0; 3]; r0.len()];
        for k in 0..3 {
            let mut q = p;
            q[k] += h;
            eval(&q, &mut g, &mut r1)?;
            for (i, j) in jac.iter_mut().enumerate() {
                j[k] = (r1[i] - r0[i]) / h;
            }
        }
        jtj = nalgebra::Matrix3::zeros();
        let mut jtr = nalgebra::Vector3::zeros();
        for (i, j) in jac.iter().enumerate() {
            let jv = nalgebra::Vector3::from(*j);
            jtj += jv * jv.transpose();
            jtr += jv * r0[i];
        }
        let damped = jtj + nalgebra::Matrix3::from_diagonal(&jtj.diagonal()) * 1e-3;
        let step = damped.cholesky()?.solve(&(-jtr));
        let mut q = p;
        for k in 0..3 {
            q[k] += step[k].clamp(-1.0, 1.0);
        }
        q[2] = q[2].clamp(MIN_WIDTH, widest);
        let cost0: f64 = r0.iter().map(|v| v * v).sum();
        let mut r_new = Vec::new();
        let amp_new = eval(&q, &mut g, &mut r_new)?;
        let cost1: f64 = r_new.iter().map(|v| v * v).sum();
        if cost1 > cost0 {
            break;
        }
        let moved = (q[0] - p[0]).abs() + (q[1] - p[1]).abs();
        p = q;
        r0 = r_new;
        amp = amp_new;
        if moved < 1e-3 {
            break;
        }
    }
    if p[0].hypot(p[1]) > reach {
        return None;
    }
    let dof = (r0.len() as f64 - 11.0).max(1.0);
    let s2 = r0.iter().map(|v| v * v).sum::<f64>() / dof;
    let cov = jtj.try_inverse()?;
    let sigma = ((cov[(0, 0)] + cov[(1, 1)]) / 2.0 * s2).sqrt();
    Some(Centre {
        x: x + p[0],
        y: y + p[1],
        strength: amp[0].hypot(amp[1]),
        chroma: amp,
        sigma,
        width: p[2],
        coarse: false,
    })
}

/// Whether a dot is darker or brighter than what it sits on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Polarity {
    Dark,
    Bright,
}

impl Polarity {
    /// The dot's contrast as a positive signal.
    #[inline]
    pub fn signal(self, background: f64, value: f64) -> f64 {
        match self {
            Polarity::Dark => background - value,
            Polarity::Bright => value - background,
        }
    }
}

fn median(v: &mut [f64]) -> f64 {
    let n = v.len();
    v.sort_by(|a, b| a.total_cmp(b));
    if n % 2 == 1 { v[n / 2] } else { (v[n / 2 - 1] + v[n / 2]) / 2.0 }
}

/// A dot's centre: the signal's centroid over a disc of radius `disc` round the estimate,
/// against the median of the ring 1.5 px beyond it, iterated.
pub fn dot_centre(
    luma: &Plane<'_>,
    polarity: Polarity,
    x: f64,
    y: f64,
    disc: f64,
    reach: f64,
) -> Option<Centre> {
    let (mut cx, mut cy) = (x, y);
    let outer = disc + 1.5;
    let r = outer.ceil() as i64 + 1;
    let mut ring = Vec::with_capacity(((2 * r + 1) * (2 * r + 1)) as usize);
    let mut result = None;
    for _ in 0..10 {
        let (xi, yi) = (cx.round() as i64, cy.round() as i64);
        if !luma.holds(xi, yi, r) {
            return None;
        }
        ring.clear();
        for j in yi - r..=yi + r {
            for i in xi - r..=xi + r {
                let d2 = (i as f64 - cx).powi(2) + (j as f64 - cy).powi(2);
                if d2 > disc * disc && d2 <= outer * outer {
                    ring.push(luma.at(i as usize, j as usize));
                }
            }
        }
        if ring.len() < 8 {
            return None;
        }
        let bg = median(&mut ring);
        for v in ring.iter_mut() {
            *v = (*v - bg).abs();
        }
        let noise = (1.4826 * median(&mut ring)).max(0.5);
        let (mut sw, mut sx, mut sy, mut n) = (0.0, 0.0, 0.0, 0usize);
        let mut spread = 0.0;
        for j in yi - r..=yi + r {
            for i in xi - r..=xi + r {
                let (dx, dy) = (i as f64 - cx, j as f64 - cy);
                if dx * dx + dy * dy <= disc * disc {
                    let w = polarity.signal(bg, luma.at(i as usize, j as usize)).max(0.0);
                    sw += w;
                    sx += w * i as f64;
                    sy += w * j as f64;
                    spread += dx * dx + dy * dy;
                    n += 1;
                }
            }
        }
        if sw <= 0.0 || n == 0 {
            return None;
        }
        let (nx, ny) = (sx / sw, sy / sw);
        let moved = (nx - cx).abs() + (ny - cy).abs();
        cx = nx;
        cy = ny;
        // Each pixel's noise moves the centroid by (x_i - x) / W; half the spread per axis.
        let sigma = noise * (spread / 2.0).sqrt() / sw;
        result = Some(Centre {
            x: cx,
            y: cy,
            strength: sw / n as f64,
            chroma: [0.0; 2],
            sigma,
            width: 0.0,
            coarse: false,
        });
        if moved < 1e-3 {
            break;
        }
    }
    let c = result?;
    ((c.x - x).hypot(c.y - y) <= reach).then_some(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame of grey metal with one blurred coloured disc drawn at a sub-pixel centre.
    fn frame_with_disc(cx: f64, cy: f64, rgb: [f64; 3], dark_edge: bool) -> Frame {
        let (w, h) = (64, 64);
        let mut img = vec![0u8; w * h * 3];
        for y in 0..h {
            for x in 0..w {
                let mut c = [150.0, 150.0, 155.0];
                if dark_edge && x as f64 > cx + 4.0 {
                    c = [60.0, 60.0, 62.0];
                }
                // Area of the disc (radius 2) in the pixel, by 8x8 sampling.
                let mut cover = 0.0;
                for sy in 0..8 {
                    for sx in 0..8 {
                        let px = x as f64 + (sx as f64 + 0.5) / 8.0 - 0.5;
                        let py = y as f64 + (sy as f64 + 0.5) / 8.0 - 0.5;
                        if (px - cx).hypot(py - cy) <= 2.0 {
                            cover += 1.0 / 64.0;
                        }
                    }
                }
                for k in 0..3 {
                    img[3 * (y * w + x) + k] =
                        (c[k] * (1.0 - cover) + rgb[k] * cover).round() as u8;
                }
            }
        }
        Frame::from_rgb(w, h, &img)
    }

    #[test]
    fn a_coloured_disc_is_found_to_a_fifth_of_a_pixel_beside_a_dark_edge() {
        for (cx, cy) in [(30.3, 31.7), (32.5, 29.25), (31.0, 33.9)] {
            let f = frame_with_disc(cx, cy, [220.0, 30.0, 30.0], true);
            let c = colour_centre(&f, (cx + 0.8, cy - 0.7), (1.2, MAX_WIDTH), 4.0).expect("found");
            assert!((c.x - cx).hypot(c.y - cy) < 0.2, "({cx}, {cy}) -> ({}, {})", c.x, c.y);
            assert!(c.chroma[1] > 20.0, "red: Cr up, {:?}", c.chroma);
        }
    }

    #[test]
    fn a_dark_dot_is_found_to_a_tenth_of_a_pixel() {
        for (cx, cy) in [(30.3, 31.7), (32.5, 29.25)] {
            let f = frame_with_disc(cx, cy, [20.0, 20.0, 20.0], false);
            let c = dot_centre(&f.luma_plane(), Polarity::Dark, cx - 0.9, cy + 0.6, 3.0, 4.0)
                .expect("found");
            assert!((c.x - cx).hypot(c.y - cy) < 0.1, "({cx}, {cy}) -> ({}, {})", c.x, c.y);
            assert!(c.sigma > 0.0 && c.sigma < 0.2, "sigma {}", c.sigma);
        }
    }

    #[test]
    fn nothing_is_found_off_the_frame() {
        let f = frame_with_disc(30.0, 30.0, [20.0, 20.0, 20.0], false);
        assert!(dot_centre(&f.luma_plane(), Polarity::Dark, 1.0, 1.0, 3.0, 4.0).is_none());
        assert!(colour_centre(&f, (1.0, 62.0), (1.2, MAX_WIDTH), 4.0).is_none());
    }
}
