//! Multiple shooting: the recording cut into segments, each predicted by the model from its
//! own start state; the misfit is the pixel residual of every tracked mark.
//!
//! A segment's prediction: the model run from the segment's start state, sampled at the
//! frame times; once the run ends (flat), the frames show its final pose, still, as a
//! recording does and as `synth` writes (frames at or after `floor(t_end / dt)`).

use super::last_runs::LastRuns;
use super::lm::{AtPoint, BlockProblem};
use super::params::ModelSpec;
use crate::physics::integrator::dp5_along;
use crate::physics::model::{STATE_LEN, ix};
use crate::physics::sample::top_centre;
use crate::physics::{Model, RunOptions, Sample, Simulation, SlipStart, StateVec};
use crate::recording::marks::MarkGeometry;
use crate::recording::{Camera, FrameMarks, MARKS};
use std::borrow::Cow;
use std::ops::Range;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// The predicted pixel positions of the marks, frame by frame.
pub type PredictedMarks = Vec<[[f64; 2]; MARKS]>;

/// Everything a prediction needs besides the parameters.
#[derive(Clone, Debug)]
pub struct Shooting<'a> {
    /// Observed marks (pixels), every frame of the recording.
    pub observed: &'a [FrameMarks],
    pub segments: Vec<Range<usize>>,
    /// Model time per frame; frame `i` is at `t = i dt`.
    pub dt: f64,
    pub spec: ModelSpec,
    /// Integration settings (tolerances, the flat limit).
    pub run: RunOptions,
    /// The marks' circle in model units.
    pub geometry: MarkGeometry,
    /// The model's unit of length in mm.
    pub length_mm: f64,
    /// Integration steps this fit may spend in all (None: no limit); shared by its clones.
    pub budget: Option<Arc<WorkBudget>>,
    /// Each segment's last run, for the Jacobian at that point ([`LastRuns`]); a clone's is
    /// empty.
    pub last_runs: LastRuns<Prediction>,
    /// The caller's flag that stops every fit made on this problem (and its clones) between
    /// evaluations: it travels with the problem, as the budget does, rather than beside it
    /// through every function of a fit.
    pub cancel: &'a AtomicBool,
}

/// A flag nobody sets: for problems whose fits are never stopped (tests, predictions).
pub static NEVER_CANCELLED: AtomicBool = AtomicBool::new(false);

/// A cap on the integration steps of one fit, shared by the threads that work for it. Once it
/// is spent every prediction fails as if outside the model's domain, and the least squares stop
/// where they are: a deterministic bound on a fit that crawls (sliding runs, trial steps into
/// stiff corners), where a clock would make the result depend on the machine. Whether it is
/// spent is decided only at [`WorkBudget::settle`], between batches of parallel predictions:
/// decided at each prediction, which segments of the batch that crossed the limit failed
/// depended on the threads' order, and the same recording could be diagnosed two ways.
#[derive(Debug)]
pub struct WorkBudget {
    used: AtomicU64,
    limit: u64,
    spent: AtomicBool,
}

impl WorkBudget {
    pub fn new(limit: u64) -> WorkBudget {
        WorkBudget { used: AtomicU64::new(0), limit, spent: AtomicBool::new(false) }
    }

    /// Spent as of the last [`WorkBudget::settle`].
    pub fn spent(&self) -> bool {
        self.spent.load(Ordering::Relaxed)
    }

    /// Decides, for the predictions that follow, whether the budget is spent.
    pub fn settle(&self) {
        self.spent.store(self.used.load(Ordering::Relaxed) >= self.limit, Ordering::Relaxed);
    }

    pub fn used(&self) -> u64 {
        self.used.load(Ordering::Relaxed)
    }

    fn charge(&self, steps: u64) {
        self.used.fetch_add(steps, Ordering::Relaxed);
    }
}

/// Integration steps per frame beyond which a prediction is abandoned (see [`predict_samples`]).
pub const STEPS_PER_FRAME: u64 = 100;

/// The model's samples at the frames `range` from state `y0` at the first of them: one per
/// frame, the final pose repeated after the run's end. None when the run cannot start. The
/// samples before the end carry positions only (`Sample::position`: the state, the top
/// centre, whether the contact slides).
pub fn predict_samples(
    model: &Model,
    run: &RunOptions,
    dt: f64,
    y0: &StateVec,
    range: Range<usize>,
) -> Option<Vec<Sample>> {
    predict_samples_counted(model, run, dt, y0, range).0
}

/// How a prediction's run picks its steps (`physics::run`'s `steps.rs`).
#[derive(Clone, Copy, Debug)]
pub enum StepChoice<'e> {
    Adaptive,
    /// Adaptive, keeping where each step ends ([`Prediction::step_ends`]).
    Keep,
    /// To the ends a run of nearby parameters kept.
    Follow(&'e Arc<[f64]>),
}

/// A prediction with the work it took.
#[derive(Clone, Debug)]
pub struct Prediction {
    /// None when the run cannot start or crawls past its budget.
    pub samples: Option<Vec<Sample>>,
    /// Integration steps taken.
    pub steps: u64,
    /// Where each step ended, with [`StepChoice::Keep`].
    pub step_ends: Vec<f64>,
    /// Whether the run ended on its own (at rest, flat, on the other rim) before the
    /// segment's end: its last frames then show its end state, still.
    pub ended_early: bool,
    /// Whether the contact slid anywhere in the run (slip effect on).
    pub slid: bool,
}

/// As [`predict_samples`], with the integration steps it took.
pub fn predict_samples_counted(
    model: &Model,
    run: &RunOptions,
    dt: f64,
    y0: &StateVec,
    range: Range<usize>,
) -> (Option<Vec<Sample>>, u64) {
    let p = predict_with_steps(model, run, dt, y0, range, StepChoice::Adaptive);
    (p.samples, p.steps)
}

/// As [`predict_samples`], its steps chosen as `choice` says.
pub fn predict_with_steps(
    model: &Model,
    run: &RunOptions,
    dt: f64,
    y0: &StateVec,
    range: Range<usize>,
    choice: StepChoice,
) -> Prediction {
    let failed = |steps| Prediction {
        samples: None,
        steps,
        step_ends: Vec::new(),
        ended_early: false,
        slid: false,
    };
    let t0 = range.start as f64 * dt;
    let n = range.len();
    let opts = RunOptions {
        t_end: t0 + n as f64 * dt,
        sample_dt: Some(dt),
        track_validity: false,
        ..run.clone()
    };
    let t_end = opts.t_end;
    let Ok(mut sim) = Simulation::from_state(model.clone(), t0, *y0, opts) else {
        return failed(0);
    };
    sim.positions_only();
    match choice {
        StepChoice::Adaptive => {}
        StepChoice::Keep => sim.keep_steps(),
        StepChoice::Follow(ends) => sim.follow_steps(ends.clone()),
    }
    let mut grid = Vec::with_capacity(n);
    let mut sink = |s: &Sample| {
        if grid.len() < n {
            grid.push(*s);
        }
    };
    // A least-squares trial step can ask for parameters where the run crawls (spin so fast or
    // drag so strong that the steps shrink): past the budget it counts as outside the model's
    // domain. Rolling runs of the recordings take about 2 steps a frame at 300 fps, sliding ones
    // about 15, up to 40 over the slow, slippery end of a run.
    let budget = STEPS_PER_FRAME * n as u64 + 5_000;
    let mut t = t0;
    while sim.end_reason().is_none() && t < t_end {
        t = (t + 16.0 * dt).min(t_end);
        sim.advance_limited(t, budget + 1, &mut sink);
        if sim.stats().steps > budget {
            return failed(sim.stats().steps);
        }
    }
    let summary = sim.finish();
    // After a natural end, frames at or after floor(t_end / dt) show the end state; after a
    // failure, every frame past the last good sample does.
    let moving = if summary.end_reason.is_natural() {
        ((summary.t_end / dt).floor() as usize).saturating_sub(range.start)
    } else {
        n
    };
    grid.truncate(moving.min(grid.len()));
    grid.resize(n, summary.final_sample);
    Prediction {
        samples: Some(grid),
        steps: summary.stats.steps,
        step_ends: summary.step_ends,
        ended_early: summary.end_reason.is_natural(),
        slid: !summary.sliding.is_empty(),
    }
}

/// The model segment `s` runs: the recording's start (held rolling, a slide in progress)
/// belongs to the first segment only ([`Shooting::samples`]).
pub(super) fn segment_model(model: &Model, s: usize) -> Cow<'_, Model> {
    let e = &model.effects;
    if s > 0 && (e.slip_start != SlipStart::Cone || e.slip_start_velocity != [0.0, 0.0]) {
        let mut m = model.clone();
        m.effects.slip_start = SlipStart::Cone;
        m.effects.slip_start_velocity = [0.0, 0.0];
        Cow::Owned(m)
    } else {
        Cow::Borrowed(model)
    }
}

impl<'a> Shooting<'a> {
    /// The same problem, its fits stopped by `cancel` instead (a job's own flag, which a
    /// queue of fits sets once another job's answer makes this one's moot).
    pub fn stopped_by<'b>(&self, cancel: &'b AtomicBool) -> Shooting<'b>
    where
        'a: 'b,
    {
        Shooting { cancel, ..self.clone() }
    }

    /// The marks' circle for `model`: the recording's, or the model body's where the body's
    /// dimensions are free.
    pub fn geometry_of(&self, model: &Model) -> MarkGeometry {
        if self.spec.body_free() {
            MarkGeometry::of_body(&model.body, self.geometry.order)
        } else {
            self.geometry
        }
    }

    /// The marks' pixel positions for a sample: at their heights above the table where the
    /// camera sees heights (a pinhole or a tilted camera), else on the table (as before, to the
    /// bit).
    #[inline]
    pub fn project(
        &self,
        geometry: &MarkGeometry,
        camera: &Camera,
        s: &Sample,
    ) -> [[f64; 2]; MARKS] {
        self.project_at(geometry, camera, [s.x_a, s.y_a], &s.y)
    }

    /// [`Self::project`] of state `y`, its top centre at `a`.
    #[inline]
    pub(super) fn project_at(
        &self,
        geometry: &MarkGeometry,
        camera: &Camera,
        a: [f64; 2],
        y: &StateVec,
    ) -> [[f64; 2]; MARKS] {
        let k = self.length_mm;
        let (phi, theta, psi) = (y[ix::PHI], y[ix::THETA], y[ix::PSI]);
        if camera.sees_height() {
            let m = geometry.marks3(a, phi, theta, psi);
            return camera.to_px3_each(m.map(|p| [p[0] * k, p[1] * k, p[2] * k]));
        }
        let m = geometry.marks(a, phi, theta, psi);
        camera.to_px3_each(m.map(|p| [p[0] * k, p[1] * k, 0.0]))
    }

    /// Decides whether the budget is spent, before a batch of parallel predictions
    /// ([`WorkBudget::settle`]).
    pub fn settle_budget(&self) {
        if let Some(b) = &self.budget {
            b.settle();
        }
    }

    /// The model's samples over segment `s` from `y0`, charged to the budget (None once it is
    /// spent). A start held rolling (`SlipStart::HeldRolling`) or sliding
    /// (`Effects::slip_start_velocity`) is the recording's start: only the first segment has
    /// it; the others start as the cone says (a free start state that could hold or slide
    /// would make every slide optional).
    pub fn samples(&self, model: &Model, s: usize, y0: &StateVec) -> Option<Vec<Sample>> {
        self.samples_with_steps(model, s, y0, StepChoice::Adaptive).samples
    }

    /// As [`Self::samples`], the run's steps chosen as `choice` says.
    pub fn samples_with_steps(
        &self,
        model: &Model,
        s: usize,
        y0: &StateVec,
        choice: StepChoice,
    ) -> Prediction {
        if self.budget.as_ref().is_some_and(|b| b.spent()) {
            return Prediction {
                samples: None,
                steps: 0,
                step_ends: Vec::new(),
                ended_early: false,
                slid: false,
            };
        }
        let model = segment_model(model, s);
        let p =
            predict_with_steps(&model, &self.run, self.dt, y0, self.segments[s].clone(), choice);
        if let Some(b) = &self.budget {
            b.charge(p.steps);
        }
        p
    }

    /// Predicted marks of segment `s` from its start state.
    pub fn predict(
        &self,
        model: &Model,
        camera: &Camera,
        s: usize,
        y0: &StateVec,
    ) -> Option<PredictedMarks> {
        let samples = self.samples(model, s, y0)?;
        Some(self.marks_of(model, camera, &samples))
    }

    /// The marks of `samples` through `camera`.
    fn marks_of(&self, model: &Model, camera: &Camera, samples: &[Sample]) -> PredictedMarks {
        let geometry = self.geometry_of(model);
        samples.iter().map(|x| self.project(&geometry, camera, x)).collect()
    }

    /// Model minus observed for every tracked mark of segment `s` (x, then y).
    pub fn residuals_of(&self, s: usize, predicted: &PredictedMarks) -> Vec<f64> {
        let mut out = Vec::new();
        for (obs, pred) in self.observed[self.segments[s].clone()].iter().zip(predicted) {
            for (o, p) in obs.iter().zip(pred) {
                if let Some(o) = o {
                    out.push(p[0] - o[0]);
                    out.push(p[1] - o[1]);
                }
            }
        }
        out
    }

    /// Residuals of segment `s`, or None where the parameters are invalid or the state
    /// is not finite.
    pub fn segment_residuals(&self, s: usize, global: &[f64], state: &[f64]) -> Option<Vec<f64>> {
        self.segment_residuals_with_steps(s, global, state, StepChoice::Adaptive)
    }

    /// As [`Self::segment_residuals`], the run's steps chosen as `choice` says.
    pub fn segment_residuals_with_steps(
        &self,
        s: usize,
        global: &[f64],
        state: &[f64],
        choice: StepChoice,
    ) -> Option<Vec<f64>> {
        let (model, camera) = self.spec.build(global)?;
        let y0: StateVec = state.try_into().ok()?;
        if y0.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let samples = self.samples_with_steps(&model, s, &y0, choice).samples?;
        Some(self.residuals_of(s, &self.marks_of(&model, &camera, &samples)))
    }

    /// Number of tracked mark coordinates in segment `s`.
    pub fn residual_count(&self, s: usize) -> usize {
        2 * self.observed[self.segments[s].clone()]
            .iter()
            .map(|f| f.iter().flatten().count())
            .sum::<usize>()
    }
}

impl BlockProblem for Shooting<'_> {
    fn global_count(&self) -> usize {
        self.spec.free.len()
    }
    fn block_count(&self) -> usize {
        self.segments.len()
    }
    fn block_size(&self) -> usize {
        STATE_LEN
    }
    fn residuals(&self, s: usize, global: &[f64], local: &[f64]) -> Option<Vec<f64>> {
        let (model, camera) = self.spec.build(global)?;
        let y0: StateVec = local.try_into().ok()?;
        if y0.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let run = self.samples_with_steps(&model, s, &y0, StepChoice::Keep);
        let r = self.residuals_of(s, &self.marks_of(&model, &camera, run.samples.as_ref()?));
        self.last_runs.keep(s, &self.segments[s], global, local, run);
        Some(r)
    }
    fn settle(&self) {
        self.settle_budget();
    }
    fn charge_deferred(&self, work: u64) {
        if let Some(b) = &self.budget {
            b.charge(work);
        }
    }
    fn global_step(&self, i: usize, value: f64) -> f64 {
        self.spec.step(i, value)
    }
    fn project_global(&self, global: &mut [f64]) {
        self.spec.project(global);
    }
    fn local_step(&self, _: usize, value: f64) -> f64 {
        1e-6 * value.abs().max(1.0)
    }
    fn symmetric_locals(&self) -> &[usize] {
        &SYMMETRIC
    }
    fn at_point(&self, s: usize, global: &[f64], local: &[f64], cheap: bool) -> Option<AtPoint> {
        self.at_point_of(s, global, local, cheap)
    }
    fn column_residuals(
        &self,
        s: usize,
        global: &[f64],
        local: &[f64],
        at: &AtPoint,
    ) -> Option<Vec<f64>> {
        match (&at.step_ends, &at.column_base) {
            (Some(ends), Some(_)) => self.segment_residuals_along(s, global, local, ends),
            (Some(ends), None) => {
                self.segment_residuals_with_steps(s, global, local, StepChoice::Follow(ends))
            }
            (None, _) => self.segment_residuals(s, global, local),
        }
    }
}

/// The start-state components whose effect on a prediction follows without integrating: the
/// table has no preferred place or heading (moving `x_C, y_C` translates the whole path,
/// turning `phi` turns it about the start's centre of mass) and the body is symmetric about
/// its axis (`psi` only turns the marks). Every force of the model and its effects respects
/// this, sliding included.
const SYMMETRIC: [usize; 4] = [ix::PHI, ix::PSI, ix::X, ix::Y];

impl Shooting<'_> {
    /// One run at the point, its step ends kept for the other columns, and the
    /// forward-difference columns for [`SYMMETRIC`] from it: the samples moved, turned
    /// or spun, and projected again.
    fn at_point_of(&self, s: usize, global: &[f64], local: &[f64], cheap: bool) -> Option<AtPoint> {
        let (model, camera) = self.spec.build(global)?;
        let y0: StateVec = local.try_into().ok()?;
        if y0.iter().any(|v| !v.is_finite()) {
            return None;
        }
        // The run the evaluation at this point made, charged again as if made again (the
        // budget then stops a fit where it did before).
        let kept = self.last_runs.take(s, &self.segments[s], global, local);
        let run = match kept {
            Some(run) if !self.budget.as_ref().is_some_and(|b| b.spent()) => {
                if let Some(b) = &self.budget {
                    b.charge(run.steps);
                }
                run
            }
            _ => self.samples_with_steps(&model, s, &y0, StepChoice::Keep),
        };
        let samples = run.samples?;
        let geometry = self.geometry_of(&model);
        let project = |f: &dyn Fn(&Sample) -> Sample| -> PredictedMarks {
            samples.iter().map(|x| self.project(&geometry, &camera, &f(x))).collect()
        };
        let base = self.residuals_of(s, &project(&|x| *x));
        let (cx, cy) = (y0[ix::X], y0[ix::Y]);
        let cols = SYMMETRIC.map(|i| {
            let h = self.local_step(i, y0[i]);
            let moved = project(&|x: &Sample| {
                let mut m = *x;
                match i {
                    ix::X => m.x_a += h,
                    ix::Y => m.y_a += h,
                    ix::PSI => m.y[ix::PSI] += h,
                    _ => {
                        let (sn, cs) = h.sin_cos();
                        let (dx, dy) = (x.x_a - cx, x.y_a - cy);
                        m.x_a = cx + cs * dx - sn * dy;
                        m.y_a = cy + sn * dx + cs * dy;
                        m.y[ix::PHI] += h;
                    }
                }
                m
            });
            self.residuals_of(s, &moved).iter().zip(&base).map(|(a, b)| (a - b) / h).collect()
        });
        let step_ends: Arc<[f64]> = Arc::from(run.step_ends);
        // A rolling run that reached the segment's end: the integrated columns by a cheaper
        // formula along its steps (`dp5_along`), against that formula's own run at the point.
        // A run that slid switches contact and an early end freezes frames, which those steps
        // do not carry: their columns follow with DOP853 as before. A run of the slip effect
        // that rolled throughout is the rolling model's run: along its steps too.
        let along = (cheap && !run.slid && !run.ended_early)
            .then(|| self.run_along(&model, s, &y0, &step_ends))
            .flatten();
        let by_along = along.is_some();
        let (seen, work) = along.unwrap_or_else(|| {
            (samples.iter().map(|x| ([x.x_a, x.y_a], x.y)).collect(), run.steps)
        });
        let column_base =
            by_along.then(|| self.residuals_of(s, &self.seen_through(&geometry, &camera, &seen)));
        let unrun = self.unrun_columns(s, global, &model, &camera, &seen)?;
        Some(AtPoint {
            symmetry: cols.to_vec(),
            step_ends: Some(step_ends),
            column_base,
            deferred_work: work * unrun.len() as u64,
            unrun,
        })
    }

    /// The marks of the points `seen` (top centre, state) through `camera`.
    pub(super) fn seen_through(
        &self,
        geometry: &MarkGeometry,
        camera: &Camera,
        seen: &[([f64; 2], StateVec)],
    ) -> PredictedMarks {
        seen.iter().map(|(a, y)| self.project_at(geometry, camera, *a, y)).collect()
    }

    /// A run of `model` over segment `s` from `y0` by a fifth-order formula along `ends`
    /// ([`dp5_along`]): each frame's top centre and state, and its steps, charged to the
    /// budget a step per end as the run it follows; None where it fails or the budget is
    /// spent.
    fn run_along(
        &self,
        model: &Model,
        s: usize,
        y0: &StateVec,
        ends: &[f64],
    ) -> Option<(Vec<([f64; 2], StateVec)>, u64)> {
        if self.budget.as_ref().is_some_and(|b| b.spent()) {
            return None;
        }
        let range = self.segments[s].clone();
        let t0 = range.start as f64 * self.dt;
        let (states, steps) = dp5_along(model, t0, *y0, ends, self.dt, range.len())?;
        if let Some(b) = &self.budget {
            b.charge(steps);
        }
        let seen = states.iter().map(|y| {
            let (x_a, y_a) = top_centre(&model.body, y);
            ([x_a, y_a], *y)
        });
        Some((seen.collect(), steps))
    }

    /// Residuals of segment `s` from a run by a fifth-order formula along `ends`
    /// ([`Self::run_along`]).
    fn segment_residuals_along(
        &self,
        s: usize,
        global: &[f64],
        state: &[f64],
        ends: &[f64],
    ) -> Option<Vec<f64>> {
        let (model, camera) = self.spec.build(global)?;
        let y0: StateVec = state.try_into().ok()?;
        let (seen, _) = self.run_along(&model, s, &y0, ends)?;
        let geometry = self.geometry_of(&model);
        Some(self.residuals_of(s, &self.seen_through(&geometry, &camera, &seen)))
    }
}

/// One segment's start state with the globals held fixed: the per-segment fit.
pub struct OneSegment<'a, 'b> {
    pub shooting: &'b Shooting<'a>,
    pub segment: usize,
    pub global: Vec<f64>,
}

impl BlockProblem for OneSegment<'_, '_> {
    fn global_count(&self) -> usize {
        STATE_LEN
    }
    fn block_count(&self) -> usize {
        1
    }
    fn block_size(&self) -> usize {
        0
    }
    fn residuals(&self, _: usize, state: &[f64], _: &[f64]) -> Option<Vec<f64>> {
        self.shooting.segment_residuals(self.segment, &self.global, state)
    }
    fn settle(&self) {
        self.shooting.settle_budget();
    }
    fn global_step(&self, _: usize, value: f64) -> f64 {
        1e-6 * value.abs().max(1.0)
    }
    fn local_step(&self, _: usize, _: f64) -> f64 {
        0.0
    }
}
