//! `sin` and `cos` of one angle together, for the integrator's right-hand side and the marks'
//! projection, where glibc's `sincos` took over a quarter of a diagnosis's time
//! (docs/diagnosis.md). glibc's serves every argument in every rounding mode; a run's angles
//! are a few thousand radians at most. Within 2 ulp of `f64::sin_cos` (the tests below);
//! std's for larger or non-finite arguments.

/// pi/2 in three parts (Cody-Waite): the first two carry 33 bits each, so `k` times either is
/// exact for `|k| < 2^20`, and `x - k pi/2` keeps its precision.
const PIO2_1: f64 = 1.570_796_326_734_125_6;
const PIO2_2: f64 = 6.077_100_506_303_966e-11;
const PIO2_2T: f64 = 2.022_266_248_795_950_6e-21;

/// The largest `|x|` reduced here (`k` below 2^19; a run's angles stay far below it).
const REDUCED_UP_TO: f64 = 8.0e5;

/// 1.5 * 2^52: added to a number of magnitude below 2^51, the sum's last bits are that
/// number rounded to the nearest integer, without a call to `round` (a libm call on baseline
/// x86-64) or a saturating conversion.
const ROUNDER: f64 = 6_755_399_441_055_744.0;

/// `(sin x, cos x)`.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if !(x.abs() <= REDUCED_UP_TO) {
        return x.sin_cos();
    }
    let shifted = x * std::f64::consts::FRAC_2_PI + ROUNDER;
    let k = shifted - ROUNDER;
    let q = shifted.to_bits();
    let r = ((x - k * PIO2_1) - k * PIO2_2) - k * PIO2_2T;
    let (s, c) = kernel(r);
    // The quadrant q: odd swaps sine and cosine; sine is negative in 2 and 3, cosine in 1
    // and 2.
    let (a, b) = if q & 1 == 1 { (c, s) } else { (s, c) };
    let sin_sign = (q & 2) << 62;
    let cos_sign = ((q + 1) & 2) << 62;
    (f64::from_bits(a.to_bits() ^ sin_sign), f64::from_bits(b.to_bits() ^ cos_sign))
}

/// Taylor series on `|r| <= pi/4`, to `r^15` and `r^16`: the first terms left out are below
/// 5e-17.
#[inline]
fn kernel(r: f64) -> (f64, f64) {
    let z = r * r;
    let sin_tail = z
        * (-1.0 / 6.0
            + z * (1.0 / 120.0
                + z * (-1.0 / 5040.0
                    + z * (1.0 / 362_880.0
                        + z * (-1.0 / 39_916_800.0
                            + z * (1.0 / 6_227_020_800.0 + z * (-1.0 / 1_307_674_368_000.0)))))));
    let cos_tail = z
        * z
        * (1.0 / 24.0
            + z * (-1.0 / 720.0
                + z * (1.0 / 40_320.0
                    + z * (-1.0 / 3_628_800.0
                        + z * (1.0 / 479_001_600.0
                            + z * (-1.0 / 87_178_291_200.0 + z * (1.0 / 20_922_789_888_000.0)))))));
    // 1 - z/2 loses the low bits of z/2; they are put back from the rounding of w.
    let half = 0.5 * z;
    let w = 1.0 - half;
    let c = w + (((1.0 - w) - half) + cos_tail);
    (r + r * sin_tail, c)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ulp(v: f64) -> f64 {
        (f64::from_bits(v.abs().to_bits() + 1) - v.abs()).max(f64::MIN_POSITIVE)
    }

    #[test]
    fn agrees_with_std_within_two_ulp_of_one() {
        // Angles of a run: small tilts, headings of many turns, marks' spin.
        let mut worst: f64 = 0.0;
        for i in 0..400_000 {
            let x = -3_000.0 + i as f64 * 0.015_000_37;
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
        }
        assert!(worst <= 2.0 * ulp(1.0), "worst {worst:e}");
    }

    #[test]
    fn small_angles_keep_their_relative_precision() {
        for x in [1e-300, 1e-12, 3.2e-7, 0.01, -0.2] {
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            assert!((s - s0).abs() <= 2.0 * ulp(s0), "sin {x}: {s} against {s0}");
            assert!((c - c0).abs() <= 2.0 * ulp(c0), "cos {x}: {c} against {c0}");
        }
    }

    #[test]
    fn the_quadrant_edges_and_what_it_leaves_to_std() {
        use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
        for x in [FRAC_PI_4, -FRAC_PI_4, FRAC_PI_2, PI, 1.5 * PI, 2.0 * PI, 1e5, -7.9e5] {
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            assert!((s - s0).abs() <= 2.0 * ulp(1.0) && (c - c0).abs() <= 2.0 * ulp(1.0), "{x}");
        }
        assert_eq!(sin_cos(1e7), 1e7_f64.sin_cos());
        // k times the first two parts is exact: their last 20 bits are zero.
        assert_eq!((PIO2_1.to_bits() & 0xF_FFFF, PIO2_2.to_bits() & 0xF_FFFF), (0, 0));
        assert!((PIO2_1 + PIO2_2 + PIO2_2T - FRAC_PI_2).abs() <= f64::EPSILON);
        assert!(sin_cos(f64::NAN).0.is_nan() && sin_cos(f64::INFINITY).1.is_nan());
    }
}
