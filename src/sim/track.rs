//! What the UI keeps of a run: the states received so far (bounded), its turning points, the
//! intervals where the model is invalid, the phase analysis, and the state at any time between
//! two received ones.

use super::event::{Event, RunEnd};
use crate::config::Case;
use crate::physics::motion::{MotionAnalysis, Phase, analyze};
use crate::physics::run::{IntervalTracker, TurnKind};
use crate::physics::{Interval, Sample, TurningPoint};

/// States kept before the track thins itself out (every other state dropped, and from then on
/// only every `stride`-th kept): about 24 MB, 6,000 model time units of the paper ring at its
/// output spacing, far beyond any preset's run.
pub const MAX_SAMPLES: usize = 120_000;

/// Largest turn of the heading `phi` between two drawn points of a path (rad). Near the end
/// `phi` turns by a radian or more between output states and A and P run round small loops.
const PATH_MAX_TURN: f64 = 0.2;

/// A point of the drawn paths: A (the centre of the top edge) and the contact point P.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathPoint {
    pub t: f64,
    pub a: [f64; 2],
    pub p: [f64; 2],
}

impl PathPoint {
    fn of(s: &Sample) -> PathPoint {
        PathPoint { t: s.t, a: [s.x_a, s.y_a], p: [s.x_p, s.y_p] }
    }
}

/// A state at a display time: the received states around it, blended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StateAt {
    pub sample: Sample,
    /// Whether the time lies beyond the last state (the run ended or the worker is behind).
    pub clamped: bool,
}

#[derive(Clone, Debug)]
pub struct Track {
    run: u64,
    case: Case,
    start: Option<Sample>,
    samples: Vec<Sample>,
    stride: usize,
    received: usize,
    turning: Vec<TurningPoint>,
    /// Invalid intervals: exact ones of earlier runs this one continues, then live ones found
    /// from the states (replaced by the exact ones when the run ends).
    lift_off: Intervals,
    slip: Intervals,
    end: Option<RunEnd>,
    failed: Option<String>,
    analysis: Option<MotionAnalysis>,
    /// Where the current run took over from an earlier one (continue with new drag).
    continued_at: Option<f64>,
}

/// Intervals where a condition held, built from the stream of states; a continued run's
/// exact intervals spliced in ([`replace_from`]).
type Intervals = IntervalTracker;

/// Keeps what lies before `t0` in `ints` and appends the exact intervals of a run from `t0`.
fn replace_from(ints: &mut Intervals, t0: f64, exact: &[Interval]) {
    let mut kept = ints.until(t0);
    kept.retain(|i| i.end < t0 || i.start < t0);
    // An interval open across t0 is continued by the exact one starting at t0.
    if let (Some(last), Some(first)) = (kept.last_mut(), exact.first())
        && last.end >= t0
        && first.start <= t0
    {
        last.end = first.end;
        kept.extend_from_slice(&exact[1..]);
        ints.closed = kept;
        ints.open = None;
        return;
    }
    kept.extend_from_slice(exact);
    ints.closed = kept;
    ints.open = None;
}

impl Track {
    pub fn new(run: u64, case: Case) -> Track {
        Track {
            run,
            case,
            start: None,
            samples: Vec::new(),
            stride: 1,
            received: 0,
            turning: Vec::new(),
            lift_off: Intervals::default(),
            slip: Intervals::default(),
            end: None,
            failed: None,
            analysis: None,
            continued_at: None,
        }
    }

    /// A finished track computed here and now, without a thread (headless renders, tests).
    pub fn compute(case: Case) -> Track {
        let mut track = Track::new(1, case.clone());
        let opts = case.opts.clone();
        match crate::physics::Simulation::new(case.model, &case.initial, opts) {
            Ok(sim) => {
                let start = *sim.final_sample();
                track.apply(Event::Started { run: 1, start });
                let mut states = Vec::new();
                let summary = sim.run(&mut |s| states.push(*s));
                let mut turns = summary.turning_points.iter().peekable();
                for s in states {
                    while let Some(p) = turns.next_if(|p| p.sample.t <= s.t) {
                        track.apply(Event::Turn { run: 1, point: *p });
                    }
                    track.apply(Event::State { run: 1, sample: s });
                }
                for p in turns {
                    track.apply(Event::Turn { run: 1, point: *p });
                }
                let end = RunEnd {
                    reason: summary.end_reason,
                    t_end: summary.t_end,
                    lift_off: summary.lift_off,
                    slip: summary.slip,
                };
                track.apply(Event::Ended { run: 1, end });
            }
            Err(e) => {
                track.apply(Event::Failed { run: 1, message: e.to_string() });
            }
        }
        track
    }

    pub fn run(&self) -> u64 {
        self.run
    }
    pub fn case(&self) -> &Case {
        &self.case
    }
    pub fn start(&self) -> Option<&Sample> {
        self.start.as_ref()
    }
    pub fn end(&self) -> Option<&RunEnd> {
        self.end.as_ref()
    }
    pub fn failed(&self) -> Option<&str> {
        self.failed.as_deref()
    }
    /// Ended or failed: nothing more will arrive.
    pub fn is_finished(&self) -> bool {
        self.end.is_some() || self.failed.is_some()
    }
    pub fn samples(&self) -> &[Sample] {
        &self.samples
    }
    pub fn turning_points(&self) -> &[TurningPoint] {
        &self.turning
    }
    /// Every how many received states one is kept (1 until the track was thinned out).
    pub fn stride(&self) -> usize {
        self.stride
    }

    pub fn first_time(&self) -> Option<f64> {
        self.samples.first().map(|s| s.t)
    }
    pub fn last_time(&self) -> Option<f64> {
        self.samples.last().map(|s| s.t)
    }

    /// Applies one event of this track's run (others are ignored). Returns whether it applied.
    pub fn apply(&mut self, ev: Event) -> bool {
        if ev.run() != self.run {
            return false;
        }
        match ev {
            Event::Started { start, .. } => {
                if self.start.is_none() {
                    self.start = Some(start);
                }
            }
            Event::State { sample, .. } => self.push_state(sample),
            Event::Turn { point, .. } => {
                if self.turning.last().is_none_or(|p| p.sample.t < point.sample.t) {
                    self.turning.push(point);
                    if point.kind == TurnKind::ThetaMax {
                        self.reanalyse(point.sample.t);
                    }
                }
            }
            Event::Ended { end, .. } => {
                let t0 = self.segment_start();
                replace_from(&mut self.lift_off, t0, &end.lift_off);
                replace_from(&mut self.slip, t0, &end.slip);
                self.reanalyse(end.t_end);
                self.end = Some(end);
            }
            Event::Failed { message, .. } => self.failed = Some(message),
        }
        true
    }

    /// Start of the part of the track the current run computes (later than the first state
    /// when it continues an earlier run).
    fn segment_start(&self) -> f64 {
        self.continued_at.unwrap_or_else(|| self.first_time().unwrap_or(0.0))
    }

    fn push_state(&mut self, s: Sample) {
        if self.last_time().is_some_and(|t| s.t <= t) {
            return; // the first state of a continued run repeats the last kept one
        }
        let mu = self.case.opts.mu;
        self.lift_off.update(s.t, s.f_n <= 0.0);
        self.slip.update(s.t, s.f_n <= 0.0 || s.friction_ratio() > mu);
        self.received += 1;
        if !self.received.is_multiple_of(self.stride) && self.samples.len() > 1 {
            return;
        }
        if self.samples.len() >= MAX_SAMPLES {
            let mut i = 0;
            self.samples.retain(|_| {
                i += 1;
                i % 2 == 1
            });
            self.stride *= 2;
        }
        self.samples.push(s);
    }

    fn reanalyse(&mut self, t_last: f64) {
        if let Some(start) = &self.start {
            self.analysis = Some(analyze(start, &self.turning, t_last));
        }
    }

    /// The phase analysis of what has arrived so far (None before the first turning point).
    pub fn analysis(&self) -> Option<&MotionAnalysis> {
        self.analysis.as_ref()
    }

    /// The phase at time `t`: the last classified phase carries on until the next cycle is
    /// complete. None before the first cycle is complete.
    pub fn phase_at(&self, t: f64) -> Option<Phase> {
        let a = self.analysis.as_ref()?;
        let first = a.phases.first()?;
        if t < first.start {
            return None;
        }
        a.phase_at(t).or_else(|| a.phases.last().map(|p| p.phase))
    }

    /// The inflection time, once what has arrived shows the retrograde turn (an inflection
    /// followed by a quarter turn backwards; before that it may still be a wobble).
    pub fn inflection_time(&self) -> Option<f64> {
        self.analysis.as_ref().filter(|a| a.retrograde_turn).and_then(|a| a.inflection_time)
    }

    /// Lift-off intervals up to `t` (exact once the run has ended, else from the states).
    pub fn lift_off_until(&self, t: f64) -> Vec<Interval> {
        self.lift_off.until(t)
    }
    /// Slip intervals (friction would have to exceed `mu F_N`) up to `t`.
    pub fn slip_until(&self, t: f64) -> Vec<Interval> {
        self.slip.until(t)
    }

    /// The states with `t_s <= t`.
    pub fn samples_until(&self, t: f64) -> &[Sample] {
        let n = self.samples.partition_point(|s| s.t <= t);
        &self.samples[..n]
    }

    /// The last received state at or before `t`.
    pub fn sample_at_or_before(&self, t: f64) -> Option<&Sample> {
        self.samples_until(t).last()
    }

    /// The state at `t`, blended from the received states around it: the angles by cubic
    /// Hermite interpolation with their exact rates (the spin can turn by a radian between
    /// output states near the end), everything else linearly. Times outside the received
    /// span give the first or last state, marked `clamped`.
    pub fn state_at(&self, t: f64) -> Option<StateAt> {
        let (first, last) = (self.samples.first()?, self.samples.last()?);
        if t <= first.t {
            return Some(StateAt { sample: *first, clamped: t < first.t });
        }
        if t >= last.t {
            return Some(StateAt { sample: *last, clamped: t > last.t });
        }
        let i = self.samples.partition_point(|s| s.t <= t);
        let (a, b) = (&self.samples[i - 1], &self.samples[i]);
        Some(StateAt { sample: self.blend(a, b, t), clamped: false })
    }

    /// The paths of A and P up to `t`, ending at the state at `t`: the received states, with
    /// blended ones between two of them wherever the heading turns by more than
    /// [`PATH_MAX_TURN`]. With more than `max_states` states, only every k-th is used.
    pub fn path_until(&self, t: f64, max_states: usize) -> Vec<PathPoint> {
        let s = self.samples_until(t);
        let Some(last) = s.last() else { return Vec::new() };
        let stride = s.len().div_ceil(max_states.max(2)).max(1);
        let mut idx: Vec<usize> = (0..s.len()).step_by(stride).collect();
        if idx.last() != Some(&(s.len() - 1)) {
            idx.push(s.len() - 1);
        }
        let mut out = Vec::with_capacity(idx.len() * 2);
        for w in idx.windows(2) {
            let (a, b) = (&s[w[0]], &s[w[1]]);
            out.push(PathPoint::of(a));
            if w[1] == w[0] + 1 {
                let k = ((b.phi() - a.phi()).abs() / PATH_MAX_TURN).ceil().min(64.0) as usize;
                for m in 1..k {
                    let tm = a.t + (b.t - a.t) * m as f64 / k as f64;
                    out.push(PathPoint::of(&self.blend(a, b, tm)));
                }
            }
        }
        out.push(PathPoint::of(last));
        if let Some(now) = self.state_at(t).filter(|n| !n.clamped && n.sample.t > last.t) {
            out.push(PathPoint::of(&now.sample));
        }
        out
    }

    /// The state at `t` between two received states `a` and `b`: the angles by cubic Hermite
    /// interpolation with their exact rates, the centre of mass and the derived values
    /// linearly; A and P follow from the angles and the centre (so they stay on the body).
    fn blend(&self, a: &Sample, b: &Sample, t: f64) -> Sample {
        let mut s = blend(a, b, t);
        let body = &self.case.model.body;
        let half = 0.5 * body.h;
        let (st, ct) = s.theta().sin_cos();
        let (sp, cp) = s.phi().sin_cos();
        let (xc, yc) = (s.x_c(), s.y_c());
        s.x_a = xc - half * ct * sp;
        s.y_a = yc + half * ct * cp;
        let lever = body.r * st - half * ct;
        s.x_p = xc - lever * sp;
        s.y_p = yc + lever * cp;
        s.z_c = half * st + body.r * ct;
        s
    }

    /// Cuts the track at `t0` for a continuation by run `run` with `case`: states and turning
    /// points after `t0` go, the invalid intervals end there.
    pub fn continue_with(&mut self, run: u64, case: Case, t0: f64) {
        let n = self.samples.partition_point(|s| s.t <= t0);
        self.samples.truncate(n);
        self.turning.retain(|p| p.sample.t <= t0);
        let lift = self.lift_off.until(t0);
        let slip = self.slip.until(t0);
        self.lift_off = Intervals { closed: lift, open: None };
        self.slip = Intervals { closed: slip, open: None };
        // An interval still open at t0 is re-opened by the new run's first state if it holds.
        for ints in [&mut self.lift_off, &mut self.slip] {
            if ints.closed.last().is_some_and(|i| i.end >= t0) {
                ints.open = ints.closed.pop().map(|i| i.start);
            }
        }
        self.run = run;
        self.case = case;
        self.end = None;
        self.failed = None;
        self.continued_at = Some(t0);
        self.reanalyse(t0);
    }
}

fn lerp(a: f64, b: f64, u: f64) -> f64 {
    a + (b - a) * u
}

/// Rates of `(phi, theta, psi)` from the state: `theta' = w1`, `phi' = w3 / cos(theta)`,
/// `psi' = w2 - w3 tan(theta)` (PHYSICS.md).
fn angle_rates(s: &Sample) -> [f64; 3] {
    let (st, ct) = s.theta().sin_cos();
    let (w1, w2, w3) = (s.y[3], s.y[4], s.y[5]);
    [w3 / ct, w1, w2 - w3 * st / ct]
}

fn hermite(p0: f64, m0: f64, p1: f64, m1: f64, h: f64, u: f64) -> f64 {
    let (u2, u3) = (u * u, u * u * u);
    (2.0 * u3 - 3.0 * u2 + 1.0) * p0
        + (u3 - 2.0 * u2 + u) * h * m0
        + (-2.0 * u3 + 3.0 * u2) * p1
        + (u3 - u2) * h * m1
}

fn blend(a: &Sample, b: &Sample, t: f64) -> Sample {
    let h = b.t - a.t;
    let u = if h > 0.0 { (t - a.t) / h } else { 0.0 };
    let (ra, rb) = (angle_rates(a), angle_rates(b));
    let mut y = a.y;
    for k in 0..y.len() {
        y[k] = lerp(a.y[k], b.y[k], u);
    }
    for k in 0..3 {
        y[k] = hermite(a.y[k], ra[k], b.y[k], rb[k], h, u);
    }
    let l = |fa: f64, fb: f64| lerp(fa, fb, u);
    Sample {
        t,
        y,
        z_c: l(a.z_c, b.z_c),
        x_a: l(a.x_a, b.x_a),
        y_a: l(a.y_a, b.y_a),
        x_p: l(a.x_p, b.x_p),
        y_p: l(a.y_p, b.y_p),
        vx_a: l(a.vx_a, b.vx_a),
        vy_a: l(a.vy_a, b.vy_a),
        v_p: l(a.v_p, b.v_p),
        f_1: l(a.f_1, b.f_1),
        f_f: l(a.f_f, b.f_f),
        f_n: l(a.f_n, b.f_n),
        energy: l(a.energy, b.energy),
        speed_c: l(a.speed_c, b.speed_c),
        reynolds: l(a.reynolds, b.reynolds),
        // A blend inside a sliding interval is sliding; its slip speed interpolates.
        sliding: a.sliding || b.sliding,
        slip_speed: l(a.slip_speed, b.slip_speed),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::load_preset;

    fn paper_case() -> Case {
        load_preset("paper-ring")
            .and_then(|f| {
                f.build().map_err(|m| crate::config::ConfigError::Invalid {
                    path: "paper-ring".into(),
                    message: m,
                })
            })
            .expect("the paper-ring preset builds")
    }

    #[test]
    fn computed_track_has_every_state_and_the_paper_phases() {
        let case = paper_case();
        let dt = case.dt;
        let track = Track::compute(case);
        let s = track.samples();
        assert!(s.len() > 2000);
        for (k, w) in s.windows(2).enumerate() {
            assert!(w[1].t > w[0].t, "states in time order at {k}");
        }
        // One state per output time up to the end point.
        for (k, x) in s[..s.len() - 1].iter().enumerate() {
            assert!((x.t - k as f64 * dt).abs() < 1e-9, "state {k} at t = {}", x.t);
        }
        let a = track.analysis().expect("analysed");
        assert!(a.retrograde_turn);
        let phases: Vec<Phase> = a.phases.iter().map(|p| p.phase).collect();
        assert_eq!(phases, vec![Phase::Prograde, Phase::Walk, Phase::Retrograde]);
        assert_eq!(track.phase_at(1.0), Some(Phase::Prograde));
        let t_inf = track.inflection_time().expect("inflection");
        assert_eq!(track.phase_at(t_inf + 5.0), Some(Phase::Retrograde));
    }

    #[test]
    fn blending_matches_the_states_at_the_ends_and_lies_between() {
        let track = Track::compute(paper_case());
        let s = track.samples();
        let (a, b) = (s[100], s[101]);
        assert_eq!(track.state_at(a.t).map(|x| x.sample.y), Some(a.y));
        let mid = track.state_at(0.5 * (a.t + b.t)).expect("state").sample;
        for k in 0..8 {
            let (lo, hi) = (a.y[k].min(b.y[k]), a.y[k].max(b.y[k]));
            let slack = 0.05 * (hi - lo) + 1e-12;
            assert!(mid.y[k] >= lo - slack && mid.y[k] <= hi + slack, "component {k}");
        }
        let end = track.state_at(1e9).expect("state");
        assert!(end.clamped);
    }

    #[test]
    fn blended_points_stay_on_the_body() {
        let track = Track::compute(paper_case());
        let s = track.samples();
        let k = s.len() - 40; // near the end, where phi turns fast
        let (a, b) = (s[k], s[k + 1]);
        let mid = track.state_at(0.5 * (a.t + b.t)).expect("state").sample;
        let exact = Sample::new(&track.case().model, mid.t, &mid.y);
        assert!((mid.x_a - exact.x_a).abs() < 1e-12 && (mid.y_p - exact.y_p).abs() < 1e-12);
        let path = track.path_until(b.t, 100_000);
        let n_states = track.samples_until(b.t).len();
        assert!(path.len() > n_states, "fast turns get extra points");
        assert!(path.windows(2).all(|w| w[1].t > w[0].t));
    }

    #[test]
    fn stale_events_are_ignored_and_thinning_keeps_the_track_bounded() {
        let case = paper_case();
        let mut track = Track::new(2, case.clone());
        let s = Sample::new(&case.model, 0.0, &case.initial.to_state());
        assert!(!track.apply(Event::State { run: 1, sample: s }));
        assert!(track.samples().is_empty());
        for k in 0..(MAX_SAMPLES + 10) {
            let mut x = s;
            x.t = k as f64;
            track.apply(Event::State { run: 2, sample: x });
        }
        assert!(track.samples().len() <= MAX_SAMPLES);
        assert_eq!(track.stride(), 2);
        assert!(track.last_time().is_some_and(|t| t >= (MAX_SAMPLES - 2) as f64));
    }
}
