//! The mismatch's signature: when in the run the baseline departs (the end: drag that grows
//! as the ring slows; all along: a missing loss; abruptly: a slide), where in the image
//! (radially from the centre: the lens), and when each model's motion ends.

use super::result::Signature;
use super::whole::WholeFit;
use crate::analysis::fit::shooting::{PredictedMarks, Shooting};
use crate::physics::{RunOptions, Simulation};
use crate::recording::FrameMarks;

/// The end of a model's motion in model time, if it ends (flat or at rest) before `t_stop`;
/// and its sliding intervals (model time).
pub fn run_end(fit: &WholeFit, sh: &Shooting, t_stop: f64) -> (Option<f64>, Vec<(f64, f64)>) {
    let t0 = fit.span.start as f64 * sh.dt;
    let opts = RunOptions {
        t_end: t_stop.max(t0 + sh.dt),
        sample_dt: None,
        track_validity: false,
        ..sh.run.clone()
    };
    let Ok(sim) = Simulation::from_state(fit.model.clone(), t0, fit.start, opts) else {
        return (None, Vec::new());
    };
    let summary = sim.run(&mut |_| {});
    let end = summary.end_reason.is_natural().then_some(summary.t_end);
    (end, summary.sliding.iter().map(|i| (i.start, i.end)).collect())
}

/// Squared-residual shares along the radius from `centre`: of model minus observed
/// (`pred` against `observed`), and of the change from `pred` to `other`.
fn radial_shares(
    observed: &[FrameMarks],
    pred: &PredictedMarks,
    other: &PredictedMarks,
    centre: [f64; 2],
) -> (f64, f64) {
    let (mut rad, mut all, mut crad, mut call) = (0.0, 0.0, 0.0, 0.0);
    for ((obs, p), q) in observed.iter().zip(pred).zip(other) {
        for k in 0..4 {
            let Some(o) = obs[k] else { continue };
            let u = [o[0] - centre[0], o[1] - centre[1]];
            let len = u[0].hypot(u[1]);
            if len < 1.0 {
                continue;
            }
            let u = [u[0] / len, u[1] / len];
            let r = [p[k][0] - o[0], p[k][1] - o[1]];
            let d = [q[k][0] - p[k][0], q[k][1] - p[k][1]];
            rad += (r[0] * u[0] + r[1] * u[1]).powi(2);
            all += r[0] * r[0] + r[1] * r[1];
            crad += (d[0] * u[0] + d[1] * u[1]).powi(2);
            call += d[0] * d[0] + d[1] * d[1];
        }
    }
    let share = |a: f64, b: f64| if b > 0.0 { a / b } else { 0.5 };
    (share(rad, all), share(crad, call))
}

/// The thirds' RMS and the last third's share of the excess over the noise, from per-frame
/// `(squared sum, count)`.
fn thirds(sums: &[(f64, usize)], noise_px: f64) -> ([f64; 3], f64) {
    let n = sums.len();
    let var = noise_px * noise_px;
    let mut rms = [f64::NAN; 3];
    let mut excess = [0.0; 3];
    for (i, part) in [0..n / 3, n / 3..2 * n / 3, 2 * n / 3..n].into_iter().enumerate() {
        let (s, c) = sums[part].iter().fold((0.0, 0usize), |a, x| (a.0 + x.0, a.1 + x.1));
        if c > 0 {
            rms[i] = (s / c as f64).sqrt();
        }
        excess[i] = (s - var * c as f64).max(0.0);
    }
    let total: f64 = excess.iter().sum();
    (rms, if total > 0.0 { excess[2] / total } else { 0.0 })
}

/// Everything of [`Signature`] but the times, which the caller converts to seconds.
pub struct Measured {
    pub thirds_rms_px: [f64; 3],
    pub late_share: f64,
    pub radial_share: f64,
    pub change_radial_share: f64,
}

pub fn measure(
    observed: &[FrameMarks],
    before_sums: &[(f64, usize)],
    before: &PredictedMarks,
    after: &PredictedMarks,
    centre: [f64; 2],
    noise_px: f64,
) -> Measured {
    let (thirds_rms_px, late_share) = thirds(before_sums, noise_px);
    let (radial_share, change_radial_share) = radial_shares(observed, before, after, centre);
    Measured { thirds_rms_px, late_share, radial_share, change_radial_share }
}

impl Signature {
    pub fn from_measured(m: Measured) -> Signature {
        Signature {
            thirds_rms_px: m.thirds_rms_px,
            late_share: m.late_share,
            radial_share: m.radial_share,
            change_radial_share: m.change_radial_share,
            ..Signature::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radial_errors_are_told_from_tangential_ones() {
        let centre = [100.0, 100.0];
        let obs: Vec<FrameMarks> =
            vec![[Some([200.0, 100.0]), Some([100.0, 300.0]), None, Some([0.0, 100.0])]];
        // Model pushed outward by 1 px: all radial; the change to `other` is tangential.
        let pred = vec![[[201.0, 100.0], [100.0, 301.0], [0.0, 0.0], [-1.0, 100.0]]];
        let other = vec![[[201.0, 101.0], [101.0, 301.0], [0.0, 0.0], [-1.0, 101.0]]];
        let (r, c) = radial_shares(&obs, &pred, &other, centre);
        assert!((r - 1.0).abs() < 1e-12 && c.abs() < 1e-12, "{r} {c}");
    }

    #[test]
    fn the_late_share_sees_an_end_mismatch() {
        let mut sums = vec![(2.0, 8); 300];
        for s in &mut sums[250..] {
            s.0 += 80.0;
        }
        let (rms, late) = thirds(&sums, 0.5);
        assert!((rms[0] - 0.5).abs() < 1e-12 && rms[2] > 1.0);
        assert!((late - 1.0).abs() < 1e-12);
    }
}
