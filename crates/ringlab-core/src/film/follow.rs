//! Following the four marks from frame to frame: each mark predicted from its last frames
//! (A extrapolated, the mark's offset from A in angle and length, which stay smooth while the
//! ring spins fast), a hidden mark from the other three (the parallelogram), searched for
//! near there alone, its centre refined, then kept only where it is as strong as the mark
//! was and, for colours, of its hue. A mark that cannot be told from another is left out and
//! counted, never swapped.

use super::centre::{Centre, MAX_WIDTH, Polarity, colour_centre, dot_centre};
use super::choice::{Choice, blend};
use super::find::{Found, find_marks_sized};
use super::frame::{CHROMA_OFFSET, Frame};
use super::phase::Figure;
use super::rim::{RingView, rim_centre};
use super::tuning::FollowTuning;
use super::{MarkStyle, Roi};

/// What the follower looks for and where: the marks' style, the region, and the range of
/// the marks' semi-major axis (px).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Search {
    pub style: MarkStyle,
    pub roi: Roi,
    pub range: (f64, f64),
}
use crate::recording::FrameMarks;

/// What one frame gave.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameResult {
    pub marks: FrameMarks,
    /// Standard error of each centre found (px, per coordinate).
    pub sigma: [Option<f64>; 4],
    /// Marks left out because another mark claimed the same place.
    pub ambiguous: usize,
    /// Dots found anew with no mark followed: their numbering is a guess until the ring's
    /// turning settles it (`join`).
    pub new_numbering: bool,
    /// Colours: the hue each mark found showed (radians in the Cb, Cr plane).
    pub hues: [Option<f64>; 4],
}

#[derive(Clone, Debug)]
struct MarkState {
    /// Last positions found, newest last, with their frame index.
    history: Vec<(u64, [f64; 2])>,
    /// Typical strength of this mark when seen.
    strength: f64,
    /// Colour marks: the hue (radians in the Cb, Cr plane): the medoid of `hues`.
    hue: f64,
    /// Colour marks: the hues it showed where the four were found together, newest last.
    hues: Vec<f64>,
    /// Colour marks: the blob's typical fitted width (px); `None` until first fitted.
    width: Option<f64>,
}

/// The follower's state between frames.
pub struct Follower {
    style: MarkStyle,
    polarity: Polarity,
    /// Dots: the disc (px) the centroid is taken over.
    disc: f64,
    /// Dots: the discs tried beside it, and the running sum of the marks' parallelogram gap
    /// squared that each gives (the smallest error is the disc to use: `error`).
    discs: [f64; DISCS],
    disc_gaps: [f64; DISCS],
    disc_frames: usize,
    marks: [MarkState; 4],
    /// A (the marks' centre) by frame, newest last.
    centres: Vec<(u64, [f64; 2])>,
    /// Where the marks may be, and the range of the marks' semi-major axis (px).
    roi: Roi,
    range: (f64, f64),
    /// The marks' semi-major axis when last all found (px).
    size: f64,
    /// Colours: for each mark, its chroma centre or its centre on the brightness.
    choice: Choice,
    /// Times the four were found anew in a frame (after a loss or at the start).
    pub refound: usize,
    /// The marks' ellipse in the last frame with all four, and that frame.
    figure: Option<(u64, Figure)>,
}

const HISTORY: usize = 4;
/// Colours: the hues a mark showed when found anew, kept for its own (their medoid): one from
/// a blur (the ring acquired on edge) or a look-alike does not carry it.
const HUES: usize = 9;
/// Colours: a mark looked for round the whole ring meets more look-alikes than one followed,
/// and is taken only with a hue this close to its own (radians; a followed mark: 0.6),
const WIDE_HUE: f64 = 0.35;
/// not this near (px) a mark found (each chroma sample is weighed against a ring of samples
/// 4 away, 8 px: beside a mark, that ring takes in its colour and the difference shows its
/// complement),
const FRINGE: f64 = 10.0;
/// and not where the marks found would spread wider than this many times the ring's size.
const WIDER: f64 = 1.15;
/// Colours: the brightness centre may lie this far (px) from the chroma's.
const REACH: f64 = 3.0;
/// A coloured mark's blob may be fitted up to this many times its typical width.
const WIDEST: f64 = 1.6;
/// Discs tried: the dot's radius as first measured plus these (px). The parallelogram's gap
/// cannot see an error common to the four marks (the light's side darkens each dot alike), and
/// a disc inside the dot's blurred edge has one: none is tried inside it.
const DISC_MARGINS: [f64; DISCS] = [0.25, 0.75, 1.25, 1.75, 2.5];
const DISCS: usize = 5;
/// Frames of the running sums' memory.
const DISC_MEMORY: f64 = 100.0;

/// The angle of `angles` nearest the others in all (the median of a circle's values); of
/// those as near, the first: two values keep the older.
fn medoid(angles: &[f64]) -> f64 {
    let spread = |a: f64| angles.iter().map(|&b| angle_between(a, b)).sum::<f64>();
    let mut best = (f64::INFINITY, 0.0);
    for &a in angles {
        let s = spread(a);
        if s < best.0 - 1e-9 {
            best = (s, a);
        }
    }
    best.1
}

fn angle_between(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d)
}

fn unwrap(reference: f64, a: f64) -> f64 {
    reference + (a - reference + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
        - std::f64::consts::PI
}

/// The centre of four marks from what was found: the mean of an opposite pair's midpoints.
pub fn centre_of(marks: &FrameMarks) -> Option<[f64; 2]> {
    let mid = |a: [f64; 2], b: [f64; 2]| [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
    match (
        marks[0].zip(marks[2]).map(|(a, b)| mid(a, b)),
        marks[1].zip(marks[3]).map(|(a, b)| mid(a, b)),
    ) {
        (Some(m), Some(n)) => Some(mid(m, n)),
        (m, n) => m.or(n),
    }
}

/// The semi-major axis (px) of the ellipse through the marks found, with the marks a quarter
/// turn apart on it (an affine view of the mark circle), from three marks or four; from two,
/// the least it can be. In every pose it is the ring's size: a circle seen from afar keeps
/// the diameter parallel to the image whatever its tilt.
pub fn least_semi_major(marks: &FrameMarks) -> Option<f64> {
    let half = |p: [f64; 2], q: [f64; 2]| [(p[0] - q[0]) / 2.0, (p[1] - q[1]) / 2.0];
    let seen = marks.iter().filter(|m| m.is_some()).count();
    match seen {
        4 => {
            let [a, b, c, d] = marks.map(|m| m.unwrap_or_default());
            Some(super::find::ellipse_axes(half(a, c), half(b, d)).0)
        }
        3 => {
            // Conjugate semi-diameters: from an opposite pair's midpoint to its mark and to
            // the mark between.
            let k = (0..4).find(|&k| marks[k].is_some() && marks[(k + 2) % 4].is_some())?;
            let (a, c) = (marks[k]?, marks[(k + 2) % 4]?);
            let m = [(a[0] + c[0]) / 2.0, (a[1] + c[1]) / 2.0];
            let b = marks[(k + 1) % 4].or(marks[(k + 3) % 4])?;
            Some(super::find::ellipse_axes(half(a, c), [b[0] - m[0], b[1] - m[1]]).0)
        }
        2 => {
            let k: Vec<usize> = (0..4).filter(|&k| marks[k].is_some()).collect();
            let (p, q) = (marks[k[0]]?, marks[k[1]]?);
            let d = (p[0] - q[0]).hypot(p[1] - q[1]);
            Some(if (k[1] - k[0]).is_multiple_of(2) {
                d / 2.0
            } else {
                d / std::f64::consts::SQRT_2
            })
        }
        _ => None,
    }
}

impl Follower {
    /// Starts from four marks found in frame `index`.
    pub fn new(
        search: Search,
        found: &Found,
        frame: &Frame,
        index: u64,
        tuning: &FollowTuning,
    ) -> Follower {
        let Search { style, roi, range } = search;
        debug_assert_eq!(tuning.disc_margins, DISC_MARGINS);
        let polarity = if style == MarkStyle::Bright { Polarity::Bright } else { Polarity::Dark };
        let disc = if style == MarkStyle::Colours {
            0.0
        } else {
            // The four are alike: the middle of their sizes, past a neighbour that widens one.
            let mut r: Vec<f64> = found
                .marks
                .iter()
                .map(|m| measure_dot(frame, polarity, m, found.dot_radius))
                .collect();
            r.sort_by(|a, b| a.total_cmp(b));
            (r[1] + r[2]) / 2.0
        };
        let discs = DISC_MARGINS.map(|m| disc + m);
        let disc = discs[1];
        let marks = found.marks.map(|c| MarkState {
            history: vec![(index, [c.x, c.y])],
            strength: 0.0,
            hue: c.chroma[1].atan2(c.chroma[0]),
            hues: Vec::new(),
            width: None,
        });
        let d1 = [
            (found.marks[0].x - found.marks[2].x) / 2.0,
            (found.marks[0].y - found.marks[2].y) / 2.0,
        ];
        let d2 = [
            (found.marks[1].x - found.marks[3].x) / 2.0,
            (found.marks[1].y - found.marks[3].y) / 2.0,
        ];
        let size = super::find::ellipse_axes(d1, d2).0;
        let mut f = Follower {
            style,
            polarity,
            disc,
            discs,
            disc_gaps: [0.0; DISCS],
            disc_frames: 0,
            marks,
            centres: Vec::new(),
            roi,
            range,
            size,
            choice: Choice::default(),
            refound: 0,
            figure: None,
        };
        for k in 0..4 {
            if let Some(c) = f.learn(frame, &found.marks[k], k) {
                f.marks[k].history = vec![(index, [c.x, c.y])];
            }
        }
        let first: FrameMarks = std::array::from_fn(|k| Some(f.marks[k].history[0].1));
        if let Some(a) = centre_of(&first) {
            f.centres.push((index, a));
        }
        f
    }

    /// Mark `k`'s strength and, for colours, its hue and width, learnt from a mark found
    /// (`c`) by the same measure as later frames.
    fn learn(&mut self, frame: &Frame, c: &super::find::Candidate, k: usize) -> Option<Centre> {
        self.marks[k].strength = c.strength;
        let centre = self.centre_at(frame, c.x, c.y, k, 4.0)?;
        let m = &mut self.marks[k];
        m.strength = centre.strength;
        if self.style == MarkStyle::Colours {
            m.width = Some(centre.width);
        }
        self.learn_hue(&centre, k);
        Some(centre)
    }

    /// Colours: the hue mark `k` showed (`centre`) added to those it is known by.
    fn learn_hue(&mut self, centre: &Centre, k: usize) {
        if self.style != MarkStyle::Colours {
            return;
        }
        let m = &mut self.marks[k];
        m.hues.push(centre.hue());
        if m.hues.len() > HUES {
            m.hues.remove(0);
        }
        m.hue = medoid(&m.hues);
    }

    /// Where each mark was last found, and for colours its hue then: the result of the frame
    /// the ring was acquired in.
    pub fn acquired(&self) -> FrameResult {
        FrameResult {
            marks: std::array::from_fn(|k| self.marks[k].history.last().map(|h| h.1)),
            hues: std::array::from_fn(|k| {
                (self.style == MarkStyle::Colours).then_some(self.marks[k].hue)
            }),
            ..FrameResult::default()
        }
    }

    /// Dots: each disc tried on the four marks found, its parallelogram gap added to its
    /// running sum; the disc with the smallest sum is taken from then on.
    fn choose_disc(&mut self, frame: &Frame, marks: &FrameMarks) {
        if self.style == MarkStyle::Colours {
            return;
        }
        let [Some(a), Some(b), Some(c), Some(d)] = *marks else { return };
        let l = frame.luma_plane();
        let keep = 1.0 - 1.0 / DISC_MEMORY;
        for (i, &disc) in self.discs.iter().enumerate() {
            let at = |p: [f64; 2]| dot_centre(&l, self.polarity, p[0], p[1], disc, 3.0);
            let gap = match (at(a), at(b), at(c), at(d)) {
                (Some(a), Some(b), Some(c), Some(d)) => {
                    ((a.x + c.x - b.x - d.x) / 2.0).powi(2)
                        + ((a.y + c.y - b.y - d.y) / 2.0).powi(2)
                }
                _ => 100.0,
            };
            self.disc_gaps[i] = keep * self.disc_gaps[i] + gap;
        }
        self.disc_frames += 1;
        if self.disc_frames >= 10 {
            let best = (0..DISCS)
                .min_by(|&i, &j| self.disc_gaps[i].total_cmp(&self.disc_gaps[j]))
                .expect("discs");
            self.disc = self.discs[best];
        }
    }

    /// Whether mark `k` was found in the two frames before `index` (its motion is known).
    fn moving(&self, k: usize, index: u64) -> bool {
        let h = &self.marks[k].history;
        h.len() >= 2 && h[h.len() - 1].0 + 1 == index && h[h.len() - 2].0 + 2 == index
    }

    /// The four found anew near where the ring was last, numbered as before: colours by their
    /// hue; dots by the rotation of the numbers that puts them nearest where they were last,
    /// where one rotation is clearly the best, else as found (dots found anew with no mark
    /// followed are numbered again from the ring's turning afterwards: `join`).
    fn find_again(&self, frame: &Frame, index: u64) -> Option<Found> {
        let last: Vec<(usize, [f64; 2])> = (0..4)
            .filter_map(|k| {
                self.marks[k].history.last().filter(|h| index - h.0 <= 8).map(|h| (k, h.1))
            })
            .collect();
        let roi = if last.is_empty() {
            self.roi
        } else {
            let (cx, cy) = (
                last.iter().map(|p| p.1[0]).sum::<f64>() / last.len() as f64,
                last.iter().map(|p| p.1[1]).sum::<f64>() / last.len() as f64,
            );
            let r = 2.0 * self.size + 30.0;
            Roi { x: (cx - r).max(0.0), y: (cy - r).max(0.0), width: 2.0 * r, height: 2.0 * r }
        };
        let range = if self.size > 0.0 { (0.75 * self.size, 1.33 * self.size) } else { self.range };
        let known = if self.style == MarkStyle::Colours { 0.0 } else { (self.disc - 1.0).max(1.0) };
        let (_, found) = find_marks_sized(frame, &roi, self.style, range, known)?;
        // Four found anew must sit where the ring was: its centre moves far less than its size
        // in the few frames it was lost.
        if !last.is_empty() {
            let n = last.len() as f64;
            let was = [
                last.iter().map(|p| p.1[0]).sum::<f64>() / n,
                last.iter().map(|p| p.1[1]).sum::<f64>() / n,
            ];
            let now = [
                found.marks.iter().map(|m| m.x).sum::<f64>() / 4.0,
                found.marks.iter().map(|m| m.y).sum::<f64>() / 4.0,
            ];
            let reach = if last.len() == 4 { 0.5 } else { 1.2 } * self.size + 10.0;
            if (was[0] - now[0]).hypot(was[1] - now[1]) > reach {
                return None;
            }
        }
        let cost = |rot: usize| -> f64 {
            let mut s = 0.0;
            for k in 0..4 {
                let c = &found.marks[(k + rot) % 4];
                s += match self.style {
                    MarkStyle::Colours => {
                        angle_between(c.chroma[1].atan2(c.chroma[0]), self.marks[k].hue)
                    }
                    _ => last
                        .iter()
                        .find(|p| p.0 == k)
                        .map_or(0.0, |p| (p.1[0] - c.x).hypot(p.1[1] - c.y)),
                };
            }
            s
        };
        let mut costs: Vec<(f64, usize)> = (0..4).map(|r| (cost(r), r)).collect();
        costs.sort_by(|a, b| a.0.total_cmp(&b.0));
        if costs[0].0 > 0.5 * costs[1].0 {
            if self.style == MarkStyle::Colours {
                return None;
            }
            costs[0].1 = 0;
        }
        let mut marks = found.marks;
        marks.rotate_left(costs[0].1);
        Some(Found { marks, dot_radius: found.dot_radius })
    }

    fn centre_at(&self, frame: &Frame, x: f64, y: f64, k: usize, reach: f64) -> Option<Centre> {
        match self.style {
            MarkStyle::Colours => {
                // A blob far wider than the mark has been is the rim or the table's grain the
                // fit ran to (small marks in a compressed film): the width stays near the mark's.
                let widths = match self.marks[k].width {
                    Some(w) => (w, (WIDEST * w).max(1.0)),
                    None => (1.2, MAX_WIDTH),
                };
                colour_centre(frame, (x, y), widths, reach)
            }
            _ => dot_centre(&frame.luma_plane(), self.polarity, x, y, self.disc, reach),
        }
    }

    /// The camera moved between the last frame and the next: what the follower holds of
    /// the past frames is carried into the next frame's image by `moved` (a rigid motion of
    /// the image turning it by `turn_rad`), so that its predictions follow the ring and not
    /// the camera.
    pub fn follow_camera(&mut self, moved: &dyn Fn([f64; 2]) -> [f64; 2], turn_rad: f64) {
        for m in &mut self.marks {
            for (_, p) in &mut m.history {
                *p = moved(*p);
            }
        }
        for (_, c) in &mut self.centres {
            *c = moved(*c);
        }
        if let Some((_, f)) = &mut self.figure {
            *f = f.turned(turn_rad);
        }
    }

    /// Where mark `k` should be in frame `index`, and how far it may be from there.
    fn predict(&self, k: usize, index: u64) -> Option<([f64; 2], f64)> {
        let h = &self.marks[k].history;
        let &(last_i, last) = h.last()?;
        let gap = index.saturating_sub(last_i);
        if gap == 0 || gap > 3 {
            return None;
        }
        let centre = |i: u64| self.centres.iter().find(|c| c.0 == i).map(|c| c.1);
        // Offsets from A in polar form, where A was known, at consecutive frames.
        let recent: Vec<(u64, [f64; 2], [f64; 2])> =
            h.iter().rev().take(3).filter_map(|&(i, p)| centre(i).map(|a| (i, p, a))).collect();
        let consecutive = recent.windows(2).all(|w| w[0].0 == w[1].0 + 1);
        let step_size = if h.len() >= 2 {
            let p = h[h.len() - 2].1;
            (last[0] - p[0]).hypot(last[1] - p[1]) / (last_i - h[h.len() - 2].0) as f64
        } else {
            6.0
        };
        let gate = (4.0 + 0.6 * step_size * gap as f64).min(20.0);
        if recent.len() >= 2 && consecutive && recent[0].0 == last_i {
            let g = gap as f64;
            let polar = |(_, p, a): &(u64, [f64; 2], [f64; 2])| {
                let o = [p[0] - a[0], p[1] - a[1]];
                (o[1].atan2(o[0]), o[0].hypot(o[1]))
            };
            let (t1, r1) = polar(&recent[0]);
            let (t2, r2) = polar(&recent[1]);
            let t2 = unwrap(t1, t2);
            let (a1, a2) = (recent[0].2, recent[1].2);
            let (theta, radius, a) = if recent.len() == 3 {
                let (t3, _) = polar(&recent[2]);
                let t3 = unwrap(t2, t3);
                let a3 = recent[2].2;
                // Quadratic in the angle, linear in the length, quadratic in A.
                let d1 = t1 - t2;
                let d2 = t1 - 2.0 * t2 + t3;
                let theta = t1 + g * d1 + 0.5 * g * (g + 1.0) * d2;
                let a: [f64; 2] = std::array::from_fn(|c| {
                    a1[c]
                        + g * (a1[c] - a2[c])
                        + 0.5 * g * (g + 1.0) * (a1[c] - 2.0 * a2[c] + a3[c])
                });
                (theta, r1 + g * (r1 - r2), a)
            } else {
                let a: [f64; 2] = std::array::from_fn(|c| a1[c] + g * (a1[c] - a2[c]));
                (t1 + g * (t1 - t2), r1 + g * (r1 - r2), a)
            };
            return Some(([a[0] + radius * theta.cos(), a[1] + radius * theta.sin()], gate));
        }
        if h.len() >= 2 && h[h.len() - 2].0 + 1 == last_i {
            let p = h[h.len() - 2].1;
            let g = gap as f64;
            return Some(([last[0] + g * (last[0] - p[0]), last[1] + g * (last[1] - p[1])], gate));
        }
        Some((last, gate.max(8.0)))
    }

    /// The strongest place of mark `k`'s kind within `gate` of `p`.
    fn peak_near(&self, frame: &Frame, k: usize, p: [f64; 2], gate: f64) -> Option<[f64; 2]> {
        match self.style {
            MarkStyle::Colours => {
                let (cb, cr) = (frame.cb_plane(), frame.cr_plane());
                let (hc, hs) = (self.marks[k].hue.cos(), self.marks[k].hue.sin());
                let g = (gate / 2.0).ceil() as i64;
                let (ci, cj) = (
                    ((p[0] - CHROMA_OFFSET) / 2.0).round() as i64,
                    ((p[1] - CHROMA_OFFSET) / 2.0).round() as i64,
                );
                let k_bg = 4;
                let mut best: Option<(f64, [f64; 2])> = None;
                for j in cj - g..=cj + g {
                    for i in ci - g..=ci + g {
                        if !cb.holds(i, j, k_bg)
                            || ((i - ci).pow(2) + (j - cj).pow(2)) as f64 > (g * g) as f64 + 0.5
                        {
                            continue;
                        }
                        // The hue's projection against the mean of a ring of samples round it.
                        let proj = |i: i64, j: i64| {
                            (cb.at(i as usize, j as usize) - 128.0) * hc
                                + (cr.at(i as usize, j as usize) - 128.0) * hs
                        };
                        let mut bg = 0.0;
                        let mut n = 0.0;
                        for d in -k_bg..=k_bg {
                            for (a, b) in [(d, -k_bg), (d, k_bg), (-k_bg, d), (k_bg, d)] {
                                bg += proj(i + a, j + b);
                                n += 1.0;
                            }
                        }
                        let v = proj(i, j) - bg / n;
                        if best.is_none_or(|(b, _)| v > b) {
                            best = Some((
                                v,
                                [2.0 * i as f64 + CHROMA_OFFSET, 2.0 * j as f64 + CHROMA_OFFSET],
                            ));
                        }
                    }
                }
                best.map(|b| b.1)
            }
            _ => {
                let l = frame.luma_plane();
                let g = gate.ceil() as i64;
                let (xi, yi) = (p[0].round() as i64, p[1].round() as i64);
                let inner = ((self.disc - 1.0) * 0.7).round().max(1.0) as i64;
                let outer = (self.disc * 2.0).round() as i64;
                let mut best: Option<(f64, [f64; 2])> = None;
                let mean = |x: i64, y: i64, r: i64| {
                    let mut s = 0.0;
                    for j in y - r..=y + r {
                        for i in x - r..=x + r {
                            s += l.at(i as usize, j as usize);
                        }
                    }
                    s / ((2 * r + 1) * (2 * r + 1)) as f64
                };
                for y in yi - g..=yi + g {
                    for x in xi - g..=xi + g {
                        if !l.holds(x, y, outer) || ((x - xi).pow(2) + (y - yi).pow(2)) > g * g {
                            continue;
                        }
                        let v = self.polarity.signal(mean(x, y, outer), mean(x, y, inner));
                        if best.is_none_or(|(b, _)| v > b) {
                            best = Some((v, [x as f64, y as f64]));
                        }
                    }
                }
                best.map(|b| b.1)
            }
        }
    }

    /// Colours: the chroma sample at `peak` as a mark too faint or smeared for a blob's fit,
    /// its colour that sample's departure from the ring of samples round it.
    fn coarse_colour(&self, frame: &Frame, k: usize, peak: [f64; 2]) -> Option<Centre> {
        if self.style != MarkStyle::Colours {
            return None;
        }
        let (cb, cr) = (frame.cb_plane(), frame.cr_plane());
        let (i, j) = (
            ((peak[0] - CHROMA_OFFSET) / 2.0).round() as i64,
            ((peak[1] - CHROMA_OFFSET) / 2.0).round() as i64,
        );
        let r = 4;
        if !cb.holds(i, j, r) {
            return None;
        }
        let mut chroma = [0.0; 2];
        for (c, plane) in chroma.iter_mut().zip([&cb, &cr]) {
            let mut bg = 0.0;
            for d in -r..=r {
                for (a, b) in [(d, -r), (d, r), (-r, d), (r, d)] {
                    bg += plane.at((i + a) as usize, (j + b) as usize);
                }
            }
            *c = plane.at(i as usize, j as usize) - bg / (16 * r + 4) as f64;
        }
        Some(Centre {
            x: peak[0],
            y: peak[1],
            strength: chroma[0].hypot(chroma[1]),
            chroma,
            sigma: 1.0,
            width: self.marks[k].width.unwrap_or(1.2),
            coarse: true,
        })
    }

    /// Mark `k` searched for near `p`: its centre, if it is there and looks like itself.
    fn look(&self, frame: &Frame, k: usize, p: [f64; 2], gate: f64) -> Option<Centre> {
        let peak = self.peak_near(frame, k, p, gate)?;
        // A fit that runs off from the strongest sample (a weak or smeared mark) is tried
        // again from where the mark was predicted.
        let fitted = self
            .centre_at(frame, peak[0], peak[1], k, 3.0)
            .or_else(|| self.centre_at(frame, p[0], p[1], k, 3.0))
            .or_else(|| self.coarse_colour(frame, k, peak));
        let c = fitted?;
        if (c.x - p[0]).hypot(c.y - p[1]) > gate + 1.0 {
            return None;
        }
        let m = &self.marks[k];
        if c.strength < 0.4 * m.strength {
            return None;
        }
        if self.style == MarkStyle::Colours && angle_between(c.hue(), m.hue) > 0.6 {
            return None;
        }
        Some(c)
    }

    /// Colours: a mark neither followed nor placed by three others, where two others were
    /// found, looked for by its hue round the ring (its hue names it), and kept where it is
    /// not a look-alike (`WIDE_HUE`, `FRINGE`, `WIDER`).
    fn by_hue_round_the_ring(&self, frame: &Frame, index: u64, found: &mut [Option<Centre>; 4]) {
        let seen: Vec<[f64; 2]> = found.iter().flatten().map(|c| [c.x, c.y]).collect();
        if seen.len() < 2 || seen.len() == 4 || !(self.size > 0.0) {
            return;
        }
        let opposite = (0..2).find_map(|k| found[k].zip(found[k + 2]));
        // A between an opposite pair, else near the marks seen (A lies within the ring's size).
        let (centre, reach) = match opposite {
            Some((a, b)) => ([(a.x + b.x) / 2.0, (a.y + b.y) / 2.0], 1.25 * self.size + 3.0),
            None => {
                let n = seen.len() as f64;
                let m = [
                    seen.iter().map(|p| p[0]).sum::<f64>() / n,
                    seen.iter().map(|p| p[1]).sum::<f64>() / n,
                ];
                (m, 2.0 * self.size + 3.0)
            }
        };
        for k in 0..4 {
            if found[k].is_none() && self.predict(k, index).is_none() {
                found[k] = self
                    .look(frame, k, centre, reach)
                    .filter(|c| angle_between(c.hue(), self.marks[k].hue) <= WIDE_HUE)
                    .filter(|c| seen.iter().all(|p| (p[0] - c.x).hypot(p[1] - c.y) >= FRINGE));
                let marks: FrameMarks = std::array::from_fn(|j| found[j].map(|c| [c.x, c.y]));
                if least_semi_major(&marks).is_some_and(|a| a > WIDER * self.size + 2.0) {
                    found[k] = None;
                }
            }
        }
    }

    /// Colours: each mark's centre on the brightness (`rim`), taken in place of its chroma
    /// centre where the marks' parallelogram says it is the better (`choice`).
    fn on_brightness(&mut self, frame: &Frame, index: u64, found: &mut [Option<Centre>; 4]) {
        let at = |k: usize| found[k].map(|c| [c.x, c.y]);
        // The ring's figure: a mark not found where the other three or its motion put it.
        let figure: [Option<[f64; 2]>; 4] = std::array::from_fn(|k| {
            at(k).or_else(|| match (at((k + 1) % 4), at((k + 2) % 4), at((k + 3) % 4)) {
                (Some(a), Some(b), Some(c)) => Some([a[0] + c[0] - b[0], a[1] + c[1] - b[1]]),
                _ => self.predict(k, index).map(|p| p.0),
            })
        });
        let ring = match figure {
            [Some(a), Some(b), Some(c), Some(d)] => RingView::from_marks([a, b, c, d]),
            _ => None,
        };
        let Some(ring) = ring else {
            for f in found.iter_mut() {
                *f = f.filter(|c| !c.coarse);
            }
            return;
        };
        let luma = frame.luma_plane();
        let on_luma: [Option<Centre>; 4] = std::array::from_fn(|k| {
            let c = found[k]?;
            let radius = (1.5 * self.marks[k].width.unwrap_or(c.width)).clamp(2.0, 8.0);
            rim_centre(&luma, &ring, k, [c.x, c.y], radius, REACH)
        });
        if let ([Some(a), Some(b), Some(c), Some(d)], [Some(e), Some(f), Some(g), Some(h)]) =
            (*found, on_luma)
        {
            let xy = |c: Centre| [c.x, c.y];
            self.choice.add([a, b, c, d].map(xy), [e, f, g, h].map(xy));
        }
        // Brightness centres missing for two marks or more put the figure they were sought on
        // in doubt, not the marks.
        let unplaced = (0..4).filter(|&k| found[k].is_some() && on_luma[k].is_none()).count();
        for k in 0..4 {
            let w = self.choice.second(k);
            match (found[k].as_mut(), on_luma[k]) {
                (Some(c), Some(l)) => {
                    let w = if c.coarse { 1.0 } else { w };
                    [c.x, c.y] = blend([c.x, c.y], [l.x, l.y], w);
                    c.sigma = (1.0 - w) * c.sigma + w * l.sigma;
                    c.coarse = false;
                }
                // The film showed this mark's chroma centre to err more than its brightness
                // centre; without the latter here, the former alone is left out (a weak mark's
                // hue stuck on the table's grain while the ring turns on).
                (Some(c), None) if w >= 0.5 && unplaced == 1 => c.coarse = true,
                _ => {}
            }
            found[k] = found[k].filter(|c| !c.coarse);
        }
    }

    /// One frame: the marks found in it.
    pub fn step(&mut self, frame: &Frame, index: u64) -> FrameResult {
        let mut found: [Option<Centre>; 4] = [None; 4];
        let mut new_numbering = false;
        let moving = (0..4).filter(|&k| self.moving(k, index)).count();
        if moving < 2 {
            // Motion not known well enough to predict: the four found anew near the ring,
            // kept only where each lies within reach of where a mark still followed predicts it.
            if let Some(again) = self.find_again(frame, index) {
                let agrees = (0..4).all(|k| {
                    self.predict(k, index).is_none_or(|(p, gate)| {
                        !self.moving(k, index)
                            || (again.marks[k].x - p[0]).hypot(again.marks[k].y - p[1]) <= gate
                    })
                });
                if agrees {
                    self.refound += 1;
                    // Seen in the frame before, the nearest rotation holds; after a frame
                    // unseen the ring may have turned an eighth of a turn (an opening on
                    // edge): the turning settles it.
                    let last_seen =
                        self.marks.iter().filter_map(|m| m.history.last()).map(|h| h.0).max();
                    new_numbering =
                        self.style != MarkStyle::Colours && last_seen.is_none_or(|i| index - i > 1);
                    for k in 0..4 {
                        // Colours found anew in a clear order show their hues again: those
                        // learnt where the ring was acquired may be a blur's (an opening on
                        // edge), far enough off for every later frame to turn the mark down.
                        let at = [again.marks[k].x, again.marks[k].y];
                        if self.style == MarkStyle::Colours
                            && let Some(c) = self.centre_at(frame, at[0], at[1], k, 4.0)
                        {
                            self.learn_hue(&c, k);
                        }
                        found[k] = self.look(frame, k, at, 3.0);
                    }
                }
            }
        }
        for k in 0..4 {
            if found[k].is_none()
                && let Some((p, gate)) = self.predict(k, index)
            {
                found[k] = self.look(frame, k, p, gate);
            }
        }
        // Marks not followed: where the other three put them (the parallelogram rule).
        for k in 0..4 {
            if found[k].is_some() {
                continue;
            }
            let (a, b, c) = (found[(k + 1) % 4], found[(k + 2) % 4], found[(k + 3) % 4]);
            if let (Some(a), Some(b), Some(c)) = (a, b, c) {
                let p = [a.x + c.x - b.x, a.y + c.y - b.y];
                let size = (a.x - c.x).hypot(a.y - c.y);
                found[k] = self.look(frame, k, p, (0.08 * size + 3.0).min(10.0));
            }
        }
        if self.style == MarkStyle::Colours {
            self.by_hue_round_the_ring(frame, index, &mut found);
            self.on_brightness(frame, index, &mut found);
        }
        // One mark left behind on a look-alike, told by the marks' ellipse a few frames
        // before (its shape changes little in that time); the tolerance is the parallelogram's
        // below: the centres' noise and a near camera's departure from an affine figure.
        if let ([Some(a), Some(b), Some(c), Some(d)], Some((i, fig))) = (found, self.figure)
            && index - i <= 6
        {
            let tolerance = 2.0 + 0.05 * self.size;
            if let Some(k) = fig.odd_one_out([a, b, c, d].map(|m| [m.x, m.y]), tolerance) {
                found[k] = None;
            }
        }
        // Four points 90 degrees apart on a circle make a parallelogram (nearly, through a
        // near camera): one mark far off it was taken from something else. Which one: the
        // farthest from where it was predicted; with no prediction, none of the four stands.
        if let [Some(a), Some(b), Some(c), Some(d)] = found {
            let gap = ((a.x + c.x - b.x - d.x) / 2.0).hypot((a.y + c.y - b.y - d.y) / 2.0);
            let size = super::find::ellipse_axes(
                [(a.x - c.x) / 2.0, (a.y - c.y) / 2.0],
                [(b.x - d.x) / 2.0, (b.y - d.y) / 2.0],
            )
            .0;
            if gap > 0.06 * size + 1.5 {
                let off = |k: usize| {
                    let f = found[k].expect("all four");
                    self.predict(k, index).map(|(p, _)| (f.x - p[0]).hypot(f.y - p[1]))
                };
                let offs: Option<Vec<f64>> = (0..4).map(off).collect();
                match offs {
                    Some(o) => {
                        let worst = (0..4).max_by(|&i, &j| o[i].total_cmp(&o[j])).expect("four");
                        found[worst] = None;
                    }
                    None => found = [None; 4],
                }
            }
        }
        // Two marks in one place: neither can be trusted. In one place: closer than half the
        // least distance the ring's recent figure allows them (adjacent marks sqrt(2) times its
        // semi-minor axis apart at the least, opposite ones twice it).
        let near = if self.style == MarkStyle::Colours { 1.5 } else { self.disc.max(2.0) };
        let minor = self.figure.filter(|(i, _)| index - i <= 6).map(|(_, f)| f.minor_axis());
        let apart = |i: usize, j: usize| {
            let least = if (j - i) % 2 == 1 { std::f64::consts::SQRT_2 } else { 2.0 };
            minor.map_or(near, |b| near.max(0.5 * least * b))
        };
        let mut ambiguous = [false; 4];
        for i in 0..4 {
            for j in i + 1..4 {
                if let (Some(a), Some(b)) = (found[i], found[j])
                    && (a.x - b.x).hypot(a.y - b.y) < apart(i, j)
                {
                    ambiguous[i] = true;
                    ambiguous[j] = true;
                }
            }
        }
        let mut out = FrameResult { new_numbering, ..FrameResult::default() };
        for k in 0..4 {
            if ambiguous[k] {
                found[k] = None;
                out.ambiguous += 1;
            }
            if let Some(c) = found[k] {
                out.marks[k] = Some([c.x, c.y]);
                out.sigma[k] = Some(c.sigma);
                if self.style == MarkStyle::Colours {
                    out.hues[k] = Some(c.hue());
                }
                let m = &mut self.marks[k];
                m.history.push((index, [c.x, c.y]));
                if m.history.len() > HISTORY {
                    m.history.remove(0);
                }
                m.strength = 0.9 * m.strength + 0.1 * c.strength;
                if self.style == MarkStyle::Colours {
                    m.width = Some(m.width.map_or(c.width, |w| 0.9 * w + 0.1 * c.width));
                }
            }
        }
        if let [Some(a), Some(b), Some(c), Some(d)] = out.marks {
            self.figure = Figure::from_marks([a, b, c, d]).map(|f| (index, f));
        }
        if out.marks.iter().all(|m| m.is_some())
            && let Some(size) = least_semi_major(&out.marks)
        {
            self.size = size;
        }
        self.choose_disc(frame, &out.marks);
        if let Some(a) = centre_of(&out.marks) {
            self.centres.push((index, a));
            if self.centres.len() > HISTORY {
                self.centres.remove(0);
            }
        }
        out
    }
}

/// A dot's radius (px): in each of 16 directions from its centre, where its contrast falls
/// to half its depth; the median of those, so that a dark neighbour on one side (the rim's
/// inner wall, its shadow) does not widen it.
fn measure_dot(frame: &Frame, polarity: Polarity, c: &super::find::Candidate, guess: f64) -> f64 {
    let l = frame.luma_plane();
    let r = (guess * 3.0).ceil() as i64 + 2;
    let (xi, yi) = (c.x.round() as i64, c.y.round() as i64);
    if !l.holds(xi, yi, r + 1) {
        return guess;
    }
    let mut ring = Vec::new();
    for j in yi - r..=yi + r {
        for i in xi - r..=xi + r {
            let d = ((i - xi).pow(2) + (j - yi).pow(2)) as f64;
            if d > (r as f64 - 1.5).powi(2) && d <= (r * r) as f64 {
                ring.push(l.at(i as usize, j as usize));
            }
        }
    }
    ring.sort_by(|a, b| a.total_cmp(b));
    let bg = ring[ring.len() / 2];
    let bilinear = |x: f64, y: f64| {
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (i, j) = (x0 as usize, y0 as usize);
        l.at(i, j) * (1.0 - fx) * (1.0 - fy)
            + l.at(i + 1, j) * fx * (1.0 - fy)
            + l.at(i, j + 1) * (1.0 - fx) * fy
            + l.at(i + 1, j + 1) * fx * fy
    };
    let depth = polarity.signal(bg, bilinear(c.x, c.y));
    if !(depth > 0.0) {
        return guess;
    }
    let mut radii: Vec<f64> = (0..16)
        .map(|k| {
            let (s, co) = (k as f64 * std::f64::consts::TAU / 16.0).sin_cos();
            let mut t = 0.0;
            while t < r as f64 - 0.5
                && polarity.signal(bg, bilinear(c.x + t * co, c.y + t * s)) > depth / 2.0
            {
                t += 0.25;
            }
            t
        })
        .collect();
    radii.sort_by(|a, b| a.total_cmp(b));
    ((radii[7] + radii[8]) / 2.0).clamp(1.0, 3.0 * guess)
}
