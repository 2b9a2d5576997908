//! Dormand and Prince's fifth-order formula along step ends that another run chose, with cubic
//! Hermite output: the least squares' derivative columns (`analysis::fit`).
//!
//! Why: a forward-difference column is the difference of two runs at nearby parameters, and
//! what it needs is that both share one discretization (`physics::run`'s `steps.rs`) accurate
//! enough that the column is the model's derivative, not DOP853's order and error control.
//! Six right-hand sides a step (the seventh stage is the slope at the end, the next step's
//! first) against DOP853's twelve and its dense output's three. The order matters: classical
//! RK4 on those steps was tried and left the fits of a model that lacks an effect at another,
//! worse point (their gradient is the Jacobian times large residuals, so a Jacobian a few
//! percent off moves where it vanishes); see docs/diagnosis-history.md.

use super::System;

/// The states at `t0 + i dt` for `i < n`, from `y0` at `t0`, by one fifth-order step to each
/// of `ends` beyond `t0` in turn; with the steps taken. None where the ends stop before the
/// last frame or a state is not finite.
pub fn dp5_along<S: System<N>, const N: usize>(
    system: &S,
    t0: f64,
    y0: [f64; N],
    ends: &[f64],
    dt: f64,
    n: usize,
) -> Option<(Vec<[f64; N]>, u64)> {
    let mut out = Vec::with_capacity(n);
    if n == 0 {
        return Some((out, 0));
    }
    out.push(y0);
    let (mut t, mut y) = (t0, y0);
    let mut f = [0.0; N];
    system.rhs(t, &y, &mut f);
    let mut steps = 0;
    for &end in ends {
        if out.len() == n {
            break;
        }
        // Ends at or before where the run is (the start, or a kept run's restart) are passed.
        if end <= t + 1e-12 * t.abs().max(1.0) {
            continue;
        }
        let h = end - t;
        let (y_end, f_end) = dp5_step(system, t, &y, &f, h);
        if y_end.iter().chain(&f_end).any(|v| !v.is_finite()) {
            return None;
        }
        steps += 1;
        while out.len() < n {
            let ts = t0 + out.len() as f64 * dt;
            if ts > end {
                break;
            }
            out.push(hermite(&y, &f, &y_end, &f_end, h, (ts - t) / h));
        }
        (t, y, f) = (end, y_end, f_end);
    }
    (out.len() == n).then_some((out, steps))
}

/// One step of size `h` from `(t, y)` with slope `f` there: the end state by the fifth-order
/// solution of Dormand and Prince's 5(4) pair, and the slope at it.
#[inline]
fn dp5_step<S: System<N>, const N: usize>(
    system: &S,
    t: f64,
    y: &[f64; N],
    f: &[f64; N],
    h: f64,
) -> ([f64; N], [f64; N]) {
    let k1 = f;
    let (mut k2, mut k3, mut k4, mut k5, mut k6) =
        ([0.0; N], [0.0; N], [0.0; N], [0.0; N], [0.0; N]);
    let y2: [f64; N] = std::array::from_fn(|i| y[i] + h * (A21 * k1[i]));
    system.rhs(t + C2 * h, &y2, &mut k2);
    let y3: [f64; N] = std::array::from_fn(|i| y[i] + h * (A31 * k1[i] + A32 * k2[i]));
    system.rhs(t + C3 * h, &y3, &mut k3);
    let y4: [f64; N] =
        std::array::from_fn(|i| y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]));
    system.rhs(t + C4 * h, &y4, &mut k4);
    let y5: [f64; N] =
        std::array::from_fn(|i| y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i]));
    system.rhs(t + C5 * h, &y5, &mut k5);
    let y6: [f64; N] = std::array::from_fn(|i| {
        y[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i])
    });
    system.rhs(t + h, &y6, &mut k6);
    let y_end: [f64; N] = std::array::from_fn(|i| {
        y[i] + h * (B1 * k1[i] + B3 * k3[i] + B4 * k4[i] + B5 * k5[i] + B6 * k6[i])
    });
    let mut f_end = [0.0; N];
    system.rhs(t + h, &y_end, &mut f_end);
    (y_end, f_end)
}

// Dormand & Prince (1980), the fifth-order weights (Hairer, Norsett & Wanner, *Solving ODEs
// I*, table II.5.2).
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;

/// The cubic through `(y0, f0)` and `(y1, f1)` over a step of `h`, at the fraction `s`.
#[inline]
fn hermite<const N: usize>(
    y0: &[f64; N],
    f0: &[f64; N],
    y1: &[f64; N],
    f1: &[f64; N],
    h: f64,
    s: f64,
) -> [f64; N] {
    let (s2, s3) = (s * s, s * s * s);
    let (a0, b0) = (2.0 * s3 - 3.0 * s2 + 1.0, (s3 - 2.0 * s2 + s) * h);
    let (a1, b1) = (3.0 * s2 - 2.0 * s3, (s3 - s2) * h);
    std::array::from_fn(|i| a0 * y0[i] + b0 * f0[i] + a1 * y1[i] + b1 * f1[i])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// y'' = -y as a first-order system.
    struct Oscillator;
    impl System<2> for Oscillator {
        fn rhs(&self, _t: f64, y: &[f64; 2], dy: &mut [f64; 2]) {
            *dy = [y[1], -y[0]];
        }
    }

    /// The largest error at the frames, sampled every `dt` over 10 s by steps of `h`.
    fn error(h: f64, dt: f64) -> f64 {
        let ends: Vec<f64> = (1..=(10.5 / h).round() as usize).map(|i| i as f64 * h).collect();
        let n = (10.0 / dt).round() as usize;
        let (ys, steps) = dp5_along(&Oscillator, 0.0, [0.0, 1.0], &ends, dt, n).unwrap();
        assert!(steps as usize <= ends.len());
        ys.iter().enumerate().map(|(i, y)| (y[0] - (dt * i as f64).sin()).abs()).fold(0.0, f64::max)
    }

    #[test]
    fn steps_to_fifth_order_at_the_ends_and_interpolates_between() {
        // Frames on the step ends: halving the step cuts the error about 32 times (order 5).
        let (coarse, fine) = (error(0.1, 0.1), error(0.05, 0.05));
        assert!(coarse < 1e-7, "error {coarse:e} at h = 0.1");
        assert!(coarse / fine > 25.0, "ratio {}", coarse / fine);
        // Frames between the ends: the cubic's own error, far below a pixel's share.
        let between = error(0.1, 0.07);
        assert!(between < 1e-5, "error {between:e} between the ends");
    }

    #[test]
    fn gives_none_where_the_ends_stop_short_or_the_state_blows_up() {
        assert!(dp5_along(&Oscillator, 0.0, [0.0, 1.0], &[0.5, 1.0], 0.1, 20).is_none());
        assert!(dp5_along(&Oscillator, 0.0, [f64::NAN, 1.0], &[0.5, 1.0], 0.1, 5).is_none());
        // Ends at or before the start are passed over; the start is the first sample.
        let (ys, steps) =
            dp5_along(&Oscillator, 1.0, [0.0, 1.0], &[0.5, 1.0, 1.5], 0.1, 3).unwrap();
        assert_eq!((ys[0], steps), ([0.0, 1.0], 1));
    }
}
