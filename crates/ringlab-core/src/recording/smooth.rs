//! Local polynomial fits of noisy series sampled every frame, and the turning points of a
//! series with hysteresis (an extremum counts only when it stands out of the noise).

use crate::physics::TurnKind;

/// Coefficients `(c0, c1, c2)` of the weighted least-squares quadratic `c0 + c1 x + c2 x^2`,
/// `x = i - at`, through the finite points of `y` with weights `w` in `lo..=hi` (value, slope
/// per frame and half the curvature at `at`), with the standard deviations of `c0` and `c1`
/// that the weights (as inverse variances) imply. None with fewer than four points.
pub fn local_quadratic(
    y: &[f64],
    w: &[f64],
    lo: usize,
    hi: usize,
    at: f64,
) -> Option<([f64; 3], [f64; 2])> {
    // Normal equations in x = i - at: basis (1, x, x^2).
    let mut m = nalgebra::Matrix3::<f64>::zeros();
    let mut b = nalgebra::Vector3::<f64>::zeros();
    let mut n = 0;
    for i in lo..=hi.min(y.len().saturating_sub(1)) {
        let (yi, wi) = (y[i], w[i]);
        if !(yi.is_finite() && wi.is_finite() && wi > 0.0) {
            continue;
        }
        n += 1;
        let x = i as f64 - at;
        let row = nalgebra::Vector3::new(1.0, x, x * x);
        m += wi * row * row.transpose();
        b += wi * yi * row;
    }
    if n < 4 {
        return None;
    }
    let inv = m.try_inverse()?;
    let c = inv * b;
    let var = [inv[(0, 0)], inv[(1, 1)]];
    if !(var[0] >= 0.0 && var[1] >= 0.0) {
        return None;
    }
    Some(([c[0], c[1], c[2]], [var[0].sqrt(), var[1].sqrt()]))
}

/// Smoothed value, derivative per frame and their sigmas at every frame (window `+-half`,
/// shifted inward at the ends so that the ends get one-sided fits).
pub struct Smoothed {
    pub value: Vec<f64>,
    pub slope: Vec<f64>,
    pub value_sigma: Vec<f64>,
    pub slope_sigma: Vec<f64>,
}

pub fn smooth(y: &[f64], sigma: &[f64], half: usize) -> Smoothed {
    let n = y.len();
    let w: Vec<f64> =
        sigma.iter().map(|s| if s.is_finite() && *s > 0.0 { 1.0 / (s * s) } else { 0.0 }).collect();
    let mut out = Smoothed {
        value: vec![f64::NAN; n],
        slope: vec![f64::NAN; n],
        value_sigma: vec![f64::INFINITY; n],
        slope_sigma: vec![f64::INFINITY; n],
    };
    for i in 0..n {
        let lo = i.saturating_sub(half).min(n.saturating_sub(2 * half + 1));
        let hi = (lo + 2 * half).min(n - 1);
        if let Some(([v, d, _], [sv, sd])) = local_quadratic(y, &w, lo, hi, i as f64) {
            out.value[i] = v;
            out.slope[i] = d;
            out.value_sigma[i] = sv;
            out.slope_sigma[i] = sd;
        }
    }
    out
}

/// A turning point of a smoothed series: where its slope changes sign.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extremum {
    pub kind: TurnKind,
    /// Fractional frame index.
    pub at: f64,
    /// Its standard deviation: the slope's over the slope's change per frame.
    pub at_sigma: f64,
    pub value: f64,
    pub sigma: f64,
}

/// Extrema of a smoothed series; neighbouring pairs whose values differ by less than
/// `k_sigma` of their combined sigma are noise and are removed, smallest first.
pub fn extrema(s: &Smoothed, k_sigma: f64) -> Vec<Extremum> {
    let mut out: Vec<Extremum> = Vec::new();
    for i in 1..s.slope.len() {
        let (d0, d1) = (s.slope[i - 1], s.slope[i]);
        if !(d0.is_finite() && d1.is_finite()) || (d0 > 0.0) == (d1 > 0.0) || d0 == d1 {
            continue;
        }
        let f = d0 / (d0 - d1);
        let kind = if d0 > 0.0 { TurnKind::ThetaMax } else { TurnKind::ThetaMin };
        let j = if f < 0.5 { i - 1 } else { i };
        let value = s.value[i - 1] + f * (s.value[i] - s.value[i - 1]);
        let at_sigma = s.slope_sigma[j] / (d0 - d1).abs();
        out.push(Extremum {
            kind,
            at: (i - 1) as f64 + f,
            at_sigma,
            value,
            sigma: s.value_sigma[j],
        });
    }
    prune(out, k_sigma)
}

/// Removes neighbouring pairs that differ by less than `k_sigma`, weakest first, in
/// `O(n log n)`: a linked list of the extrema and a heap of pairs, stale entries skipped.
fn prune(points: Vec<Extremum>, k_sigma: f64) -> Vec<Extremum> {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    let n = points.len();
    let z = |a: &Extremum, b: &Extremum| (a.value - b.value).abs() / a.sigma.hypot(b.sigma);
    let mut prev: Vec<Option<usize>> = (0..n).map(|i| i.checked_sub(1)).collect();
    let mut next: Vec<Option<usize>> = (0..n).map(|i| (i + 1 < n).then_some(i + 1)).collect();
    let mut alive = vec![true; n];
    // Keys are z scaled to integers so that the heap orders them; ties are broken by position.
    let key = |z: f64| (z * 1e9).min(u64::MAX as f64 / 2.0) as u64;
    let mut heap = BinaryHeap::new();
    for i in 1..n {
        let zi = z(&points[i - 1], &points[i]);
        if zi < k_sigma {
            heap.push(Reverse((key(zi), i - 1, i)));
        }
    }
    while let Some(Reverse((_, a, b))) = heap.pop() {
        if !(alive[a] && alive[b] && next[a] == Some(b)) {
            continue;
        }
        alive[a] = false;
        alive[b] = false;
        let (p, q) = (prev[a], next[b]);
        if let Some(p) = p {
            next[p] = q;
        }
        if let Some(q) = q {
            prev[q] = p;
        }
        if let (Some(p), Some(q)) = (p, q) {
            let zi = z(&points[p], &points[q]);
            if zi < k_sigma {
                heap.push(Reverse((key(zi), p, q)));
            }
        }
    }
    points.into_iter().zip(alive).filter(|(_, keep)| *keep).map(|(p, _)| p).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recording::rng::Rng;

    #[test]
    fn finds_the_extrema_of_a_noisy_sine() {
        let mut rng = Rng::new(5);
        let n = 400;
        let y: Vec<f64> = (0..n).map(|i| (i as f64 * 0.2).sin() + 0.05 * rng.normal()).collect();
        let s = smooth(&y, &vec![0.05; n], 3);
        let ex = extrema(&s, 4.0);
        // sin(0.2 i) has an extremum every pi/0.2 = 15.7 frames, the first a maximum at 7.85.
        assert_eq!(ex.len(), 25, "{ex:?}");
        assert_eq!(ex[0].kind, TurnKind::ThetaMax);
        for (k, e) in ex.iter().enumerate() {
            let expected = (std::f64::consts::FRAC_PI_2 + k as f64 * std::f64::consts::PI) / 0.2;
            assert!((e.at - expected).abs() < 0.6, "extremum {k} at {} vs {expected}", e.at);
        }
    }
}
