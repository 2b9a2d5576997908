//! The DOP853 stepper: one accepted step at a time, dense output on demand.

use super::System;
use super::tableau::{A, B, C, D, E3, E5};
use std::fmt;

/// Relative and absolute error tolerances (per component: `atol + rtol |y|`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Tolerances {
    pub rtol: f64,
    pub atol: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances { rtol: 1e-10, atol: 1e-12 }
    }
}

/// Work done so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    pub rhs_evaluations: u64,
    pub steps: u64,
    pub rejected: u64,
}

#[derive(Clone, Debug, PartialEq)]
pub enum IntegratorError {
    /// The step size fell below what `t` can resolve: the problem is stiff or singular here.
    StepSizeTooSmall { t: f64, h: f64 },
    /// The right-hand side gave non-finite numbers that no smaller step avoids.
    NonFinite { t: f64 },
    /// The initial state or time is not finite.
    BadInitialState,
}

impl fmt::Display for IntegratorError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IntegratorError::StepSizeTooSmall { t, h } => {
                write!(f, "step size {h:e} too small at t = {t}")
            }
            IntegratorError::NonFinite { t } => write!(f, "state became non-finite at t = {t}"),
            IntegratorError::BadInitialState => f.write_str("initial state is not finite"),
        }
    }
}

impl std::error::Error for IntegratorError {}

// Controller constants. Hairer's DOP853 uses safety 0.9; on the paper's case that rejected
// about 45% of the steps (the error ratio overshoots when the step grows), while 0.8 with growth
// capped at 6 rejects about 12% and needs a sixth fewer evaluations in all (measured with
// `ringlab bench`).
const SAFETY: f64 = 0.8;
const MIN_FACTOR: f64 = 0.2;
const MAX_FACTOR: f64 = 6.0;
/// Step-size exponent `-1/(q+1)` with `q = 7`, the order of the embedded error estimate used
/// for the step size (Hairer's choice for DOP853).
const ERROR_EXPONENT: f64 = -1.0 / 8.0;

/// `sum_j c_j k_j`, skipping the tableau's zeros (at compile time where `c` is a constant row);
/// the inner loop runs over the state (axpy form), which the compiler vectorises.
#[inline(always)]
fn weighted_sum<const N: usize>(c: &[f64], k: &[[f64; N]; 16]) -> [f64; N] {
    let mut acc = [0.0; N];
    for (cj, kj) in c.iter().zip(k.iter()) {
        if *cj != 0.0 {
            for i in 0..N {
                acc[i] += cj * kj[i];
            }
        }
    }
    acc
}

/// `y + h sum_j c_j k_j`.
#[inline(always)]
fn combine<const N: usize>(y: &[f64; N], h: f64, c: &[f64], k: &[[f64; N]; 16]) -> [f64; N] {
    let acc = weighted_sum(c, k);
    let mut out = *y;
    for i in 0..N {
        out[i] += h * acc[i];
    }
    out
}

/// Integrates forward in time, one accepted step per call of [`Dop853::step`].
///
/// After a step, [`Dop853::dense`] evaluates the 7th-order interpolant anywhere in
/// `[t_prev, t]`; the three extra stages it needs are computed only on the first such call.
#[derive(Clone)]
pub struct Dop853<S, const N: usize> {
    pub system: S,
    tol: Tolerances,
    h_max: f64,
    t: f64,
    y: [f64; N],
    t_prev: f64,
    y_prev: [f64; N],
    h_next: f64,
    /// `k[0..12]`: stages of the last step (`k[0] = f(t_prev, y_prev)`), `k[12] = f(t, y)`,
    /// `k[13..16]`: the dense-output stages.
    k: [[f64; N]; 16],
    dense: [[f64; N]; 7],
    dense_ready: bool,
    stepped: bool,
    stats: Stats,
}

impl<S: System<N>, const N: usize> Dop853<S, N> {
    /// Starts at `(t0, y0)`; `h_max` bounds the step (use `f64::INFINITY` for none).
    pub fn new(
        system: S,
        t0: f64,
        y0: [f64; N],
        tol: Tolerances,
        h_max: f64,
    ) -> Result<Self, IntegratorError> {
        if !t0.is_finite() || y0.iter().any(|v| !v.is_finite()) {
            return Err(IntegratorError::BadInitialState);
        }
        let mut s = Dop853 {
            system,
            tol,
            h_max: if h_max > 0.0 { h_max } else { f64::INFINITY },
            t: t0,
            y: y0,
            t_prev: t0,
            y_prev: y0,
            h_next: 0.0,
            k: [[0.0; N]; 16],
            dense: [[0.0; N]; 7],
            dense_ready: false,
            stepped: false,
            stats: Stats::default(),
        };
        let mut f0 = [0.0; N];
        s.system.rhs(t0, &y0, &mut f0);
        s.stats.rhs_evaluations += 1;
        if f0.iter().any(|v| !v.is_finite()) {
            return Err(IntegratorError::NonFinite { t: t0 });
        }
        s.k[12] = f0;
        s.h_next = s.initial_step(&f0);
        Ok(s)
    }

    pub fn t(&self) -> f64 {
        self.t
    }
    pub fn y(&self) -> &[f64; N] {
        &self.y
    }
    /// `f(t, y)` at the current point (free: the last stage of the last step).
    pub fn dydt(&self) -> &[f64; N] {
        &self.k[12]
    }
    pub fn t_prev(&self) -> f64 {
        self.t_prev
    }
    pub fn y_prev(&self) -> &[f64; N] {
        &self.y_prev
    }
    /// `f(t_prev, y_prev)`.
    pub fn dydt_prev(&self) -> &[f64; N] {
        &self.k[0]
    }
    pub fn stats(&self) -> Stats {
        self.stats
    }
    pub fn tolerances(&self) -> Tolerances {
        self.tol
    }

    /// Hairer's starting step: from the sizes of `y0`, `f0` and a second-derivative estimate.
    fn initial_step(&mut self, f0: &[f64; N]) -> f64 {
        let (mut dnf, mut dny) = (0.0, 0.0);
        for i in 0..N {
            let sk = self.tol.atol + self.tol.rtol * self.y[i].abs();
            dnf += (f0[i] / sk).powi(2);
            dny += (self.y[i] / sk).powi(2);
        }
        let mut h = if dnf <= 1e-10 || dny <= 1e-10 { 1e-6 } else { (dny / dnf).sqrt() * 0.01 };
        h = h.min(self.h_max);
        let mut y1 = [0.0; N];
        for i in 0..N {
            y1[i] = self.y[i] + h * f0[i];
        }
        let mut f1 = [0.0; N];
        self.system.rhs(self.t + h, &y1, &mut f1);
        self.stats.rhs_evaluations += 1;
        let mut der2 = 0.0;
        for i in 0..N {
            let sk = self.tol.atol + self.tol.rtol * self.y[i].abs();
            der2 += ((f1[i] - f0[i]) / sk).powi(2);
        }
        let der2 = der2.sqrt() / h;
        let der12 = der2.abs().max(dnf.sqrt());
        let h1 =
            if !(der12 > 1e-15) { (h * 1e-3).max(1e-6) } else { (0.01 / der12).powf(1.0 / 8.0) };
        (100.0 * h).min(h1).min(self.h_max)
    }

    /// Takes one accepted step. On error the state is left at the last good point.
    pub fn step(&mut self) -> Result<(), IntegratorError> {
        let mut h = self.h_next.min(self.h_max);
        let mut rejected = false;
        let mut last_nonfinite = false;
        let f0 = self.k[12];
        self.k[0] = f0;
        loop {
            let h_min = 10.0 * (f64::EPSILON * self.t.abs()).max(f64::MIN_POSITIVE);
            if h < h_min {
                self.k[12] = f0;
                return Err(if last_nonfinite {
                    IntegratorError::NonFinite { t: self.t }
                } else {
                    IntegratorError::StepSizeTooSmall { t: self.t, h }
                });
            }
            let (y_new, err) = self.attempt(h);
            if !err.is_finite() {
                last_nonfinite = true;
                rejected = true;
                self.stats.rejected += 1;
                h *= MIN_FACTOR;
                continue;
            }
            last_nonfinite = false;
            if err <= 1.0 {
                let mut factor = if err == 0.0 {
                    MAX_FACTOR
                } else {
                    (SAFETY * err.powf(ERROR_EXPONENT)).min(MAX_FACTOR)
                };
                if rejected {
                    factor = factor.min(1.0);
                }
                self.t_prev = self.t;
                self.y_prev = self.y;
                self.t += h;
                self.y = y_new;
                self.h_next = h * factor;
                self.dense_ready = false;
                self.stepped = true;
                self.stats.steps += 1;
                return Ok(());
            }
            rejected = true;
            self.stats.rejected += 1;
            h *= (SAFETY * err.powf(ERROR_EXPONENT)).max(MIN_FACTOR);
        }
    }

    /// Takes one step to exactly `t_target`, accepted where its error ratio is at most
    /// `max_err`; false leaves the stepper as it was (the caller steps adaptively instead).
    /// Steps of a run replayed at nearby parameters make the difference of the two runs smooth
    /// in the parameters: adaptive steps would add the tolerance's jitter to a
    /// finite-difference derivative.
    pub fn step_to(&mut self, t_target: f64, max_err: f64) -> bool {
        let h = t_target - self.t;
        if !(h > 0.0) || h > self.h_max * (1.0 + 1e-12) {
            return false;
        }
        let f0 = self.k[12];
        self.k[0] = f0;
        let (y_new, err) = self.attempt(h);
        if !(err <= max_err) {
            self.k[12] = f0;
            return false;
        }
        let factor = if err == 0.0 {
            MAX_FACTOR
        } else {
            (SAFETY * err.powf(ERROR_EXPONENT)).min(MAX_FACTOR)
        };
        self.t_prev = self.t;
        self.y_prev = self.y;
        self.t = t_target;
        self.y = y_new;
        self.h_next = h * factor;
        self.dense_ready = false;
        self.stepped = true;
        self.stats.steps += 1;
        true
    }

    /// One trial step of size `h` from `(t, y)`; fills `k[1..=12]` and returns the new state
    /// and the scaled error norm (non-finite when the stages are).
    #[inline]
    fn attempt(&mut self, h: f64) -> ([f64; N], f64) {
        let t = self.t;
        let y = self.y;
        // Stage by stage with its row of the tableau a constant: the combinations then skip
        // the tableau's zeros at compile time and keep the stages in registers.
        macro_rules! stages {
            ($($s:literal)*) => {$(
                let ys = combine(&y, h, &A[$s][..$s], &self.k);
                self.system.rhs(t + C[$s] * h, &ys, &mut self.k[$s]);
            )*};
        }
        stages!(1 2 3 4 5 6 7 8 9 10 11);
        let y_new = combine(&y, h, &B, &self.k);
        self.system.rhs(t + h, &y_new, &mut self.k[12]);
        self.stats.rhs_evaluations += 12;

        let e5 = weighted_sum(&E5, &self.k);
        let e3 = weighted_sum(&E3, &self.k);
        let (mut err5, mut err3) = (0.0, 0.0);
        for i in 0..N {
            let sc = self.tol.atol + self.tol.rtol * y[i].abs().max(y_new[i].abs());
            err5 += (e5[i] / sc).powi(2);
            err3 += (e3[i] / sc).powi(2);
        }
        let den = err5 + 0.01 * err3;
        let err = if den > 0.0 { h.abs() * err5 / (den * N as f64).sqrt() } else { 0.0 };
        if y_new.iter().any(|v| !v.is_finite()) {
            return (y_new, f64::NAN);
        }
        (y_new, err)
    }

    /// Computes the three extra stages and the interpolant coefficients of the last step.
    fn prepare_dense(&mut self) {
        if self.dense_ready {
            return;
        }
        let h = self.t - self.t_prev;
        let y0 = self.y_prev;
        macro_rules! stages {
            ($($s:literal)*) => {$(
                let ys = combine(&y0, h, &A[$s][..$s], &self.k);
                self.system.rhs(self.t_prev + C[$s] * h, &ys, &mut self.k[$s]);
            )*};
        }
        stages!(13 14 15);
        self.stats.rhs_evaluations += 3;
        for i in 0..N {
            let dy = self.y[i] - y0[i];
            self.dense[0][i] = dy;
            self.dense[1][i] = h * self.k[0][i] - dy;
            self.dense[2][i] = 2.0 * dy - h * (self.k[12][i] + self.k[0][i]);
        }
        macro_rules! rows {
            ($($r:literal)*) => {$(
                let acc = weighted_sum(&D[$r], &self.k);
                for i in 0..N {
                    self.dense[3 + $r][i] = h * acc[i];
                }
            )*};
        }
        rows!(0 1 2 3);
        self.dense_ready = true;
    }

    /// Changes the system between steps (a parameter of the right-hand side that the caller
    /// updates as the run goes, e.g. the sliding contact's reference direction). The last
    /// step's dense output is completed first with the old system, so it stays that of the
    /// step as integrated; `f(t, y)`, with which the next step starts, is recomputed.
    pub fn update_system(&mut self, change: impl FnOnce(&mut S)) {
        if self.stepped {
            self.prepare_dense();
        }
        change(&mut self.system);
        let mut f = [0.0; N];
        self.system.rhs(self.t, &self.y, &mut f);
        self.stats.rhs_evaluations += 1;
        self.k[12] = f;
    }

    /// The state at `t` in `[t_prev, t]` of the last step (7th-order interpolant).
    /// Before the first step it returns the initial state.
    pub fn dense(&mut self, t: f64) -> [f64; N] {
        if !self.stepped {
            return self.y;
        }
        if t == self.t {
            return self.y;
        }
        if t == self.t_prev {
            return self.y_prev;
        }
        self.prepare_dense();
        let x = (t - self.t_prev) / (self.t - self.t_prev);
        let xm = 1.0 - x;
        let c = &self.dense;
        let mut out = [0.0; N];
        for i in 0..N {
            let v = c[5][i] + x * c[6][i];
            let v = c[4][i] + xm * v;
            let v = c[3][i] + x * v;
            let v = c[2][i] + xm * v;
            let v = c[1][i] + x * v;
            let v = c[0][i] + xm * v;
            out[i] = self.y_prev[i] + x * v;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Oscillator;
    impl System<2> for Oscillator {
        fn rhs(&self, _t: f64, y: &[f64; 2], dy: &mut [f64; 2]) {
            dy[0] = y[1];
            dy[1] = -y[0];
        }
    }

    /// Kepler problem with eccentricity `e`: period 2 pi, exact return to the start.
    struct Kepler;
    impl System<4> for Kepler {
        fn rhs(&self, _t: f64, y: &[f64; 4], dy: &mut [f64; 4]) {
            let r3 = (y[0] * y[0] + y[1] * y[1]).powf(1.5);
            dy[0] = y[2];
            dy[1] = y[3];
            dy[2] = -y[0] / r3;
            dy[3] = -y[1] / r3;
        }
    }

    struct Blowup;
    impl System<1> for Blowup {
        fn rhs(&self, _t: f64, y: &[f64; 1], dy: &mut [f64; 1]) {
            dy[0] = y[0] * y[0];
        }
    }

    fn integrate_to<S: System<N>, const N: usize>(s: &mut Dop853<S, N>, t_end: f64) {
        while s.t() < t_end {
            s.step().expect("step");
        }
    }

    #[test]
    fn oscillator_and_its_dense_output_are_exact_to_tolerance() {
        let tol = Tolerances { rtol: 1e-12, atol: 1e-12 };
        let mut s = Dop853::new(Oscillator, 0.0, [0.0, 1.0], tol, f64::INFINITY).unwrap();
        let mut worst: f64 = 0.0;
        while s.t() < 100.0 {
            s.step().unwrap();
            // Dense output at points inside every step.
            for f in [0.1, 0.37, 0.5, 0.81] {
                let t = s.t_prev() + f * (s.t() - s.t_prev());
                let y = s.dense(t);
                worst = worst.max((y[0] - t.sin()).abs()).max((y[1] - t.cos()).abs());
            }
        }
        assert!(worst < 2e-10, "dense output error {worst:e} over 100 time units");
        assert!(s.stats().steps < 2000, "{} steps", s.stats().steps);
    }

    #[test]
    fn kepler_orbit_closes_after_ten_periods() {
        let e: f64 = 0.6;
        let y0 = [1.0 - e, 0.0, 0.0, ((1.0 + e) / (1.0 - e)).sqrt()];
        let t_end = 20.0 * std::f64::consts::PI;
        for (rtol, limit) in [(1e-8, 5e-4), (1e-11, 5e-7)] {
            let tol = Tolerances { rtol, atol: rtol };
            let mut s = Dop853::new(Kepler, 0.0, y0, tol, f64::INFINITY).unwrap();
            integrate_to(&mut s, t_end);
            let y = s.dense(t_end);
            let err = (0..4).map(|i| (y[i] - y0[i]).abs()).fold(0.0, f64::max);
            assert!(err < limit, "rtol {rtol}: error {err:e} after ten orbits");
        }
    }

    #[test]
    fn error_falls_with_the_tolerance_at_high_order() {
        // Tightening rtol by 1e3 should cut the global error by roughly 1e3
        // while the work grows by about 1e3^(1/8) = 2.4 (an 8th-order method).
        let run = |rtol: f64| {
            let tol = Tolerances { rtol, atol: rtol };
            let mut s = Dop853::new(Oscillator, 0.0, [0.0, 1.0], tol, f64::INFINITY).unwrap();
            integrate_to(&mut s, 50.0);
            let y = s.dense(50.0);
            ((y[0] - 50f64.sin()).abs(), s.stats().rhs_evaluations as f64)
        };
        let (e1, n1) = run(1e-6);
        let (e2, n2) = run(1e-9);
        assert!(e2 < e1 / 100.0, "errors {e1:e} -> {e2:e}");
        assert!(n2 / n1 < 4.0, "work grew {:.2}x", n2 / n1);
    }

    #[test]
    fn a_singularity_is_reported_not_hidden() {
        // y' = y^2, y(0) = 1 blows up at t = 1.
        let mut s = Dop853::new(Blowup, 0.0, [1.0], Tolerances::default(), f64::INFINITY).unwrap();
        let err = loop {
            if let Err(e) = s.step() {
                break e;
            }
            assert!(s.t() < 1.0 + 1e-9, "stepped past the singularity to {}", s.t());
        };
        assert!(matches!(
            err,
            IntegratorError::StepSizeTooSmall { .. } | IntegratorError::NonFinite { .. }
        ));
        assert!(s.y()[0].is_finite(), "state left non-finite");
    }

    #[test]
    fn non_finite_start_is_refused() {
        assert_eq!(
            Dop853::new(Oscillator, 0.0, [f64::NAN, 1.0], Tolerances::default(), 1.0).err(),
            Some(IntegratorError::BadInitialState)
        );
    }
}
