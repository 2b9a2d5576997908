//! Scalar root bracketing for event location on the dense output.

/// Finds `t` between `a` and `b` with `g(t) = 0`, given `g(a) = ga` and `g(b) = gb` of
/// opposite signs (or one of them zero). Anderson-Bjorck regula falsi: it keeps a bracket and
/// converges superlinearly on the smooth functions the interpolant gives. Stops when the
/// bracket is below `t_tol` (or after 200 iterations) and returns its end with the smaller `|g|`.
pub fn find_root(
    mut g: impl FnMut(f64) -> f64,
    a: f64,
    b: f64,
    ga: f64,
    gb: f64,
    t_tol: f64,
) -> f64 {
    if ga == 0.0 {
        return a;
    }
    if gb == 0.0 {
        return b;
    }
    // Invariant: the root lies between `a` and `b`; `b` is the newest point.
    let (mut a, mut b, mut ga, mut gb) = (a, b, ga, gb);
    for _ in 0..200 {
        if (b - a).abs() <= t_tol {
            break;
        }
        let mut t = (a * gb - b * ga) / (gb - ga);
        let (lo, hi) = (a.min(b), a.max(b));
        if !(t > lo && t < hi) {
            t = 0.5 * (a + b);
        }
        let gt = g(t);
        if gt == 0.0 || !gt.is_finite() {
            return t;
        }
        if (gt < 0.0) != (gb < 0.0) {
            // Sign change between b and t: b becomes the far end.
            a = b;
            ga = gb;
        } else {
            // Same side as b: the far end `a` is kept, its value damped so it does not stick.
            let m = 1.0 - gt / gb;
            ga *= if m > 0.0 { m } else { 0.5 };
        }
        b = t;
        gb = gt;
    }
    if ga.abs() < gb.abs() { a } else { b }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_simple_roots() {
        let r = find_root(|t| t * t - 2.0, 0.0, 2.0, -2.0, 2.0, 1e-14);
        assert!((r - 2f64.sqrt()).abs() < 1e-13);
        let r = find_root(|t: f64| t.cos(), 0.0, 3.0, 1.0, 3f64.cos(), 1e-14);
        assert!((r - std::f64::consts::FRAC_PI_2).abs() < 1e-13);
        let r = find_root(|t: f64| (t - 1.0).powi(3), 0.0, 3.0, -1.0, 8.0, 1e-13);
        assert!((r - 1.0).abs() < 1e-4);
        let r = find_root(|t: f64| 1.0 - t, 0.0, 3.0, 1.0, -2.0, 1e-14);
        assert!((r - 1.0).abs() < 1e-14);
    }
}
