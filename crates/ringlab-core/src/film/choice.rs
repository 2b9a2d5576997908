//! How to weigh two estimates of each mark's centre, judged by the marks' parallelogram: seen
//! from far away, four points 90 degrees apart on a circle have coinciding midpoints of
//! opposite pairs, so the gap between those midpoints measures the centres' error (`error`).
//! Each mark takes the first estimate, their mean, or the second; each of the 81 ways has its
//! running sum of that gap squared over the frames where all eight were found, and the
//! smallest sum names the way kept. Where the two err apart, their mean errs less than either.

/// The running sums, and the frames they hold.
#[derive(Clone, Debug)]
pub struct Choice {
    gaps: [f64; WAYS],
    frames: usize,
}

impl Default for Choice {
    fn default() -> Choice {
        Choice { gaps: [0.0; WAYS], frames: 0 }
    }
}

const WAYS: usize = 81;

/// Frames of the running sums' memory.
const MEMORY: f64 = 100.0;
/// Frames seen before any but the first estimates are kept.
const SETTLE: usize = 10;

fn gap(p: [[f64; 2]; 4]) -> f64 {
    ((p[0][0] + p[2][0] - p[1][0] - p[3][0]) / 2.0).powi(2)
        + ((p[0][1] + p[2][1] - p[1][1] - p[3][1]) / 2.0).powi(2)
}

/// The second estimate's weight for mark `k` in way `way` (its base-3 digit `k`, halved).
fn weight(way: usize, k: usize) -> f64 {
    ((way / 3usize.pow(k as u32)) % 3) as f64 / 2.0
}

/// The four centres weighed as way `way` weighs them.
fn pick(first: [[f64; 2]; 4], second: [[f64; 2]; 4], way: usize) -> [[f64; 2]; 4] {
    std::array::from_fn(|k| blend(first[k], second[k], weight(way, k)))
}

/// `w` of the second with `1 - w` of the first.
pub fn blend(first: [f64; 2], second: [f64; 2], w: f64) -> [f64; 2] {
    [first[0] + w * (second[0] - first[0]), first[1] + w * (second[1] - first[1])]
}

impl Choice {
    /// A frame where both estimates of all four marks were found.
    pub fn add(&mut self, first: [[f64; 2]; 4], second: [[f64; 2]; 4]) {
        let keep = 1.0 - 1.0 / MEMORY;
        for (mask, g) in self.gaps.iter_mut().enumerate() {
            *g = keep * *g + gap(pick(first, second, mask));
        }
        self.frames += 1;
    }

    /// The weight of the second estimate for mark `k` (0, a half or 1).
    pub fn second(&self, k: usize) -> f64 {
        if self.frames < SETTLE {
            return 0.0;
        }
        let best = (0..WAYS).min_by(|&i, &j| self.gaps[i].total_cmp(&self.gaps[j])).unwrap_or(0);
        weight(best, k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_estimate_that_closes_the_parallelogram_is_kept_per_mark() {
        let truth = [[10.0, 0.0], [0.0, 6.0], [-10.0, 0.0], [0.0, -6.0]];
        let mut c = Choice::default();
        for f in 0..20 {
            let wobble = if f % 2 == 0 { 1.0 } else { -1.0 };
            // The first estimate of mark 2 and the second of mark 4 are off.
            let mut first = truth;
            first[1][0] += wobble;
            let mut second = truth;
            second[3][1] += 0.7 * wobble;
            c.add(first, second);
        }
        assert_eq!((c.second(1), c.second(3)), (1.0, 0.0));
    }
}
