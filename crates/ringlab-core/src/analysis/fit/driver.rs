//! The stages of the fit (see the module doc of `analysis::fit`).

use super::coarse::{self, Features};
use super::lm::{self, LmError, LmOptions};
use super::params::{Free, ModelSpec};
use super::shooting::{OneSegment, Shooting, predict_samples};
use crate::analysis::sweep::Axis;
use crate::physics::effects::EffectKind;
use crate::physics::integrator::Tolerances;
use crate::physics::model::ix;
use crate::physics::run::RunError;
use crate::physics::{Initial, Model, ParamError, RunOptions, RunSummary, Sample, Simulation, StateVec, TurnKind, Units};
use crate::recording::marks::MarkGeometry;
use crate::recording::recover::{RecoverError, RecoveredMotion, recover_with};
use crate::recording::glitches::Glitch;
use crate::recording::tracks::{as_tracked, check_tracks};
use crate::recording::{Camera, FrameMarks, Recording};
use nalgebra::Vector3;
use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;
use thiserror::Error;

/// The flat limit of the fit's runs, closer to flat than a plain run's (`pi/2 - 0.02`): a
/// model that is still off may otherwise end on a `theta` maximum before the recording's ring
/// comes to rest, and whether a maximum crosses the limit is all or nothing.
pub const FIT_THETA_FLAT: f64 = std::f64::consts::FRAC_PI_2 - 0.005;

#[derive(Clone, Debug, PartialEq)]
pub struct FitOptions {
    /// Frames per shooting segment at first.
    pub segment_frames: usize,
    /// How many times the segments may be doubled in length after the first fit (each time
    /// only while the misfit stays as the noise allows).
    pub merges: usize,
    /// Drag to start from (and to use for the start state).
    pub c_start: [f64; 3],
    /// Run the coarse grid (else start the least squares from `c_start`).
    pub coarse: bool,
    pub coarse_axes: [Axis; 3],
    /// An effect whose strength is fitted too, with its starting strength.
    pub effect: Option<(EffectKind, f64)>,
    /// The camera's radial distortion, when known (`camera_distortion` fits it instead).
    pub lens_k1: f64,
    /// A pinhole camera's distance (mm) and tilt (degrees), when known, over the header's.
    pub camera_distance_mm: Option<f64>,
    pub camera_tilt_deg: Option<f64>,
    pub tolerances: Tolerances,
    pub max_iterations: usize,
    /// Leave the tracker's glitches out (`recording::glitches`); off where the caller has
    /// already done so.
    pub leave_out_glitches: bool,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            segment_frames: 60,
            merges: 2,
            c_start: crate::physics::paper::C_RING,
            coarse: true,
            coarse_axes: [Axis { lo: 0.005, hi: 0.5, n: 6, log: true }; 3],
            effect: None,
            lens_k1: 0.0,
            camera_distance_mm: None,
            camera_tilt_deg: None,
            tolerances: Tolerances { rtol: 1e-10, atol: 1e-12 },
            max_iterations: 30,
            leave_out_glitches: true,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FitStage {
    Recover,
    StartState,
    Sweep,
    Segments,
    Refine,
}

impl FitStage {
    pub fn describe(self) -> &'static str {
        match self {
            FitStage::Recover => "recovering the motion",
            FitStage::StartState => "start state",
            FitStage::Sweep => "coarse drag grid",
            FitStage::Segments => "segment states",
            FitStage::Refine => "least squares",
        }
    }
}

/// Where a fit is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitProgress {
    pub stage: FitStage,
    pub done: usize,
    pub total: usize,
    /// The misfit so far (px), where known.
    pub rms_px: Option<f64>,
}

#[derive(Debug, Error, Clone, PartialEq)]
pub enum FitError {
    #[error(transparent)]
    Recover(#[from] RecoverError),
    #[error("invalid fit setting: {0}")]
    Options(String),
    #[error("the model cannot be built: {0}")]
    Model(ParamError),
    #[error("too few frames after the start (frame {start}) to fit: {frames}, one segment at least")]
    TooFewFrames { start: usize, frames: usize },
    #[error("the start state cannot be reconstructed at frame {0} (marks missing around it?)")]
    NoStartState(usize),
    #[error("the model cannot be evaluated at the starting parameters")]
    BadStart,
    #[error("the fit was cancelled")]
    Cancelled,
}

impl From<LmError> for FitError {
    fn from(e: LmError) -> Self {
        match e {
            LmError::Cancelled => FitError::Cancelled,
            LmError::BadStart => FitError::BadStart,
        }
    }
}

/// What a fit found.
#[derive(Clone, Debug)]
pub struct FitResult {
    pub c: [f64; 3],
    /// One standard deviation (infinite where the data do not constrain it).
    pub c_sigma: [f64; 3],
    /// A fitted effect: kind, strength and its sigma.
    pub effect: Option<(EffectKind, f64, f64)>,
    /// The start state at the first inner turning point (model units).
    pub start: Initial,
    /// Its time (model units, frame `i` at `i dt`) and fractional frame index.
    pub start_t: f64,
    pub start_frame: f64,
    /// RMS of model minus recording over every tracked mark coordinate fitted (px).
    pub rms_px: f64,
    pub residual_count: usize,
    pub parameter_count: usize,
    /// Frames in the recording.
    pub frames: usize,
    /// Frames fitted: from the start to the still end (the still frames show only the pose
    /// in which the ring landed, which the model's flat limit gives to a frame at best).
    pub frames_fitted: usize,
    /// The pixel noise per coordinate from the marks' tracks alone (`recording::noise`).
    pub noise_px: Option<f64>,
    /// The tracker's glitches left out of the fit.
    pub glitches: Vec<Glitch>,
    pub segments: Vec<Range<usize>>,
    pub segment_states: Vec<StateVec>,
    pub coarse_c: Option<[f64; 3]>,
    pub iterations: usize,
    /// The fitted model and camera (model units).
    pub model: Model,
    pub camera: Camera,
    pub units: Units,
    /// Model time per frame.
    pub dt: f64,
    /// The marks' circle in model units.
    pub geometry: MarkGeometry,
    /// Reynolds number at the start (the reference of `reynolds_drag`).
    pub re_start: f64,
    /// The integration settings of the fit's runs.
    pub run: RunOptions,
    pub compute_seconds: f64,
}

impl FitResult {
    /// The fit's multiple-shooting problem at its final segments, with the drag free (the
    /// fitted model as the base): for refits that start where this fit ended (the diagnosis).
    pub fn shooting<'a>(&self, observed: &'a [FrameMarks]) -> Shooting<'a> {
        let free = (0..3).map(Free::Drag).collect();
        Shooting {
            observed,
            segments: self.segments.clone(),
            dt: self.dt,
            spec: ModelSpec { base: self.model.clone(), camera: self.camera, free, re_start: self.re_start, strength_ranges: Vec::new() },
            run: self.run.clone(),
            geometry: self.geometry,
            length_mm: self.units.length_mm,
            budget: None,
        }
    }

    /// The fitted model run from the fitted start to its end, sampled at the recording's
    /// frames (`t = start_t + k dt`): the model's path to show beside the recording's (same
    /// table coordinates, model units; the recording's are in mm).
    pub fn model_run(&self) -> Result<(RunSummary, Vec<Sample>), RunError> {
        let opts = RunOptions { sample_dt: Some(self.dt), ..RunOptions::default() };
        let sim = Simulation::from_state(self.model.clone(), self.start_t, self.start.to_state(), opts)?;
        let mut samples = Vec::new();
        let summary = sim.run(&mut |s| samples.push(*s));
        Ok((summary, samples))
    }
}

/// Fits the model to a recording. `progress` is called from worker threads; `cancel` stops
/// the fit at the next evaluation with [`FitError::Cancelled`].
pub fn fit(
    rec: &Recording,
    opts: &FitOptions,
    progress: &(dyn Fn(&FitProgress) + Sync),
    cancel: &AtomicBool,
) -> Result<FitResult, FitError> {
    let clock = Instant::now();
    let report = |stage, done, total, rms_px| progress(&FitProgress { stage, done, total, rms_px });
    let check = || if cancel.load(Ordering::Relaxed) { Err(FitError::Cancelled) } else { Ok(()) };
    if opts.segment_frames < 10 {
        return Err(FitError::Options(format!("segments of {} frames are too short (10 at least)", opts.segment_frames)));
    }
    report(FitStage::Recover, 0, 1, None);
    let tracks = if opts.leave_out_glitches { check_tracks(rec) } else { as_tracked(rec) };
    let rec = &tracks.recording;
    let mut camera = Camera { k1: opts.lens_k1, ..Camera::for_recording(&rec.header, &rec.frames) };
    if let Some(d) = opts.camera_distance_mm {
        if !(d.is_finite() && d > 0.0) {
            return Err(FitError::Options(format!("camera distance {d} mm must be a positive number")));
        }
        camera.distance_mm = Some(d);
    }
    if let Some(t) = opts.camera_tilt_deg {
        if !(t.abs() < 80.0) {
            return Err(FitError::Options(format!("camera tilt {t} degrees must lie between -80 and 80")));
        }
        camera.tilt_rad = t.to_radians();
    }
    let motion = recover_with(rec, camera)?;
    check()?;
    // The first frame when theta rises from it, else the first minimum; the model places the
    // turning point exactly (`start_at_turning_point`).
    let f0 = match motion.turning_points.first() {
        Some(p) if p.kind == TurnKind::ThetaMin => p.at.floor().max(0.0) as usize,
        _ => 0,
    };
    let n = rec.frames.len();
    let moving_end = motion.rest_from.unwrap_or(n).max(f0);
    if moving_end - f0 < opts.segment_frames {
        return Err(FitError::TooFewFrames { start: f0, frames: moving_end - f0 });
    }

    let units = motion.units;
    let to_model = motion.to_model();
    let body = motion.body_model().map_err(FitError::Model)?;
    let base = Model::new(body, units.g(), opts.c_start, units.nu_air()).map_err(FitError::Model)?;
    let dt = 1.0 / motion.fps * to_model.time;
    let mut starts = reconstruct(&motion, f0);
    // The start is a turning point: the same states with theta' = 0, and the paper's reading.
    let level: Vec<StateVec> = starts.iter().map(level_start).collect();
    starts.extend(level);
    starts.extend([false, true].iter().filter_map(|&f| motion.turning_point_state(f0, f)));
    let y0 = *starts.first().ok_or(FitError::NoStartState(f0))?;
    let mut free: Vec<Free> = (0..3).map(Free::Drag).collect();
    if let Some((kind, _)) = opts.effect
        && kind != EffectKind::None
    {
        free.push(Free::Effect(kind));
    }
    let re_start = Sample::new(&base, 0.0, &y0).reynolds;
    let spec = ModelSpec { base, camera, free, re_start, strength_ranges: Vec::new() };
    let mut shooting = Shooting {
        observed: &rec.frames,
        segments: split(f0, moving_end, opts.segment_frames),
        dt,
        spec,
        run: RunOptions { tol: opts.tolerances, theta_flat: FIT_THETA_FLAT, ..RunOptions::default() },
        geometry: motion.geometry_mm.scaled(to_model.length),
        length_mm: 1.0 / to_model.length,
        budget: None,
    };
    let mut global = shooting.spec.to_internal(&shooting.spec.initial_values());
    if let (Some((_, strength)), Some(g)) = (opts.effect, global.get_mut(3)) {
        *g = strength;
    }

    // The start state, refined with the starting drag over a growing window: a quarter of
    // the first segment, half, all of it (the rates from the poses are rough, and over a short
    // window a rough start still lies in the right valley).
    report(FitStage::StartState, 0, 1, None);
    let first = shooting.segments[0].clone();
    let mut y0 = starts[0];
    let mut candidates = starts;
    for part in [4, 2, 1] {
        let end = first.start + (first.len() / part).max(12).min(first.len());
        let window = Shooting { segments: std::iter::once(first.start..end).collect(), ..shooting.clone() };
        y0 = fit_segment(&window, 0, &global, &candidates, cancel)?.0;
        candidates = vec![y0];
    }
    check()?;

    // Coarse grid on phase-free features.
    let mut coarse_c = None;
    if opts.coarse {
        let features = features(&motion, f0, moving_end, n, dt);
        let span = coarse::Span { t0: f0 as f64 * dt, y0, t_stop: (n as f64 + 1.0) * dt };
        let total = opts.coarse_axes.iter().map(|a| a.n).product::<usize>() + 125;
        // The end time is a feature here: the model ends where a plain run (and `synth`) does.
        let plain = RunOptions { theta_flat: RunOptions::default().theta_flat, ..shooting.run.clone() };
        let (c, score) = coarse::sweep(&shooting.spec.base, &plain, &span, &features, opts.coarse_axes, &|k, _| {
            report(FitStage::Sweep, k, total, None)
        });
        check()?;
        if score.is_finite() {
            coarse_c = Some(c);
        }
    }

    // Each segment's state in turn, with the coarse drag and with the starting drag: the
    // features can mislead (turning points a slow camera blurs), the misfit decides.
    let mut best: Option<(f64, Vec<f64>, Vec<StateVec>)> = None;
    let drags = coarse_c.into_iter().map(|c| c.map(f64::ln).to_vec()).chain([global[..3].to_vec()]);
    for drag in drags {
        let mut g = global.clone();
        g[..3].copy_from_slice(&drag);
        let (cost, states) = init_segments(&shooting, &motion, &g, y0, &report, cancel)?;
        if best.as_ref().is_none_or(|b| cost < b.0) {
            best = Some((cost, g, states));
        }
    }
    let (_, global, states) = best.ok_or(FitError::BadStart)?;
    let count = shooting.segments.len();

    // Everything together; then segments twice as long, while the data agree.
    let lm_opts = LmOptions { max_iterations: opts.max_iterations, rel_tol: 1e-6, ..LmOptions::default() };
    let locals: Vec<Vec<f64>> = states.iter().map(|y| y.to_vec()).collect();
    let m_total: usize = (0..count).map(|s| shooting.residual_count(s)).sum();
    let max_it = opts.max_iterations;
    let mut on_iteration = |k, cost: f64| report(FitStage::Refine, k, max_it, Some((cost / m_total as f64).sqrt()));
    let mut sol = lm::solve(&shooting, global, locals, &lm_opts, &mut on_iteration, cancel)?;
    let mut iterations = sol.iterations;
    for _ in 0..opts.merges {
        if shooting.segments.len() < 2 {
            break;
        }
        let merged: Vec<Range<usize>> = shooting.segments.chunks(2).map(|p| p[0].start..p[p.len() - 1].end).collect();
        let locals: Vec<Vec<f64>> = sol.local.iter().step_by(2).cloned().collect();
        let longer = Shooting { segments: merged, ..shooting.clone() };
        let trial = lm::solve(&longer, sol.global.clone(), locals, &lm_opts, &mut on_iteration, cancel)?;
        iterations += trial.iterations;
        // Merging frees 8 numbers per pair: the cost may grow by about that many noise
        // variances. Much more means the segments no longer follow the data (a model that is
        // not the ring's, or a start state the least squares could not reach): keep the shorter.
        let freed = 8.0 * (shooting.segments.len() - longer.segments.len()) as f64;
        let variance = sol.cost / (sol.residual_count as f64 - (sol.global.len() + 8 * sol.local.len()) as f64).max(1.0);
        if (trial.cost - sol.cost) / variance > freed + 4.0 * (2.0 * freed).sqrt() {
            break;
        }
        (shooting, sol) = (longer, trial);
    }
    let count = shooting.segments.len();
    let values = shooting.spec.to_values(&sol.global);
    let params = sol.global.len() + count * 8;
    let jac = shooting.spec.value_per_internal(&sol.global);
    let sigma = |i: usize| sol.global_sigma(i, params, &jac);
    let segment_states: Vec<StateVec> = sol.local.iter().map(|b| b.as_slice().try_into().unwrap_or([f64::NAN; 8])).collect();
    let (model, camera) = shooting.spec.build(&sol.global).ok_or(FitError::BadStart)?;
    let window = shooting.segments[0].len();
    let (start, start_t) = start_at_turning_point(&model, &shooting.run, dt, f0, window, &segment_states[0]);
    let effect = match shooting.spec.free.get(3) {
        Some(Free::Effect(kind)) => Some((*kind, values[3], sigma(3))),
        _ => None,
    };
    Ok(FitResult {
        c: [values[0], values[1], values[2]],
        c_sigma: [sigma(0), sigma(1), sigma(2)],
        effect,
        start,
        start_t,
        start_frame: start_t / dt,
        rms_px: (sol.cost / sol.residual_count.max(1) as f64).sqrt(),
        residual_count: sol.residual_count,
        parameter_count: params,
        frames: n,
        frames_fitted: moving_end - f0,
        noise_px: tracks.noise.map(|n| n.px),
        glitches: tracks.glitches,
        segments: shooting.segments.clone(),
        segment_states,
        coarse_c,
        iterations,
        model,
        camera,
        units,
        dt,
        geometry: shooting.geometry,
        re_start: shooting.spec.re_start,
        run: shooting.run.clone(),
        compute_seconds: clock.elapsed().as_secs_f64(),
    })
}

/// Every segment's start state with the globals fixed, each from the previous segment's end
/// or the recovered poses, whichever fits better; and the total cost.
fn init_segments(
    sh: &Shooting,
    motion: &RecoveredMotion,
    global: &[f64],
    y0: StateVec,
    report: &dyn Fn(FitStage, usize, usize, Option<f64>),
    cancel: &AtomicBool,
) -> Result<(f64, Vec<StateVec>), FitError> {
    let count = sh.segments.len();
    let (model, _) = sh.spec.build(global).ok_or(FitError::BadStart)?;
    let (y0, mut total) = fit_segment(sh, 0, global, &[y0], cancel)?;
    let mut states = vec![y0];
    for s in 1..count {
        report(FitStage::Segments, s, count, None);
        let mut starts = Vec::new();
        let prev = sh.segments[s - 1].clone();
        if let Some(samples) = predict_samples(&model, &sh.run, sh.dt, &states[s - 1], prev.start..prev.end + 1)
            && let Some(last) = samples.last().filter(|x| x.t > (prev.end as f64 - 0.5) * sh.dt)
        {
            starts.push(last.y);
        }
        starts.extend(reconstruct(motion, sh.segments[s].start));
        if starts.is_empty() {
            starts.push(states[s - 1]);
        }
        let (y, cost) = fit_segment(sh, s, global, &starts, cancel)?;
        states.push(y);
        total += cost;
    }
    Ok((total, states))
}

/// Segments of `len` frames over `start..end`; a short remainder joins the last segment.
fn split(start: usize, end: usize, len: usize) -> Vec<Range<usize>> {
    let mut out = Vec::new();
    let mut a = start;
    while a < end {
        let b = (a + len).min(end);
        out.push(a..b);
        a = b;
    }
    if out.len() > 1
        && out.last().is_some_and(|r| r.len() < len / 2)
        && let Some(last) = out.pop()
        && let Some(prev) = out.last_mut()
    {
        prev.end = last.end;
    }
    out
}

/// The state at frame `i` from the recovered poses (or the nearest frame that has one), on
/// both branches `(phi, psi)` and `(phi + pi, psi + pi)` and with rates over +-2 and +-4
/// frames (the shorter for slow cameras): the fit keeps the one that fits best.
fn reconstruct(motion: &RecoveredMotion, i: usize) -> Vec<StateVec> {
    let j = (0..4).flat_map(|d| [i + d, i.saturating_sub(d)]).find(|&j| motion.state(j, 4, false).is_some());
    let Some(j) = j else { return Vec::new() };
    [(4, false), (4, true), (2, false), (2, true)].iter().filter_map(|&(half, f)| motion.state(j, half, f)).collect()
}

/// Fits segment `s`'s start state from the best of `starts` with the globals fixed.
fn fit_segment(sh: &Shooting, s: usize, global: &[f64], starts: &[StateVec], cancel: &AtomicBool) -> Result<(StateVec, f64), FitError> {
    let problem = OneSegment { shooting: sh, segment: s, global: global.to_vec() };
    let cost = |y: &StateVec| {
        sh.segment_residuals(s, global, y).map_or(f64::INFINITY, |r| r.iter().map(|x| x * x).sum::<f64>())
    };
    let best = starts.iter().copied().min_by(|a, b| cost(a).total_cmp(&cost(b))).ok_or(FitError::BadStart)?;
    let opts = LmOptions { max_iterations: 25, rel_tol: 1e-6, ..LmOptions::default() };
    match lm::solve(&problem, best.to_vec(), vec![vec![]], &opts, &mut |_, _| {}, cancel) {
        Ok(sol) => Ok((sol.global.as_slice().try_into().unwrap_or(best), sol.cost)),
        Err(LmError::Cancelled) => Err(FitError::Cancelled),
        // A start the model cannot run from: keep it, the joint fit may still move it.
        Err(LmError::BadStart) => Ok((best, f64::INFINITY)),
    }
}

/// A state with `theta' = 0` and the same `phi'` and `psi'` (w2 and w3 do not hold theta').
fn level_start(y: &StateVec) -> StateVec {
    let mut y = *y;
    y[ix::W1] = 0.0;
    y
}

/// The data's features for the coarse stage, in model time.
fn features(motion: &RecoveredMotion, f0: usize, moving_end: usize, n: usize, dt: f64) -> Features {
    let turning_points = motion
        .turning_points
        .iter()
        .filter(|p| p.at > f0 as f64 + 0.5 && p.at < moving_end as f64)
        .map(|p| (p.kind, p.at * dt, p.theta, p.theta_sigma))
        .collect();
    let t_end = (moving_end < n).then_some(moving_end as f64 * dt);
    Features { turning_points, t_end, t_end_sigma: 2.0 * dt }
}

/// The model's state at the first inner turning point: at frame `f0` when `theta`'s minimum
/// lies within half a frame before it (the start is the turning point to the frame), else the
/// first minimum the model passes in the next `window` frames.
fn start_at_turning_point(model: &Model, run: &RunOptions, dt: f64, f0: usize, window: usize, y0: &StateVec) -> (Initial, f64) {
    let t0 = f0 as f64 * dt;
    let w = Vector3::new(y0[ix::W1], y0[ix::W2], y0[ix::W3]);
    let theta_ddot = model.dynamics(y0[ix::THETA], &w).omega_dot.x;
    let vertex = if theta_ddot > 0.0 { -y0[ix::W1] / theta_ddot } else { f64::INFINITY };
    if (-0.5 * dt..=0.0).contains(&vertex) {
        return (Initial::from_state(y0), t0);
    }
    let opts = RunOptions { t_end: t0 + window as f64 * dt, sample_dt: None, track_validity: false, ..run.clone() };
    if let Ok(sim) = Simulation::from_state(model.clone(), t0, *y0, opts) {
        let summary = sim.run(&mut |_| {});
        if let Some(p) = summary.turning_points.iter().find(|p| p.kind == TurnKind::ThetaMin) {
            return (Initial::from_state(&p.sample.y), p.sample.t);
        }
    }
    (Initial::from_state(y0), t0)
}
