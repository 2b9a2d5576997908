//! What kind of motion a run made: the paper's phases from the path of point A.
//!
//! The mean path is the polyline through A at the `theta_max` turning points (the lowest
//! centre of mass, where the walk has its cusps); one *cycle* is one `theta` oscillation, from
//! one `theta_max` to the next. Per cycle:
//! - the **turn** is the signed angle between successive chords of the mean path, counted
//!   positive when it turns with the body's spin about the table normal (`omega . Z`):
//!   prograde. This is the paper's `L . omega > 0` with `L` the orbital angular momentum of
//!   the centre of mass about the centre of the turn. (Measured from the contact point, as
//!   the paper writes `r_G`, `L . omega = |r_G|^2 |omega|^2 - (r_G . omega)^2 >= 0` under
//!   rolling for every motion, so it cannot tell a turn's direction.)
//! - the **loop**: whether A runs backwards (against the chord) at the `theta_min` turning
//!   point inside the cycle, i.e. whether the cycloid still has its inner loop.
//!
//! Phases: *prograde cycloids* while the mean path turns prograde by more than
//! [`WALK_TURN_DEG`] per cycle; the *directional walk* while it is nearly straight
//! (`|turn| <= WALK_TURN_DEG`); the *retrograde turn* from the inflection on, where the turn
//! changes sign for good (the path then revolves the other way round a new centre).

use super::run::{Sample, TurnKind, TurningPoint};

/// Turn per cycle (degrees) below which the mean path counts as a straight walk.
pub const WALK_TURN_DEG: f64 = 15.0;
/// Total retrograde turning (degrees) after the inflection for the run to count as having made
/// a retrograde turn (a quarter revolution: a spiral turn, not a wobble).
pub const RETROGRADE_MIN_TOTAL_DEG: f64 = 90.0;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    Prograde,
    Walk,
    Retrograde,
}

impl Phase {
    pub fn as_str(self) -> &'static str {
        match self {
            Phase::Prograde => "prograde",
            Phase::Walk => "walk",
            Phase::Retrograde => "retrograde",
        }
    }

    /// A sentence for the live view.
    pub fn describe(self) -> &'static str {
        match self {
            Phase::Prograde => {
                "prograde cycloids: the path loops and turns with the spin, like a coin"
            }
            Phase::Walk => {
                "directional walk: cusps joined by half-circle arcs along a nearly straight line"
            }
            Phase::Retrograde => {
                "retrograde turn: the path spirals against the spin round a new centre"
            }
        }
    }
}

/// One `theta` oscillation, from one `theta_max` to the next.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cycle {
    pub t_start: f64,
    pub t_end: f64,
    /// Signed turn of the mean path at the cycle's start (degrees, prograde positive); the
    /// first cycle has none and reports 0.
    pub turn_deg: f64,
    /// Whether A's path has an inner loop in this cycle.
    pub has_loop: bool,
    pub phase: Phase,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseSpan {
    pub phase: Phase,
    pub start: f64,
    pub end: f64,
}

/// A `theta_max` turning point with the friction it needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThetaMaxPoint {
    pub t: f64,
    pub f_f: f64,
    /// `sqrt(F_1^2 + F_f^2) / F_N`.
    pub friction_ratio: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct MotionAnalysis {
    /// +1 when the body spins counter-clockwise seen from above (`omega . Z > 0`), else -1.
    pub spin_sign: f64,
    pub cycles: Vec<Cycle>,
    pub phases: Vec<PhaseSpan>,
    /// Time of the mean path's inflection (between the two cycles where the turn changes sign
    /// for good), if it has one.
    pub inflection_time: Option<f64>,
    /// Whether the run makes the retrograde turn: an inflection followed by at least
    /// [`RETROGRADE_MIN_TOTAL_DEG`] of retrograde turning.
    pub retrograde_turn: bool,
    /// Total retrograde turning after the inflection, degrees (positive).
    pub retrograde_total_deg: f64,
    /// Cycles before the directional walk begins (all of them if it never does).
    pub prograde_cycles: usize,
    /// Cycles before the retrograde turn (the inflection); all of them if there is none.
    pub cycles_before_retrograde: usize,
    pub theta_max_points: Vec<ThetaMaxPoint>,
    pub theta_min: Vec<(f64, f64)>,
    pub theta_max: Vec<(f64, f64)>,
}

fn cross(a: (f64, f64), b: (f64, f64)) -> f64 {
    a.0 * b.1 - a.1 * b.0
}

fn dot(a: (f64, f64), b: (f64, f64)) -> f64 {
    a.0 * b.0 + a.1 * b.1
}

fn spin_about_up(s: &Sample) -> f64 {
    let (st, ct) = s.theta().sin_cos();
    s.y[4] * st + s.y[5] * ct
}

/// Analyses the turning points of a run that started with `start` and ended at `t_end`.
pub fn analyze(start: &Sample, turning_points: &[TurningPoint], t_end: f64) -> MotionAnalysis {
    let spin_sign = if spin_about_up(start) < 0.0 { -1.0 } else { 1.0 };
    let maxima: Vec<&Sample> =
        turning_points.iter().filter(|p| p.kind == TurnKind::ThetaMax).map(|p| &p.sample).collect();
    let minima: Vec<&Sample> =
        turning_points.iter().filter(|p| p.kind == TurnKind::ThetaMin).map(|p| &p.sample).collect();

    let mut cycles = Vec::new();
    for k in 0..maxima.len().saturating_sub(1) {
        let (a, b) = (maxima[k], maxima[k + 1]);
        let chord = (b.x_a - a.x_a, b.y_a - a.y_a);
        let turn_deg = if k == 0 {
            0.0
        } else {
            let p = maxima[k - 1];
            let prev = (a.x_a - p.x_a, a.y_a - p.y_a);
            spin_sign * cross(prev, chord).atan2(dot(prev, chord)).to_degrees()
        };
        let has_loop = minima
            .iter()
            .find(|m| m.t > a.t && m.t < b.t)
            .is_some_and(|m| dot((m.vx_a, m.vy_a), chord) < 0.0);
        cycles.push(Cycle { t_start: a.t, t_end: b.t, turn_deg, has_loop, phase: Phase::Prograde });
    }

    // The inflection: the last change of sign of the turn from prograde to retrograde after
    // which it stays retrograde to the end.
    let mut inflection_cycle = None;
    for k in (1..cycles.len()).rev() {
        if cycles[k].turn_deg >= 0.0 {
            break;
        }
        inflection_cycle = Some(k);
    }
    // A lone negative wobble in the last cycle is not an inflection: it needs a prograde
    // stretch before it.
    let inflection_cycle = inflection_cycle.filter(|&k| k >= 2 && cycles[k - 1].turn_deg > 0.0);
    let inflection_time = inflection_cycle.map(|k| {
        // Interpolate the zero of the turn between the cycle starts.
        let (a, b) = (&cycles[k - 1], &cycles[k]);
        let f = a.turn_deg / (a.turn_deg - b.turn_deg);
        a.t_start + f * (b.t_start - a.t_start)
    });
    let retrograde_total_deg =
        inflection_cycle.map(|k| cycles[k..].iter().map(|c| -c.turn_deg).sum()).unwrap_or(0.0);
    let retrograde_turn = retrograde_total_deg >= RETROGRADE_MIN_TOTAL_DEG;

    // Phases only move forward: prograde, then walk, then retrograde.
    let mut walk_started = false;
    for (k, c) in cycles.iter_mut().enumerate() {
        c.phase = if retrograde_turn && inflection_cycle.is_some_and(|i| k >= i) {
            Phase::Retrograde
        } else if k > 0 && (walk_started || c.turn_deg <= WALK_TURN_DEG) {
            walk_started = true;
            Phase::Walk
        } else {
            Phase::Prograde
        };
    }
    let prograde_cycles =
        cycles.iter().position(|c| c.phase != Phase::Prograde).unwrap_or(cycles.len());
    let cycles_before_retrograde =
        cycles.iter().position(|c| c.phase == Phase::Retrograde).unwrap_or(cycles.len());

    let mut phases: Vec<PhaseSpan> = Vec::new();
    for c in &cycles {
        match phases.last_mut() {
            Some(p) if p.phase == c.phase => p.end = c.t_end,
            _ => phases.push(PhaseSpan { phase: c.phase, start: c.t_start, end: c.t_end }),
        }
    }
    if let Some(first) = phases.first_mut() {
        first.start = start.t;
    }
    if let Some(last) = phases.last_mut() {
        last.end = t_end;
    }

    MotionAnalysis {
        spin_sign,
        cycles,
        phases,
        inflection_time,
        retrograde_turn,
        retrograde_total_deg,
        prograde_cycles,
        cycles_before_retrograde,
        theta_max_points: maxima
            .iter()
            .map(|s| ThetaMaxPoint { t: s.t, f_f: s.f_f, friction_ratio: s.friction_ratio() })
            .collect(),
        theta_min: minima.iter().map(|s| (s.t, s.theta())).collect(),
        theta_max: maxima.iter().map(|s| (s.t, s.theta())).collect(),
    }
}

impl MotionAnalysis {
    /// The phase at time `t` (None before the first cycle is complete).
    pub fn phase_at(&self, t: f64) -> Option<Phase> {
        self.phases.iter().find(|p| t >= p.start && t <= p.end).map(|p| p.phase)
    }
}
