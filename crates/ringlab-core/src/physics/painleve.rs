//! Painleve's bound on the sliding friction coefficient (see [`super::slip`]): the sliding
//! solve for `F_N` divides by `1 - kappa m_1 / I_1`, which large `mu` can drive to zero. It
//! depends on the body and the rolling-friction arm only, so the model's parameter checks use
//! it without the sliding equations.

use super::body::Body;
use std::f64::consts::FRAC_PI_2;

/// The smallest value of `1 - kappa m_1 / I_1` that [`mu_limit`] allows.
const PAINLEVE_MARGIN: f64 = 0.25;

pub const PAINLEVE_REASON: &str = "is too large for this body: sliding friction would make the normal force ill-defined (Painleve's paradox; slip::painleve_mu_limit gives the bound)";

/// The largest `mu` for which the sliding solve stays well posed with a margin, for every tilt
/// `theta` in `[0, pi/2]` and every slip direction: `1 - kappa m_1 / I_1 >= 1/4` when
/// `mu z_C |kappa| <= (3/4) I_1 + kappa^2 - |kappa| k_r` (`k_r` the rolling-friction arm).
pub fn mu_limit(b: &Body, k_r: f64) -> f64 {
    let (a, r, i1) = (0.5 * b.h, b.r, b.inertia.x);
    // Every run of a slip model checks it (`Model::check_effects`), and a diagnosis makes
    // thousands of runs of one body: the last answer kept per thread.
    let key = [a, r, i1, k_r].map(f64::to_bits);
    LAST.with(|last| match last.get() {
        Some((k, limit)) if k == key => limit,
        _ => {
            let limit = scan(a, r, i1, k_r);
            last.set(Some((key, limit)));
            limit
        }
    })
}

thread_local! {
    static LAST: std::cell::Cell<Option<([u64; 4], f64)>> = const { std::cell::Cell::new(None) };
}

/// [`mu_limit`] by its scan over the tilt.
fn scan(a: f64, r: f64, i1: f64, k_r: f64) -> f64 {
    let mut limit = f64::INFINITY;
    let n = 2000;
    for k in 0..=n {
        let (st, ct) = (FRAC_PI_2 * k as f64 / n as f64).sin_cos();
        let kappa = (a * ct - r * st).abs();
        let z_c = a * st + r * ct;
        if kappa > 0.0 {
            let mu = ((1.0 - PAINLEVE_MARGIN) * i1 + kappa * kappa - kappa * k_r) / (kappa * z_c);
            limit = limit.min(mu.max(0.0));
        }
    }
    limit
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::body::Shape;

    #[test]
    fn the_kept_limit_is_the_scan_of_the_body_asked_for() {
        let ring = Body::new(Shape::Ring, 20.66, 18.0, 1.0).expect("a ring");
        let disk = Body::new(Shape::Disk, 20.0, 4.0, 1.0).expect("a disk");
        let scan_of = |b: &Body, k_r: f64| scan(0.5 * b.h, b.r, b.inertia.x, k_r);
        // Alternating bodies and arms: each answer is its own scan's, not the last one kept.
        for (b, k_r) in [(&ring, 0.0), (&ring, 0.0), (&disk, 0.0), (&ring, 0.01), (&ring, 0.0)] {
            assert_eq!(mu_limit(b, k_r), scan_of(b, k_r));
        }
        assert_ne!(scan_of(&ring, 0.0), scan_of(&disk, 0.0));
        assert_ne!(scan_of(&ring, 0.0), scan_of(&ring, 0.01));
    }
}
