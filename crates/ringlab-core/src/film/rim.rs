//! A coloured mark's centre on the brightness, which H.264 keeps at full resolution while it
//! halves the colour's. Beside every mark lie the rim's edges and dark inner wall, which pull
//! a plain brightness centroid off; but the rim looks the same a little farther round the
//! ring, so its look there, carried back by the ring's own turn, is taken away first, which
//! leaves the mark alone. The centre is the centroid of what is left, of either sign: a mark
//! may be darker than the rim (it breaks the rim's bright edge) or brighter (it overhangs it).

use super::centre::Centre;
use super::find::ellipse_axes;
use super::frame::Plane;

/// The marks' circle as the image shows it: an affine image of the unit circle, mark `k` at
/// `k` quarter turns (A plus the two conjugate semi-diameters to marks 1 and 2). The rim's
/// top edges are circles about the same axis in the same plane, so a turn of the ring
/// carries them onto themselves.
#[derive(Clone, Copy, Debug)]
pub struct RingView {
    a: [f64; 2],
    /// Columns: the semi-diameters to mark 1 and to mark 2.
    m: [[f64; 2]; 2],
    inv: [[f64; 2]; 2],
}

/// A ring seen nearly on edge shows its rim as a line: no turn carries it onto itself there.
const THINNEST: f64 = 0.25;
/// The largest turn (radians) the rim is compared over: the neighbouring marks, a quarter turn
/// away, stay out of the comparison.
const LARGEST_TURN: f64 = 0.6;

impl RingView {
    /// From the four marks in order round the rim; `None` where the ring is seen on edge.
    pub fn from_marks(p: [[f64; 2]; 4]) -> Option<RingView> {
        let a = [
            (p[0][0] + p[1][0] + p[2][0] + p[3][0]) / 4.0,
            (p[0][1] + p[1][1] + p[2][1] + p[3][1]) / 4.0,
        ];
        let u = [(p[0][0] - p[2][0]) / 2.0, (p[0][1] - p[2][1]) / 2.0];
        let v = [(p[1][0] - p[3][0]) / 2.0, (p[1][1] - p[3][1]) / 2.0];
        let (major, minor) = ellipse_axes(u, v);
        if !(major > 0.0 && minor > THINNEST * major) {
            return None;
        }
        let det = u[0] * v[1] - v[0] * u[1];
        let inv = [[v[1] / det, -v[0] / det], [-u[1] / det, u[0] / det]];
        Some(RingView { a, m: [u, v], inv })
    }

    /// Where `p` goes when the ring turns by `angle` (radians) in its own plane.
    fn turned(&self, p: [f64; 2], angle: f64) -> [f64; 2] {
        let d = [p[0] - self.a[0], p[1] - self.a[1]];
        let q = [
            self.inv[0][0] * d[0] + self.inv[0][1] * d[1],
            self.inv[1][0] * d[0] + self.inv[1][1] * d[1],
        ];
        let (s, c) = angle.sin_cos();
        let r = [c * q[0] - s * q[1], s * q[0] + c * q[1]];
        [
            self.a[0] + self.m[0][0] * r[0] + self.m[1][0] * r[1],
            self.a[1] + self.m[0][1] * r[0] + self.m[1][1] * r[1],
        ]
    }

    /// Pixels along the rim per radian of turn at mark `k`.
    fn rim_speed(&self, k: usize) -> f64 {
        let (s, c) = (k as f64 * std::f64::consts::FRAC_PI_2).sin_cos();
        let t = [-s * self.m[0][0] + c * self.m[1][0], -s * self.m[0][1] + c * self.m[1][1]];
        t[0].hypot(t[1])
    }
}

/// Mark `k`'s centre on the brightness, starting at `start`: the centroid of the brightness
/// less the rim's look a turn either way, over a disc of `radius` px, iterated until it stays;
/// `None` off the frame, or more than `reach` px from the start.
pub fn rim_centre(
    luma: &Plane<'_>,
    ring: &RingView,
    k: usize,
    start: [f64; 2],
    radius: f64,
    reach: f64,
) -> Option<Centre> {
    // The rim a mark's width and a margin away on either side.
    let turn = (2.0 * radius + 1.0) / ring.rim_speed(k);
    if !(turn > 0.0 && turn <= LARGEST_TURN) {
        return None;
    }
    let half = (radius + reach).ceil() as i64 + 1;
    let (x0, y0) = (start[0].round() as i64, start[1].round() as i64);
    if !luma.holds(x0, y0, half) {
        return None;
    }
    let side = (2 * half + 1) as usize;
    let mut left = Vec::with_capacity(side * side);
    for j in y0 - half..=y0 + half {
        for i in x0 - half..=x0 + half {
            let p = [i as f64, j as f64];
            let (a, b) = (ring.turned(p, turn), ring.turned(p, -turn));
            let rim = (luma.bilinear(a[0], a[1])? + luma.bilinear(b[0], b[1])?) / 2.0;
            left.push(luma.at(i as usize, j as usize) - rim);
        }
    }
    let noise = {
        let mut v: Vec<f64> = left.iter().map(|r| r.abs()).collect();
        v.sort_by(|a, b| a.total_cmp(b));
        (1.4826 * v[v.len() / 2]).max(0.5)
    };
    let (mut cx, mut cy) = (start[0], start[1]);
    let mut result = None;
    for _ in 0..20 {
        let (mut sw, mut sx, mut sy, mut spread, mut n) = (0.0, 0.0, 0.0, 0.0, 0usize);
        for (idx, r) in left.iter().enumerate() {
            let i = x0 - half + (idx % side) as i64;
            let j = y0 - half + (idx / side) as i64;
            let (dx, dy) = (i as f64 - cx, j as f64 - cy);
            if dx * dx + dy * dy <= radius * radius {
                let w = r.abs();
                sw += w;
                sx += w * i as f64;
                sy += w * j as f64;
                spread += dx * dx + dy * dy;
                n += 1;
            }
        }
        if !(sw > 0.0) || n == 0 {
            return None;
        }
        let (nx, ny) = (sx / sw, sy / sw);
        let moved = (nx - cx).abs() + (ny - cy).abs();
        (cx, cy) = (nx, ny);
        if (cx - start[0]).hypot(cy - start[1]) > reach {
            return None;
        }
        result = Some(Centre {
            x: cx,
            y: cy,
            strength: sw / n as f64,
            chroma: [0.0; 2],
            sigma: noise * (spread / 2.0).sqrt() / sw,
            width: 0.0,
            coarse: false,
        });
        if moved < 1e-3 {
            break;
        }
    }
    result
}
