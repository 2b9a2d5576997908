//! What a run produced, in the forms the CLI and the window hand out: the JSON summary and
//! the sample table (CSV).

use crate::physics::motion::{self, MotionAnalysis};
use crate::physics::{EffectKind, Effects, Interval, RunSummary, Sample};
use serde::Serialize;
use std::io::{self, Write};

/// Columns of the sample CSV, in order.
pub const CSV_COLUMNS: &[&str] = &[
    "t",
    "phi",
    "theta",
    "psi",
    "w1",
    "w2",
    "w3",
    "x_c",
    "y_c",
    "z_c",
    "x_a",
    "y_a",
    "x_p",
    "y_p",
    "v_p",
    "f_1",
    "f_f",
    "f_n",
    "energy",
    "reynolds",
    "sliding",
    "slip_speed",
];

/// A sample's values in the order of [`CSV_COLUMNS`] (sliding as 0 or 1).
pub fn sample_row(s: &Sample) -> [f64; 22] {
    let y = &s.y;
    [
        s.t,
        y[0],
        y[1],
        y[2],
        y[3],
        y[4],
        y[5],
        y[6],
        y[7],
        s.z_c,
        s.x_a,
        s.y_a,
        s.x_p,
        s.y_p,
        s.v_p,
        s.f_1,
        s.f_f,
        s.f_n,
        s.energy,
        s.reynolds,
        if s.sliding { 1.0 } else { 0.0 },
        s.slip_speed,
    ]
}

/// Writes samples as CSV with a header line.
pub fn write_samples_csv(out: &mut impl Write, samples: &[Sample]) -> io::Result<()> {
    writeln!(out, "{}", CSV_COLUMNS.join(","))?;
    for s in samples {
        let row = sample_row(s).map(|v| v.to_string());
        writeln!(out, "{}", row.join(","))?;
    }
    Ok(())
}

/// An effect beyond the paper's model that the run had on.
#[derive(Clone, Debug, Serialize)]
pub struct EffectJson {
    pub name: &'static str,
    pub strength: f64,
    /// What the strength is.
    pub parameter: &'static str,
}

#[derive(Clone, Debug, Serialize)]
pub struct PhaseJson {
    pub phase: &'static str,
    pub start: f64,
    pub end: f64,
}

/// The JSON object of `ringlab simulate --json`.
#[derive(Clone, Debug, Serialize)]
pub struct RunReport {
    pub case: String,
    pub units: &'static str,
    pub t_end: f64,
    pub end_reason: &'static str,
    pub retrograde_turn: bool,
    pub inflection_time: Option<f64>,
    pub prograde_cycles: usize,
    pub cycles_before_retrograde: usize,
    pub retrograde_total_deg: f64,
    pub phases: Vec<PhaseJson>,
    /// Intervals `[start, end]` where `F_N <= 0`.
    pub lift_off: Vec<[f64; 2]>,
    /// Intervals where `sqrt(F_1^2 + F_f^2) > mu F_N` (pure rolling; with the slip effect
    /// the contact slides there, see `sliding`).
    pub slip: Vec<[f64; 2]>,
    pub mu: f64,
    /// The effects beyond the paper's model (empty: the paper's model).
    pub effects: Vec<EffectJson>,
    /// Friction coefficient of the sliding contact (slip effect), if on.
    pub slip_mu: Option<f64>,
    /// Intervals where the contact slides (slip effect).
    pub sliding: Vec<[f64; 2]>,
    /// Total time spent sliding.
    pub sliding_total: f64,
    /// Largest slip speed removed at a stick (creep level).
    pub stick_residual: f64,
    pub friction_ratio_at_theta_max: Vec<f64>,
    pub f_f_at_theta_max: Vec<[f64; 2]>,
    /// `[t, theta]` at each minimum and maximum of theta.
    pub theta_min: Vec<[f64; 2]>,
    pub theta_max: Vec<[f64; 2]>,
    pub energy_start: f64,
    pub energy_end: f64,
    pub rhs_evaluations: u64,
    pub steps: u64,
    pub rejected_steps: u64,
    pub compute_seconds: f64,
    pub error: Option<String>,
}

fn pairs(v: &[Interval]) -> Vec<[f64; 2]> {
    v.iter().map(|i| [i.start, i.end]).collect()
}

impl RunReport {
    pub fn new(
        case: &str,
        units: &'static str,
        mu: f64,
        start: &Sample,
        summary: &RunSummary,
        motion: &MotionAnalysis,
        compute_seconds: f64,
    ) -> RunReport {
        RunReport {
            case: case.to_string(),
            units,
            t_end: summary.t_end,
            end_reason: summary.end_reason.as_str(),
            retrograde_turn: motion.retrograde_turn,
            inflection_time: motion.inflection_time,
            prograde_cycles: motion.prograde_cycles,
            cycles_before_retrograde: motion.cycles_before_retrograde,
            retrograde_total_deg: motion.retrograde_total_deg,
            phases: motion
                .phases
                .iter()
                .map(|p| PhaseJson { phase: p.phase.as_str(), start: p.start, end: p.end })
                .collect(),
            lift_off: pairs(&summary.lift_off),
            slip: pairs(&summary.slip),
            mu,
            effects: Vec::new(),
            slip_mu: None,
            sliding: pairs(&summary.sliding),
            sliding_total: summary.sliding.iter().map(|i| i.end - i.start).sum(),
            stick_residual: summary.stick_residual,
            friction_ratio_at_theta_max: motion
                .theta_max_points
                .iter()
                .map(|p| p.friction_ratio)
                .collect(),
            f_f_at_theta_max: motion.theta_max_points.iter().map(|p| [p.t, p.f_f]).collect(),
            theta_min: motion.theta_min.iter().map(|&(t, th)| [t, th]).collect(),
            theta_max: motion.theta_max.iter().map(|&(t, th)| [t, th]).collect(),
            energy_start: start.energy,
            energy_end: summary.final_sample.energy,
            rhs_evaluations: summary.stats.rhs_evaluations,
            steps: summary.stats.steps,
            rejected_steps: summary.stats.rejected,
            compute_seconds,
            error: summary.error.as_ref().map(|e| e.to_string()),
        }
    }

    /// Records the effects the run had on (as given by name and strength, and the model's).
    pub fn set_effects(&mut self, effects: &Effects, named: &[(EffectKind, f64)]) {
        self.effects = named
            .iter()
            .map(|&(k, x)| EffectJson { name: k.name(), strength: x, parameter: k.parameter() })
            .collect();
        self.slip_mu = effects.slip_mu;
    }

    /// A few lines for a person: the outcome and every breach of the model's assumptions.
    pub fn human(&self) -> String {
        let mut s = String::new();
        let fmt_iv = |v: &[[f64; 2]]| {
            let one = |i: &[f64; 2]| format!("[{:.3}, {:.3}]", i[0], i[1]);
            if v.len() <= 6 {
                return v.iter().map(one).collect::<Vec<_>>().join(", ");
            }
            let total: f64 = v.iter().map(|i| i[1] - i[0]).sum();
            format!(
                "{} intervals ({:.3} in all): {}, {}, ..., {} (all of them in --json)",
                v.len(),
                total,
                one(&v[0]),
                one(&v[1]),
                one(&v[v.len() - 1])
            )
        };
        s += &format!("case {} ({})\n", self.case, self.units);
        for e in &self.effects {
            s += &format!("effect {} = {} ({})\n", e.name, e.strength, e.parameter);
        }
        s += &format!("ended: {} at t = {:.4}\n", self.end_reason, self.t_end);
        if let Some(e) = &self.error {
            s += &format!("integrator: {e}\n");
        }
        for p in &self.phases {
            s += &format!("  {:<10} t in [{:.2}, {:.2}]\n", p.phase, p.start, p.end);
        }
        s += &format!(
            "retrograde turn: {}{}; {} prograde cycles before the walk, {} cycles before the retrograde turn\n",
            if self.retrograde_turn { "yes" } else { "no" },
            self.inflection_time
                .map(|t| format!(" (inflection at t = {t:.2})"))
                .unwrap_or_default(),
            self.prograde_cycles,
            self.cycles_before_retrograde
        );
        if !self.lift_off.is_empty() {
            s += &format!(
                "MODEL INVALID: F_N <= 0 (the body would leave the table) for t in {}\n",
                fmt_iv(&self.lift_off)
            );
        }
        if let Some(mu) = self.slip_mu {
            if self.sliding.is_empty() {
                s += &format!("sliding contact (mu = {mu}): it never slid\n");
            } else {
                s += &format!(
                    "sliding contact (mu = {mu}): slid {:.3} of the time, for t in {}\n",
                    self.sliding_total,
                    fmt_iv(&self.sliding)
                );
            }
        }
        if !self.slip.is_empty() {
            s += &format!(
                "MODEL INVALID: rolling needs more friction than mu = {} gives (it would slip) for t in {}\n",
                self.mu,
                fmt_iv(&self.slip)
            );
        }
        s += &format!(
            "energy {:.6} -> {:.6}; {} steps, {} right-hand-side evaluations, {:.2} ms\n",
            self.energy_start,
            self.energy_end,
            self.steps,
            self.rhs_evaluations,
            self.compute_seconds * 1e3
        );
        s
    }
}

/// Runs the motion analysis on a finished run.
pub fn analyze(start: &Sample, summary: &RunSummary) -> MotionAnalysis {
    motion::analyze(start, &summary.turning_points, summary.t_end)
}
