//! The four marks found in a whole frame (or its region of interest), with no prediction: the
//! first frame, and again after the ring was lost. Candidates are the strongest blobs of the
//! marks' kind; the four are those that lie as four points 90 degrees apart on one circle do
//! when projected: a parallelogram whose diagonals halve each other at A.

use super::centre::Polarity;
use super::frame::{CHROMA_OFFSET, Frame};
use super::{MarkStyle, Roi};

/// A blob that may be a mark.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Candidate {
    pub x: f64,
    pub y: f64,
    pub strength: f64,
    /// Colour blobs: the chroma's departure from its surroundings (Cb, Cr).
    pub chroma: [f64; 2],
}

/// Four marks found together, in cyclic order round the rim.
#[derive(Clone, Debug, PartialEq)]
pub struct Found {
    pub marks: [Candidate; 4],
    /// Dots: the radius (px) of the detector that found them.
    pub dot_radius: f64,
}

/// Sums over rectangles in O(1) (a summed-area table).
struct Integral {
    /// The table covers columns `x0..x0 + w` and rows `y0..y0 + h` of the plane.
    x0: usize,
    y0: usize,
    w: usize,
    sums: Vec<f64>,
}

impl Integral {
    fn new(data: &[u8], stride: usize, (x0, y0, w, h): (usize, usize, usize, usize)) -> Integral {
        let mut sums = vec![0.0; (w + 1) * (h + 1)];
        for y in 0..h {
            let mut row = 0.0;
            for x in 0..w {
                row += data[(y + y0) * stride + x + x0] as f64;
                sums[(y + 1) * (w + 1) + x + 1] = sums[y * (w + 1) + x + 1] + row;
            }
        }
        Integral { x0, y0, w, sums }
    }
    /// Mean over the square of half-size `r` at `(x, y)` (caller keeps it inside).
    fn mean(&self, x: usize, y: usize, r: usize) -> f64 {
        let (x, y) = (x - self.x0, y - self.y0);
        let (x0, y0, x1, y1) = (x - r, y - r, x + r + 1, y + r + 1);
        let s = |x: usize, y: usize| self.sums[y * (self.w + 1) + x];
        (s(x1, y1) - s(x0, y1) - s(x1, y0) + s(x0, y0)) / ((2 * r + 1) * (2 * r + 1)) as f64
    }
}

/// Local maxima of `score` over a `w x h` grid, at least `min` and at least `sep` apart.
fn peaks(
    score: &[f64],
    w: usize,
    b: (usize, usize, usize, usize),
    sep: usize,
    min: f64,
    keep: usize,
) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for y in (b.1 + sep)..(b.1 + b.3).saturating_sub(sep) {
        for x in (b.0 + sep)..(b.0 + b.2).saturating_sub(sep) {
            let v = score[y * w + x];
            if v < min {
                continue;
            }
            let mut best = true;
            'n: for j in y - sep..=y + sep {
                for i in x - sep..=x + sep {
                    let u = score[j * w + i];
                    if u > v || (u == v && (j, i) < (y, x)) {
                        best = false;
                        break 'n;
                    }
                }
            }
            if best {
                out.push((x, y));
            }
        }
    }
    out.sort_by(|a, b| score[b.1 * w + b.0].total_cmp(&score[a.1 * w + a.0]));
    out.truncate(keep);
    out
}

const KEEP: usize = 24;

/// Coloured blobs: chroma far from the mean of its neighbourhood.
fn colour_candidates(frame: &Frame, roi: &Roi) -> Vec<Candidate> {
    let (cw, ch) = (frame.chroma_width(), frame.chroma_height());
    let k = 5;
    let b = roi.bounds(2.0, cw, ch, k);
    let (icb, icr) = (Integral::new(&frame.cb, cw, b), Integral::new(&frame.cr, cw, b));
    let mut score = vec![0.0; cw * ch];
    let mut dev = vec![[0.0; 2]; cw * ch];
    for j in b.1 + k..(b.1 + b.3).saturating_sub(k) {
        for i in b.0 + k..(b.0 + b.2).saturating_sub(k) {
            let (x, y) = (2.0 * i as f64 + CHROMA_OFFSET, 2.0 * j as f64 + CHROMA_OFFSET);
            if !roi.contains(x, y) {
                continue;
            }
            let d = [
                frame.cb[j * cw + i] as f64 - icb.mean(i, j, k),
                frame.cr[j * cw + i] as f64 - icr.mean(i, j, k),
            ];
            score[j * cw + i] = d[0].hypot(d[1]);
            dev[j * cw + i] = d;
        }
    }
    peaks(&score, cw, b, 2, 12.0, KEEP)
        .into_iter()
        .map(|(i, j)| Candidate {
            x: 2.0 * i as f64 + CHROMA_OFFSET,
            y: 2.0 * j as f64 + CHROMA_OFFSET,
            strength: score[j * cw + i],
            chroma: dev[j * cw + i],
        })
        .collect()
}

/// Dots of about radius `r`: the mean over a box the dot fills against one three times wider.
fn dot_candidates(frame: &Frame, roi: &Roi, polarity: Polarity, r: f64) -> Vec<Candidate> {
    let (w, h) = (frame.width, frame.height);
    let inner = ((r * 0.7).round() as usize).max(1);
    let outer = ((r * 2.5).round() as usize).max(inner + 2);
    let b = roi.bounds(1.0, w, h, outer);
    let il = Integral::new(&frame.luma, w, b);
    let mut score = vec![0.0; w * h];
    for y in b.1 + outer..(b.1 + b.3).saturating_sub(outer) {
        for x in b.0 + outer..(b.0 + b.2).saturating_sub(outer) {
            if !roi.contains(x as f64, y as f64) {
                continue;
            }
            score[y * w + x] = polarity.signal(il.mean(x, y, outer), il.mean(x, y, inner));
        }
    }
    peaks(&score, w, b, inner.max(2), 8.0, KEEP)
        .into_iter()
        .map(|(x, y)| Candidate {
            x: x as f64,
            y: y as f64,
            strength: score[y * w + x],
            chroma: [0.0; 2],
        })
        .collect()
}

fn hue(c: &Candidate) -> f64 {
    c.chroma[1].atan2(c.chroma[0])
}

fn angle_between(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d)
}

/// The semi-major axis (px) of the ellipse through four points 90 degrees apart on a circle,
/// from the conjugate semi-diameters `d1`, `d2`: `a^2 + b^2 = |d1|^2 + |d2|^2`, `ab = |d1 x d2|`.
pub fn ellipse_axes(d1: [f64; 2], d2: [f64; 2]) -> (f64, f64) {
    let s = d1[0] * d1[0] + d1[1] * d1[1] + d2[0] * d2[0] + d2[1] * d2[1];
    let p = (d1[0] * d2[1] - d1[1] * d2[0]).abs();
    let (sum, diff) = ((s + 2.0 * p).sqrt(), (s - 2.0 * p).max(0.0).sqrt());
    ((sum + diff) / 2.0, (sum - diff) / 2.0)
}

/// The best four candidates that sit as the marks do, in cyclic order (clockwise on the
/// screen, y down), or `None`. `semi_major`: the range the ring's mark circle may have (px).
fn choose_four(c: &[Candidate], colours: bool, semi_major: (f64, f64)) -> Option<[Candidate; 4]> {
    let n = c.len();
    let mut best: Option<(f64, [usize; 4])> = None;
    for a in 0..n {
        for b in a + 1..n {
            for cc in b + 1..n {
                for d in cc + 1..n {
                    let q = [a, b, cc, d];
                    if colours
                        && q.iter().enumerate().any(|(i, &x)| {
                            q[i + 1..].iter().any(|&y| angle_between(hue(&c[x]), hue(&c[y])) < 0.6)
                        })
                    {
                        continue;
                    }
                    let s: Vec<f64> = q.iter().map(|&i| c[i].strength).collect();
                    let (lo, hi) =
                        s.iter().fold((f64::MAX, 0.0f64), |(l, h), &v| (l.min(v), h.max(v)));
                    if !colours && lo < 0.3 * hi {
                        continue;
                    }
                    // The three ways to pair them into diagonals.
                    for (p, r, t, u) in [(a, cc, b, d), (a, b, cc, d), (a, d, b, cc)] {
                        let m1 = [(c[p].x + c[r].x) / 2.0, (c[p].y + c[r].y) / 2.0];
                        let m2 = [(c[t].x + c[u].x) / 2.0, (c[t].y + c[u].y) / 2.0];
                        let d1 = [(c[p].x - c[r].x) / 2.0, (c[p].y - c[r].y) / 2.0];
                        let d2 = [(c[t].x - c[u].x) / 2.0, (c[t].y - c[u].y) / 2.0];
                        let (major, minor) = ellipse_axes(d1, d2);
                        if major < semi_major.0 || major > semi_major.1 || minor < 0.08 * major {
                            continue;
                        }
                        let miss = (m1[0] - m2[0]).hypot(m1[1] - m2[1]);
                        let allowed = 0.06 * major + 1.5;
                        if miss > allowed {
                            continue;
                        }
                        let score = s.iter().sum::<f64>() * (1.0 - 0.5 * miss / allowed);
                        if best.is_none_or(|(b, _)| score > b) {
                            best = Some((score, [p, t, r, u]));
                        }
                    }
                }
            }
        }
    }
    let (_, q) = best?;
    let mut four = q.map(|i| c[i]);
    let (ax, ay) =
        (four.iter().map(|m| m.x).sum::<f64>() / 4.0, four.iter().map(|m| m.y).sum::<f64>() / 4.0);
    four.sort_by(|m, n| (m.y - ay).atan2(m.x - ax).total_cmp(&(n.y - ay).atan2(n.x - ax)));
    // Mark 1: the reddest colour (hue nearest Cr up, Cb a little down); the first dot on the
    // screen's +x side otherwise (any start will do: the format leaves it open).
    let first = if colours {
        let red = 1.93;
        (0..4).min_by(|&i, &j| {
            angle_between(hue(&four[i]), red).total_cmp(&angle_between(hue(&four[j]), red))
        })?
    } else {
        0
    };
    four.rotate_left(first);
    Some(four)
}

/// The marks of a frame, or `None` when no four candidates sit as marks do.
pub fn find_marks(
    frame: &Frame,
    roi: &Roi,
    style: MarkStyle,
    semi_major: (f64, f64),
) -> Option<(MarkStyle, Found)> {
    find_marks_sized(frame, roi, style, semi_major, 0.0)
}

/// As [`find_marks`], for dots of a known radius (`known_dot` px; 0: not known).
pub fn find_marks_sized(
    frame: &Frame,
    roi: &Roi,
    style: MarkStyle,
    semi_major: (f64, f64),
    known_dot: f64,
) -> Option<(MarkStyle, Found)> {
    match style {
        MarkStyle::Colours => {
            let c = colour_candidates(frame, roi);
            choose_four(&c, true, semi_major).map(|marks| (style, Found { marks, dot_radius: 0.0 }))
        }
        MarkStyle::Dark | MarkStyle::Bright => {
            let polarity = if style == MarkStyle::Dark { Polarity::Dark } else { Polarity::Bright };
            let mut best: Option<(f64, Found)> = None;
            let radii: &[f64] = if known_dot > 0.0 { &[known_dot] } else { &[1.5, 2.5, 4.0, 6.0] };
            for &r in radii {
                let c = dot_candidates(frame, roi, polarity, r);
                if let Some(marks) = choose_four(&c, false, semi_major) {
                    let score = marks.iter().map(|m| m.strength).sum::<f64>();
                    if best.as_ref().is_none_or(|(b, _)| score > *b) {
                        best = Some((score, Found { marks, dot_radius: r }));
                    }
                }
            }
            best.map(|(_, f)| (style, f))
        }
        // Four blobs of four distinct hues on one circle: a table's grain varies along one.
        MarkStyle::Auto => find_marks(frame, roi, MarkStyle::Colours, semi_major)
            .or_else(|| find_marks(frame, roi, MarkStyle::Dark, semi_major))
            .or_else(|| find_marks(frame, roi, MarkStyle::Bright, semi_major)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_semi_axes_of_an_ellipse_from_conjugate_diameters() {
        // Circle radius 10 seen tilted: x squeezed to 0.5, points at 30 degrees apart from axes.
        let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let d1 = [5.0 * c, 10.0 * s];
        let d2 = [-5.0 * s, 10.0 * c];
        let (a, b) = ellipse_axes(d1, d2);
        assert!((a - 10.0).abs() < 1e-9 && (b - 5.0).abs() < 1e-9, "{a} {b}");
    }
}
