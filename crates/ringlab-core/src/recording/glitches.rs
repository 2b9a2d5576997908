//! A tracker's glitches: mark positions far off their own track (a blob mistaken for a
//! mark), and labels swapped between marks for a few frames. Found from the tracks alone, so
//! that every fit can leave them out; a fit in pixels would otherwise bend its whole path
//! towards a 40 px outlier.
//!
//! Each mark position is compared with a cubic fitted to the same mark's neighbours within
//! [`HALF_WIDTH`] frames on both sides (the position itself left out). Its residual is scaled
//! by the larger of the noise and the local scatter of such residuals (where the marks turn
//! fast the cubic misses by more than the noise, and that is motion, not a glitch), and a
//! position that lies [`THRESHOLD`] such scales off and is the worst of its neighbourhood is a
//! glitch; the search repeats without it until no new one appears, so a glitch never hides
//! its neighbours or condemns them.
//!
//! Swapped labels: the marks are numbered in cyclic order, so the quadrilateral of a frame has
//! the same orientation all through a recording (`marks.rs`), and swapping two opposite marks
//! reverses it. Frames that turn the other way are first left out of every neighbourhood; the
//! marks in them that their clean neighbours do not predict are the swapped ones.

use super::{FrameMarks, MARKS};
use nalgebra::{DMatrix, DVector};

/// Neighbours on each side of a position that predict it.
pub const HALF_WIDTH: usize = 4;
/// Degree of the local polynomial.
const DEGREE: usize = 3;
/// Scales off (2D residual over the per-coordinate scale) for a glitch: white noise reaches 8
/// with probability `exp(-32)`, and a tracker's glitch lies tens of pixels off.
pub const THRESHOLD: f64 = 8.0;
/// Frames on each side over which the local scatter of the residuals is taken.
const SCATTER_HALF_WIDTH: usize = 30;
/// Median of a 2D Gaussian residual's length over its per-coordinate deviation: `sqrt(2 ln 2)`.
const RAYLEIGH_MEDIAN: f64 = 1.177_410_022_515_474_6;
/// A bound on the passes (each finds at least one glitch per neighbourhood).
const MAX_PASSES: usize = 50;

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum GlitchKind {
    /// Off its own track.
    Outlier,
    /// In a frame whose marks turn the wrong way round: a label swapped with another mark's.
    Swapped,
}

/// One mark position left out (`frame` is the index into the recording's frames; `mark` 0-based).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Glitch {
    pub frame: usize,
    pub mark: usize,
    pub kind: GlitchKind,
}

/// The frames with the glitches' positions removed (as not tracked).
pub fn without_glitches(frames: &[FrameMarks], glitches: &[Glitch]) -> Vec<FrameMarks> {
    let mut out = frames.to_vec();
    for g in glitches {
        if let Some(f) = out.get_mut(g.frame) {
            f[g.mark] = None;
        }
    }
    out
}

/// Signed area of a frame's mark quadrilateral (None unless all four are tracked).
fn signed_area(f: &FrameMarks) -> Option<f64> {
    let mut area = 0.0;
    for k in 0..MARKS {
        let (a, b) = (f[k]?, f[(k + 1) % MARKS]?);
        area += a[0] * b[1] - b[0] * a[1];
    }
    Some(area)
}

/// The position of `mark` at `frame` predicted from its usable neighbours, and the factor by
/// which the prediction's residual is noisier than one position (`sqrt(1 + var(pred)/s^2)`).
fn predict(
    frames: &[FrameMarks],
    mark: usize,
    frame: usize,
    usable: &dyn Fn(usize) -> bool,
) -> Option<([f64; 2], f64)> {
    let lo = frame.saturating_sub(HALF_WIDTH);
    let hi = (frame + HALF_WIDTH).min(frames.len() - 1);
    let points: Vec<(f64, [f64; 2])> = (lo..=hi)
        .filter(|&j| j != frame && usable(j))
        .filter_map(|j| frames[j][mark].map(|p| (j as f64 - frame as f64, p)))
        .collect();
    if points.len() < 4 {
        return None;
    }
    let degree = DEGREE.min(points.len() - 2);
    let v = DMatrix::from_fn(points.len(), degree + 1, |r, c| points[r].0.powi(c as i32));
    let normal = v.transpose() * &v;
    let inv = normal.try_inverse()?;
    let mut at = [0.0; 2];
    for (c, slot) in at.iter_mut().enumerate() {
        let y = DVector::from_iterator(points.len(), points.iter().map(|p| p.1[c]));
        *slot = (&inv * v.transpose() * y)[0];
    }
    Some((at, (1.0 + inv[(0, 0)]).sqrt()))
}

/// The glitches of a recording whose pixel noise per coordinate is `noise_px`, in frame order.
pub fn find_glitches(frames: &[FrameMarks], noise_px: f64) -> Vec<Glitch> {
    let n = frames.len();
    if n < 2 * HALF_WIDTH || !(noise_px > 0.0) {
        return Vec::new();
    }
    let areas: Vec<Option<f64>> = frames.iter().map(signed_area).collect();
    let majority: f64 = areas.iter().flatten().map(|a| a.signum()).sum();
    let mut suspect: Vec<bool> =
        areas.iter().map(|a| a.is_some_and(|a| a.signum() * majority < 0.0)).collect();
    let mut bad = vec![[false; MARKS]; n];
    let mut found = Vec::new();
    for pass in 0..MAX_PASSES {
        // Scaled residuals of every position not yet left out.
        let mut z = vec![[0.0f64; MARKS]; n];
        for mark in 0..MARKS {
            let usable = |j: usize| !bad[j][mark] && !suspect[j];
            let raw: Vec<Option<(f64, f64)>> = (0..n)
                .map(|i| {
                    let p = frames[i][mark]?;
                    let (at, factor) = predict(frames, mark, i, &usable)?;
                    Some(((p[0] - at[0]).hypot(p[1] - at[1]), factor))
                })
                .collect();
            for i in 0..n {
                let Some((r, factor)) = raw[i] else { continue };
                if bad[i][mark] {
                    continue;
                }
                let scatter = local_scatter(i, n, |j| {
                    raw[j].filter(|_| !bad[j][mark] && !suspect[j]).map(|(r, f)| r / f)
                });
                z[i][mark] = r / (factor * noise_px.max(scatter));
            }
        }
        let mut new = 0;
        if pass == 0 {
            // Frames turning the wrong way: their marks that the clean neighbours do not predict.
            for i in (0..n).filter(|&i| suspect[i]) {
                for mark in 0..MARKS {
                    if z[i][mark] > THRESHOLD {
                        bad[i][mark] = true;
                        found.push(Glitch { frame: i, mark, kind: GlitchKind::Swapped });
                        new += 1;
                    }
                }
            }
            suspect.iter_mut().for_each(|s| *s = false);
            if new > 0 {
                continue;
            }
        }
        new += flag_outliers(&z, &mut bad, &mut found);
        if new == 0 {
            break;
        }
    }
    found.sort_by_key(|g| (g.frame, g.mark));
    found
}

/// The per-coordinate scale of the residuals near frame `i` (of `n`; `residual(j)`, None where
/// left out): their median length over [`RAYLEIGH_MEDIAN`], 0 with fewer than eight.
fn local_scatter(i: usize, n: usize, residual: impl Fn(usize) -> Option<f64>) -> f64 {
    let mut near: Vec<f64> = (i.saturating_sub(SCATTER_HALF_WIDTH)
        ..(i + SCATTER_HALF_WIDTH + 1).min(n))
        .filter_map(residual)
        .collect();
    if near.len() < 8 {
        return 0.0;
    }
    let mid = near.len() / 2;
    *near.select_nth_unstable_by(mid, f64::total_cmp).1 / RAYLEIGH_MEDIAN
}

/// Positions whose scaled residual `z` lies beyond [`THRESHOLD`] and is the worst of its
/// neighbourhood ([`HALF_WIDTH`] frames each side), left out as outliers; how many.
fn flag_outliers(z: &[[f64; MARKS]], bad: &mut [[bool; MARKS]], found: &mut Vec<Glitch>) -> usize {
    let n = z.len();
    let mut new = 0;
    for mark in 0..MARKS {
        for i in 0..n {
            let zi = z[i][mark];
            let (lo, hi) = (i.saturating_sub(HALF_WIDTH), (i + HALF_WIDTH + 1).min(n));
            if zi > THRESHOLD && (lo..hi).all(|j| z[j][mark] <= zi) {
                bad[i][mark] = true;
                found.push(Glitch { frame: i, mark, kind: GlitchKind::Outlier });
                new += 1;
            }
        }
    }
    new
}

/// The glitches that the tracks alone let through, found against a model's prediction of every
/// position (`predicted`, None where it predicts none): the same rule as [`find_glitches`] on
/// the residual to the prediction instead of to a local cubic. Where the marks turn fast a
/// cubic over a few frames misses by more than the noise, its scatter raises the bar, and a
/// 10 to 20 px outlier stays under it; a model fitted to the recording (the multiple-shooting
/// fit) follows the fast turns, so its residual stays near the noise there and the outlier
/// stands out. `already` are left out of the scatter and not found again.
pub fn find_glitches_against(
    frames: &[FrameMarks],
    predicted: &[Option<[[f64; 2]; MARKS]>],
    noise_px: f64,
    already: &[Glitch],
) -> Vec<Glitch> {
    let n = frames.len().min(predicted.len());
    if !(noise_px > 0.0) {
        return Vec::new();
    }
    let mut bad = vec![[false; MARKS]; n];
    for g in already.iter().filter(|g| g.frame < n) {
        bad[g.frame][g.mark] = true;
    }
    let residual: Vec<[Option<f64>; MARKS]> = (0..n)
        .map(|i| {
            std::array::from_fn(|mark| {
                let (o, p) = (frames[i][mark]?, predicted[i]?[mark]);
                Some((o[0] - p[0]).hypot(o[1] - p[1]))
            })
        })
        .collect();
    let mut found = Vec::new();
    for _ in 0..MAX_PASSES {
        let mut z = vec![[0.0f64; MARKS]; n];
        for mark in 0..MARKS {
            for i in 0..n {
                let Some(r) = residual[i][mark].filter(|_| !bad[i][mark]) else { continue };
                let scatter = local_scatter(i, n, |j| residual[j][mark].filter(|_| !bad[j][mark]));
                z[i][mark] = r / noise_px.max(scatter);
            }
        }
        if flag_outliers(&z, &mut bad, &mut found) == 0 {
            break;
        }
    }
    found.sort_by_key(|g| (g.frame, g.mark));
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recording::noise::tests::spinning;
    use crate::recording::rng::Rng;

    #[test]
    fn clean_tracks_have_no_glitches() {
        for rate in [0.1, 0.33, 0.7] {
            assert_eq!(
                find_glitches(&spinning(1500, rate, 0.5, 5), 0.5),
                Vec::new(),
                "rate {rate}"
            );
        }
    }

    #[test]
    fn finds_outliers_and_swapped_labels_and_nothing_else() {
        let mut frames = spinning(1500, 0.33, 0.5, 9);
        let mut rng = Rng::new(2);
        let mut planted = Vec::new();
        for i in (20..1480).step_by(61) {
            let mark = rng.below(4);
            let off = 10.0 + 50.0 * rng.uniform();
            let angle = std::f64::consts::TAU * rng.uniform();
            frames[i][mark] =
                frames[i][mark].map(|p| [p[0] + off * angle.cos(), p[1] + off * angle.sin()]);
            planted.push(Glitch { frame: i, mark, kind: GlitchKind::Outlier });
        }
        // Marks 1 and 3 (0 and 2 here) swapped for three frames, twice.
        for start in [500, 1201] {
            for i in start..start + 3 {
                frames[i].swap(0, 2);
                planted.extend([0, 2].map(|mark| Glitch {
                    frame: i,
                    mark,
                    kind: GlitchKind::Swapped,
                }));
            }
        }
        planted.sort_by_key(|g| (g.frame, g.mark));
        assert_eq!(find_glitches(&frames, 0.5), planted);
        let kept = without_glitches(&frames, &planted);
        assert_eq!(kept.iter().flatten().filter(|m| m.is_none()).count(), planted.len());
    }
    #[test]
    fn against_a_prediction_finds_outliers_the_cubic_lets_through() {
        // Marks turning fast (0.7 rad per frame): the cubic's scatter hides 10 to 20 px.
        let clean = spinning(1500, 0.7, 0.0, 3);
        let mut frames = spinning(1500, 0.7, 0.5, 3);
        let predicted: Vec<Option<[[f64; 2]; MARKS]>> =
            clean.iter().map(|f| Some(std::array::from_fn(|m| f[m].unwrap_or([0.0; 2])))).collect();
        assert_eq!(find_glitches_against(&frames, &predicted, 0.5, &[]), Vec::new());
        let mut planted = Vec::new();
        let mut rng = Rng::new(4);
        for i in (30..1470).step_by(47) {
            let mark = rng.below(4);
            let off = 10.0 + 10.0 * rng.uniform();
            let angle = std::f64::consts::TAU * rng.uniform();
            frames[i][mark] =
                frames[i][mark].map(|p| [p[0] + off * angle.cos(), p[1] + off * angle.sin()]);
            planted.push(Glitch { frame: i, mark, kind: GlitchKind::Outlier });
        }
        let by_cubic = find_glitches(&frames, 0.5);
        assert!(
            by_cubic.len() < planted.len(),
            "the cubic must miss some here, else this shows nothing"
        );
        let missed: Vec<Glitch> =
            planted.iter().filter(|g| !by_cubic.contains(g)).copied().collect();
        assert_eq!(find_glitches_against(&frames, &predicted, 0.5, &by_cubic), missed);
    }
}
