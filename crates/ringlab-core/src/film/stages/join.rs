//! Identical dots numbered again across a loss. Found anew after a loss, four alike dots can
//! be numbered four ways; the ring's turning settles which. The marks' figure has a phase,
//! the rotation part of the map from a unit circle onto their ellipse, that turns smoothly
//! with the ring (the spin and the line of nodes' turn together) and steps a quarter turn
//! when the numbers are rotated by one. A smooth curve through the phases just before the
//! loss and just after it, the later ones shifted by whole quarter turns, fits within the
//! noise for one shift alone where the loss is short against the changes of the ring's
//! rate: the numbers are rotated by that shift. Where no shift or more than one fits, the
//! marks found after the loss are left out and counted, never numbered by a guess.

use nalgebra::{Matrix3, Vector3};

use super::{Stage, StageContext, StageReport, Track};
use crate::film::tuning::JoinTuning;
use crate::recording::FrameMarks;

/// The stage: dots found anew numbered across each loss, or left out.
pub struct Join;

impl Stage for Join {
    fn name(&self) -> &'static str {
        "join"
    }
    fn run(&self, track: &mut Track, ctx: &StageContext) -> StageReport {
        let (frames, sigma) = (&mut track.frames, &mut track.sigma);
        let joined = number_across_losses(frames, sigma, ctx.new_numbering, &ctx.tuning.join);
        let note = (joined.unsettled > 0).then(|| {
            format!(
                "{} marks left out in {} stretches after a loss: dots found anew there that the ring's turning across the loss could not number as the rest",
                joined.marks_left_out, joined.unsettled
            )
        });
        StageReport {
            name: self.name(),
            left_out: joined.marks_left_out,
            renumbered: joined.settled,
            note,
        }
    }
}

/// What numbering across the losses did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Joined {
    /// Stretches numbered as one before them from the phase.
    pub settled: usize,
    /// Stretches left out: those in groups the turning could not join to the one kept.
    pub unsettled: usize,
    /// Marks left out with them.
    pub marks_left_out: usize,
}

/// The phase of four marks (three: the fourth from the parallelogram), in (-pi, pi].
pub fn phase(m: &FrameMarks) -> Option<f64> {
    let p: [[f64; 2]; 4] = match *m {
        [Some(a), Some(b), Some(c), Some(d)] => [a, b, c, d],
        _ => {
            let missing = (0..4).find(|&k| m[k].is_none())?;
            let [a, b, c] = [1, 2, 3].map(|s| m[(missing + s) % 4]);
            let (a, b, c) = (a?, b?, c?);
            let mut p = [[0.0; 2]; 4];
            p[missing] = [a[0] + c[0] - b[0], a[1] + c[1] - b[1]];
            p[(missing + 1) % 4] = a;
            p[(missing + 2) % 4] = b;
            p[(missing + 3) % 4] = c;
            p
        }
    };
    // Columns d1, d2: the half diagonals, the images of two perpendicular radii.
    let d1 = [(p[0][0] - p[2][0]) / 2.0, (p[0][1] - p[2][1]) / 2.0];
    let d2 = [(p[1][0] - p[3][0]) / 2.0, (p[1][1] - p[3][1]) / 2.0];
    Some((d1[1] - d2[0]).atan2(d1[0] + d2[1]))
}

/// Phases of the frames `range` covers, nearest the loss first (`from_end`: the last
/// frames), unwrapped, up to `t.window` of them and none across a long hole.
fn window(
    frames: &[FrameMarks],
    range: std::ops::Range<usize>,
    from_end: bool,
    t: &JoinTuning,
) -> Vec<(f64, f64)> {
    let order: Box<dyn Iterator<Item = usize>> =
        if from_end { Box::new(range.rev()) } else { Box::new(range) };
    let mut out: Vec<(f64, f64)> = Vec::new();
    for i in order {
        let Some(a) = phase(&frames[i]) else { continue };
        if let Some(&(at, last)) = out.last() {
            if (at - i as f64).abs() > t.most_apart as f64 {
                break;
            }
            let a = last + (a - last + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            out.push((i as f64, a));
        } else {
            out.push((i as f64, a));
        }
        if out.len() == t.window {
            break;
        }
    }
    out
}

/// A side's phases (nearest the loss first) without the few next to the loss that sit off
/// the others' parabola: the ring is lost where it is hard to see, and the four found
/// in the frames beside that are often partly taken from something else. The fewest dropped
/// whose own misfit is within half again of the least any dropping gives.
fn settled_in(near_first: &[(f64, f64)], t: &JoinTuning) -> Vec<(f64, f64)> {
    let noise = |m: usize| {
        let rest = &near_first[m..];
        let t0 = rest.iter().map(|p| p.0).sum::<f64>() / rest.len() as f64;
        parabola_misfit(rest, t0).map_or(f64::INFINITY, |r| r / (rest.len() - 3) as f64)
    };
    let most = t.most_dropped.min(near_first.len().saturating_sub(t.fewest));
    let noises: Vec<f64> = (0..=most).map(noise).collect();
    let least = noises.iter().copied().fold(f64::INFINITY, f64::min);
    let m =
        noises.iter().position(|&n| n <= 1.5 * least + t.least_noise * t.least_noise).unwrap_or(0);
    near_first[m..].to_vec()
}

struct Parabola {
    t0: f64,
    c: Vector3<f64>,
}

impl Parabola {
    fn at(&self, t: f64) -> f64 {
        let x = t - self.t0;
        self.c[0] + self.c[1] * x + self.c[2] * x * x
    }
}

/// The least-squares parabola in time through `points` (centred on `t0`).
fn parabola(points: &[(f64, f64)], t0: f64) -> Option<Parabola> {
    let mut ata = Matrix3::zeros();
    let mut aty = Vector3::zeros();
    for &(t, y) in points {
        let x = t - t0;
        let row = Vector3::new(1.0, x, x * x);
        ata += row * row.transpose();
        aty += row * y;
    }
    Some(Parabola { t0, c: ata.lu().solve(&aty)? })
}

/// The residual sum of squares about the least-squares parabola.
fn parabola_misfit(points: &[(f64, f64)], t0: f64) -> Option<f64> {
    let c = parabola(points, t0)?;
    Some(points.iter().map(|&(t, y)| (y - c.at(t)).powi(2)).sum())
}

/// The line through a side's phases, at time `t`.
fn line_at(points: &[(f64, f64)], t: f64) -> f64 {
    let n = points.len() as f64;
    let (mt, my) =
        (points.iter().map(|p| p.0).sum::<f64>() / n, points.iter().map(|p| p.1).sum::<f64>() / n);
    let (sxy, sxx) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), p| (a + (p.0 - mt) * (p.1 - my), b + (p.0 - mt).powi(2)));
    my + if sxx > 0.0 { sxy / sxx } else { 0.0 } * (t - mt)
}

/// The quarter turns to add to the phases after a loss (`after`) to join those before it
/// (`before`); `None` where no shift, or more than one, fits.
pub fn settle(before: &[(f64, f64)], after: &[(f64, f64)], t: &JoinTuning) -> Option<i64> {
    if before.len() < t.fewest || after.len() < t.fewest {
        return None;
    }
    let mut before = settled_in(&before.iter().rev().copied().collect::<Vec<_>>(), t);
    before.reverse();
    let after = settled_in(after, t);
    let (before, after) = (&before[..], &after[..]);
    if before.len() < t.fewest || after.len() < t.fewest {
        return None;
    }
    let quarter = std::f64::consts::FRAC_PI_2;
    let t_before = before.iter().map(|p| p.0).sum::<f64>() / before.len() as f64;
    let t_after = after.iter().map(|p| p.0).sum::<f64>() / after.len() as f64;
    let own = parabola_misfit(before, t_before)? + parabola_misfit(after, t_after)?;
    let dof = (before.len() + after.len() - 6) as f64;
    let noise = (own / dof).max(t.least_noise * t.least_noise);
    let mid = (t_before + t_after) / 2.0;
    let guess = ((line_at(before, mid) - line_at(after, mid)) / quarter).round() as i64;
    let mut scores: Vec<(f64, i64)> = (guess - 4..=guess + 4)
        .filter_map(|k| {
            let joint: Vec<(f64, f64)> = before
                .iter()
                .copied()
                .chain(after.iter().map(|&(t, y)| (t, y + k as f64 * quarter)))
                .collect();
            Some(((parabola_misfit(&joint, mid)? - own).max(0.0) / noise, k))
        })
        .collect();
    scores.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (best, second) = (scores.first()?, scores.get(1)?);
    (second.0 >= t.doubt && second.0 >= t.clear * best.0).then_some(best.1)
}

/// Numbers the marks of each stretch that began with a new numbering (`starts`: the frames'
/// slots, ascending) as a stretch before it, where the phase settles it: stretches so joined
/// make a group with one numbering. The group with the most marks is kept; the marks of the
/// others (a stretch the turning could not join, the ones joined to it) are left out, with
/// their errors.
pub fn number_across_losses(
    frames: &mut [FrameMarks],
    sigma: &mut [[Option<f64>; 4]],
    starts: &[usize],
    t: &JoinTuning,
) -> Joined {
    let mut bounds: Vec<usize> = std::iter::once(0).chain(starts.iter().copied()).collect();
    bounds.push(frames.len());
    let stretches: Vec<std::ops::Range<usize>> = bounds
        .windows(2)
        .map(|w| w[0].min(frames.len())..w[1].min(frames.len()))
        .filter(|r| !r.is_empty())
        .collect();
    // Each group's stretches, the last the one the next stretch is tried against.
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut joined = Joined::default();
    for (s, range) in stretches.iter().enumerate() {
        let after = window(frames, range.clone(), false, t);
        let mut settled = None;
        for (g, group) in groups.iter().enumerate().rev() {
            let last = &stretches[*group.last().expect("a group has a stretch")];
            let mut before = window(frames, last.clone(), true, t);
            before.reverse();
            if let Some(k) = settle(&before, &after, t) {
                settled = Some((g, k));
                break;
            }
        }
        match settled {
            Some((g, k)) => {
                let rot = k.rem_euclid(4) as usize;
                for i in range.clone() {
                    frames[i].rotate_left(rot);
                    sigma[i].rotate_left(rot);
                }
                joined.settled += 1;
                groups[g].push(s);
            }
            None => groups.push(vec![s]),
        }
    }
    let marks = |group: &Vec<usize>| -> usize {
        group
            .iter()
            .flat_map(|&s| stretches[s].clone())
            .map(|i| frames[i].iter().flatten().count())
            .sum()
    };
    let kept = (0..groups.len()).max_by_key(|&g| marks(&groups[g]));
    for (g, group) in groups.iter().enumerate() {
        if Some(g) == kept {
            continue;
        }
        joined.unsettled += group.len();
        for i in group.iter().flat_map(|&s| stretches[s].clone()) {
            joined.marks_left_out += frames[i].iter().flatten().count();
            frames[i] = [None; 4];
            sigma[i] = [None; 4];
        }
    }
    joined
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::tuning::JoinTuning;

    /// Four marks on a tilted circle's ellipse whose phase is `a`, numbered from `first`.
    fn marks(a: f64, first: usize, jitter: f64) -> FrameMarks {
        std::array::from_fn(|j| {
            let mark = (j + first) % 4;
            let b = a + mark as f64 * std::f64::consts::FRAC_PI_2;
            let wobble = jitter * ((mark as f64 + 1.0) * (a * 37.0).sin());
            Some([320.0 + 40.0 * b.cos() - 9.0 * b.sin() + wobble, 240.0 + 26.0 * b.sin() - wobble])
        })
    }

    /// A ring turning ever slower: the phase at frame `i`.
    fn turning(i: usize) -> f64 {
        -30.0 * (1.0 - (-(i as f64) / 100.0).exp())
    }

    /// A film of `n` frames, none found in `lost`, those after it numbered from `first`.
    fn film(n: usize, lost: std::ops::Range<usize>, first: usize, extra: f64) -> Vec<FrameMarks> {
        (0..n)
            .map(|i| match i {
                i if lost.contains(&i) => [None; 4],
                i if i >= lost.end => marks(turning(i) + extra, first, 0.3),
                i => marks(turning(i), 0, 0.3),
            })
            .collect()
    }

    #[test]
    fn numbering_the_marks_one_on_turns_the_phase_a_quarter() {
        let (a, b) = (phase(&marks(0.4, 0, 0.0)).unwrap(), phase(&marks(0.4, 1, 0.0)).unwrap());
        let step = (b - a).rem_euclid(std::f64::consts::TAU);
        assert!((step - std::f64::consts::FRAC_PI_2).abs() < 1e-9, "{step}");
        let mut three = marks(0.4, 0, 0.0);
        three[2] = None;
        assert!((phase(&three).unwrap() - a).abs() < 1e-9);
    }

    #[test]
    fn dots_found_again_after_a_loss_are_numbered_as_before() {
        // 40 frames lost while the ring turns 2.7 rad: the nearest places would misnumber.
        let mut frames = film(300, 80..120, 3, 0.0);
        let mut sigma = vec![[Some(0.2); 4]; 300];
        let joined = number_across_losses(&mut frames, &mut sigma, &[120], &JoinTuning::default());
        assert_eq!(joined, Joined { settled: 1, unsettled: 0, marks_left_out: 0 });
        assert_eq!(frames, film(300, 80..120, 0, 0.0));
    }

    #[test]
    fn a_loss_the_turning_cannot_bridge_leaves_out_the_side_with_fewer_marks() {
        // Across the loss the ring turned an eighth of a turn more than its rate says: two
        // numberings fit alike. The 180 frames after it are kept, the 80 before left out.
        let extra = std::f64::consts::FRAC_PI_4;
        let mut frames = film(300, 80..120, 1, extra);
        let mut sigma = vec![[Some(0.2); 4]; 300];
        let joined = number_across_losses(&mut frames, &mut sigma, &[120], &JoinTuning::default());
        assert_eq!(joined, Joined { settled: 0, unsettled: 1, marks_left_out: 320 });
        assert!(frames[..120].iter().flatten().all(Option::is_none));
        assert!(sigma[..120].iter().flatten().all(Option::is_none));
        assert_eq!(frames[120..], film(300, 80..120, 1, extra)[120..]);
        // Found again a second time, the turning joins the last stretch to the one kept.
        let mut frames = film(300, 80..120, 1, extra);
        frames[200..210].fill([None; 4]);
        for f in &mut frames[210..] {
            f.rotate_left(2);
        }
        let mut sigma = vec![[Some(0.2); 4]; 300];
        let joined =
            number_across_losses(&mut frames, &mut sigma, &[120, 210], &JoinTuning::default());
        assert_eq!(joined, Joined { settled: 1, unsettled: 1, marks_left_out: 320 });
        let mut expected = film(300, 80..120, 1, extra);
        expected[200..210].fill([None; 4]);
        assert_eq!(frames[120..], expected[120..]);
    }
}
