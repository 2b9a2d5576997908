//! The fit as a list of named stages (see the module doc of `analysis::fit`), each over a small
//! state: [`Data`] (the recording as the fit sees it), [`Problem`] (the multiple-shooting
//! problem and where it starts), [`Refined`] (the least squares' solution). [`FitRun`] owns the
//! progress reports and the cancel flag.

use super::coarse;
use super::last_runs::LastRuns;
use super::lm::{self, LmOptions, LmSolution};
use super::options::{FIT_THETA_FLAT, FitError, FitOptions, FitProgress, FitStage};
use super::params::{Free, ModelSpec, StartReynolds};
use super::result::FitResult;
use super::shooting::Shooting;
use super::start::{
    features, fit_segment, init_segments, level_start, reconstruct, split, start_at_turning_point,
};
use crate::physics::effects::EffectKind;
use crate::physics::{Model, RunOptions, StateVec, TurnKind};
use crate::recording::recover::{RecoveredMotion, recover_with};
use crate::recording::tracks::{CheckedTracks, as_tracked, check_tracks};
use crate::recording::{Camera, Recording};
use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};
use web_time::Instant;

/// Fits the model to a recording. `progress` is called from worker threads; `cancel` stops
/// the fit at the next evaluation with [`FitError::Cancelled`].
pub fn fit(
    rec: &Recording,
    opts: &FitOptions,
    progress: &(dyn Fn(&FitProgress) + Sync),
    cancel: &AtomicBool,
) -> Result<FitResult, FitError> {
    let clock = Instant::now();
    let run = FitRun { opts, progress, cancel };
    let data = run.recover(rec)?;
    let mut problem = run.set_up(&data)?;
    run.start_state(&mut problem)?;
    let coarse_c = run.coarse_drag(&data, &problem)?;
    run.segment_states(&data, &mut problem, coarse_c)?;
    let refined = run.refine(problem)?;
    refined.into_result(&data, coarse_c, clock)
}

/// One fit's options, progress and cancel flag.
struct FitRun<'a> {
    opts: &'a FitOptions,
    progress: &'a (dyn Fn(&FitProgress) + Sync),
    cancel: &'a AtomicBool,
}

/// The recording as the fit sees it: glitches left out, the motion recovered, the frames fitted.
struct Data {
    tracks: CheckedTracks,
    camera: Camera,
    motion: RecoveredMotion,
    /// The start (the first inner turning point's frame) and the end of the moving frames.
    f0: usize,
    moving_end: usize,
}

/// The multiple-shooting problem and where it starts.
struct Problem<'a> {
    shooting: Shooting<'a>,
    /// The global parameters (internal form: log drag, then an effect's strength).
    global: Vec<f64>,
    /// Start-state candidates at `f0`, and the one refined.
    starts: Vec<StateVec>,
    y0: StateVec,
    /// Each segment's start state (after [`FitRun::segment_states`]).
    states: Vec<StateVec>,
}

/// The least squares' solution, on the segments it ended with.
struct Refined<'a> {
    shooting: Shooting<'a>,
    sol: LmSolution,
    iterations: usize,
}

impl<'r> FitRun<'r> {
    fn report(&self, stage: FitStage, done: usize, total: usize, rms_px: Option<f64>) {
        (self.progress)(&FitProgress { stage, done, total, rms_px });
    }

    fn check(&self) -> Result<(), FitError> {
        if self.cancel.load(Ordering::Relaxed) { Err(FitError::Cancelled) } else { Ok(()) }
    }

    /// Stage 1: the tracker's glitches out, the camera, the motion from the poses, the frames
    /// from the first inner turning point to the still end.
    fn recover(&self, rec: &Recording) -> Result<Data, FitError> {
        let opts = self.opts;
        if opts.segment_frames < 10 {
            return Err(FitError::Options(format!(
                "segments of {} frames are too short (10 at least)",
                opts.segment_frames
            )));
        }
        self.report(FitStage::Recover, 0, 1, None);
        let tracks = if opts.leave_out_glitches { check_tracks(rec) } else { as_tracked(rec) };
        let rec = &tracks.recording;
        let mut camera =
            Camera { k1: opts.lens_k1, ..Camera::for_recording(&rec.header, &rec.frames) };
        if let Some(d) = opts.camera_distance_mm {
            if !(d.is_finite() && d > 0.0) {
                return Err(FitError::Options(format!(
                    "camera distance {d} mm must be a positive number"
                )));
            }
            camera.distance_mm = Some(d);
        }
        if let Some(t) = opts.camera_tilt_deg {
            if !(t.abs() < 80.0) {
                return Err(FitError::Options(format!(
                    "camera tilt {t} degrees must lie between -80 and 80"
                )));
            }
            camera.tilt_rad = t.to_radians();
        }
        let motion = recover_with(rec, camera)?;
        self.check()?;
        // The first frame when theta rises from it, else the first minimum; the model places
        // the turning point exactly (`start_at_turning_point`). Without one, the film's start,
        // or the first frame with a state where a film's opening is without marks (the ring
        // lost on edge).
        let f0 = match motion.turning_points.first() {
            Some(p) if p.kind == TurnKind::ThetaMin => p.at.floor().max(0.0) as usize,
            _ if reconstruct(&motion, 0).is_empty() => {
                (0..rec.frames.len()).find(|&i| motion.state(i, 4, false).is_some()).unwrap_or(0)
            }
            _ => 0,
        };
        let moving_end = motion.rest_from.unwrap_or(rec.frames.len()).max(f0);
        if moving_end - f0 < opts.segment_frames {
            return Err(FitError::TooFewFrames { start: f0, frames: moving_end - f0 });
        }
        Ok(Data { tracks, camera, motion, f0, moving_end })
    }

    /// Stage 2: the model (the recording's body, the starting drag, an effect's strength), the
    /// segments and the start-state candidates from the poses.
    fn set_up<'d>(&self, data: &'d Data) -> Result<Problem<'d>, FitError>
    where
        'r: 'd,
    {
        let opts = self.opts;
        let (motion, f0) = (&data.motion, data.f0);
        let units = motion.units;
        let to_model = motion.to_model();
        let body = motion.body_model().map_err(FitError::Model)?;
        let base =
            Model::new(body, units.g(), opts.c_start, units.nu_air()).map_err(FitError::Model)?;
        let dt = 1.0 / motion.fps * to_model.time;
        let mut starts = reconstruct(motion, f0);
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
        let re_start = StartReynolds::of(&base, &y0);
        let spec =
            ModelSpec { base, camera: data.camera, free, re_start, strength_ranges: Vec::new() };
        let shooting = Shooting {
            observed: &data.tracks.recording.frames,
            segments: split(f0, data.moving_end, opts.segment_frames),
            dt,
            spec,
            run: RunOptions {
                tol: opts.tolerances,
                theta_flat: FIT_THETA_FLAT,
                ..RunOptions::default()
            },
            geometry: motion.geometry_mm.scaled(to_model.length),
            length_mm: 1.0 / to_model.length,
            budget: None,
            last_runs: LastRuns::default(),
            cancel: self.cancel,
        };
        let mut global = shooting.spec.to_internal(&shooting.spec.initial_values());
        if let (Some((_, strength)), Some(g)) = (opts.effect, global.get_mut(3)) {
            *g = strength;
        }
        Ok(Problem { shooting, global, starts, y0, states: Vec::new() })
    }

    /// Stage 3: the start state, refined with the starting drag over a growing window: a
    /// quarter of the first segment, half, all of it (the rates from the poses are rough, and
    /// over a short window a rough start still lies in the right valley).
    fn start_state(&self, p: &mut Problem) -> Result<(), FitError> {
        self.report(FitStage::StartState, 0, 1, None);
        let first = p.shooting.segments[0].clone();
        let mut candidates = std::mem::take(&mut p.starts);
        for part in [4, 2, 1] {
            let end = first.start + (first.len() / part).max(12).min(first.len());
            let window = Shooting {
                segments: std::iter::once(first.start..end).collect(),
                ..p.shooting.clone()
            };
            p.y0 = fit_segment(&window, 0, &p.global, &candidates)?.0;
            candidates = vec![p.y0];
        }
        self.check()
    }

    /// Stage 4: the drag from a coarse grid on phase-free features (`coarse`), if asked for.
    fn coarse_drag(&self, data: &Data, p: &Problem) -> Result<Option<[f64; 3]>, FitError> {
        if !self.opts.coarse {
            return Ok(None);
        }
        let (f0, n, dt) = (data.f0, data.tracks.recording.frames.len(), p.shooting.dt);
        let features = features(&data.motion, f0, data.moving_end, n, dt);
        let span = coarse::Span { t0: f0 as f64 * dt, y0: p.y0, t_stop: (n as f64 + 1.0) * dt };
        let axes = self.opts.coarse_axes;
        let total = axes.iter().map(|a| a.n).product::<usize>() + 125;
        // The end time is a feature here: the model ends where a plain run (and `synth`) does.
        let plain =
            RunOptions { theta_flat: RunOptions::default().theta_flat, ..p.shooting.run.clone() };
        let (c, score) =
            coarse::sweep(&p.shooting.spec.base, &plain, &span, &features, axes, &|k, _| {
                self.report(FitStage::Sweep, k, total, None)
            });
        self.check()?;
        Ok(score.is_finite().then_some(c))
    }

    /// Stage 5: each segment's state in turn, with the coarse drag and with the starting drag:
    /// the features can mislead (turning points a slow camera blurs), the misfit decides.
    fn segment_states(
        &self,
        data: &Data,
        p: &mut Problem,
        coarse_c: Option<[f64; 3]>,
    ) -> Result<(), FitError> {
        let report = |stage: FitStage, done: usize, total: usize, rms: Option<f64>| {
            self.report(stage, done, total, rms)
        };
        let mut best: Option<(f64, Vec<f64>, Vec<StateVec>)> = None;
        let drags =
            coarse_c.into_iter().map(|c| c.map(f64::ln).to_vec()).chain([p.global[..3].to_vec()]);
        for drag in drags {
            let mut g = p.global.clone();
            g[..3].copy_from_slice(&drag);
            let (cost, states) = init_segments(&p.shooting, &data.motion, &g, p.y0, &report)?;
            if best.as_ref().is_none_or(|b| cost < b.0) {
                best = Some((cost, g, states));
            }
        }
        let (_, global, states) = best.ok_or(FitError::BadStart)?;
        (p.global, p.states) = (global, states);
        Ok(())
    }

    /// Stage 6: everything together (Levenberg-Marquardt); then segments twice as long, while
    /// the data agree.
    fn refine<'d>(&self, p: Problem<'d>) -> Result<Refined<'d>, FitError> {
        let max_it = self.opts.max_iterations;
        let lm_opts = LmOptions { max_iterations: max_it, rel_tol: 1e-6, ..LmOptions::default() };
        let mut shooting = p.shooting;
        let locals: Vec<Vec<f64>> = p.states.iter().map(|y| y.to_vec()).collect();
        let m_total: usize = (0..shooting.segments.len()).map(|s| shooting.residual_count(s)).sum();
        let mut on_iteration = |k, cost: f64| {
            self.report(FitStage::Refine, k, max_it, Some((cost / m_total as f64).sqrt()))
        };
        let mut sol =
            lm::solve(&shooting, p.global, locals, &lm_opts, &mut on_iteration, shooting.cancel)?;
        let mut iterations = sol.iterations;
        for _ in 0..self.opts.merges {
            if shooting.segments.len() < 2 {
                break;
            }
            let merged: Vec<Range<usize>> =
                shooting.segments.chunks(2).map(|p| p[0].start..p[p.len() - 1].end).collect();
            let locals: Vec<Vec<f64>> = sol.local.iter().step_by(2).cloned().collect();
            let longer = Shooting { segments: merged, ..shooting.clone() };
            let trial = lm::solve(
                &longer,
                sol.global.clone(),
                locals,
                &lm_opts,
                &mut on_iteration,
                longer.cancel,
            )?;
            iterations += trial.iterations;
            // Merging frees 8 numbers per pair: the cost may grow by about that many noise
            // variances. Much more means the segments no longer follow the data (a model that
            // is not the ring's, or a start state the least squares could not reach): keep the
            // shorter.
            let freed = 8.0 * (shooting.segments.len() - longer.segments.len()) as f64;
            let variance = sol.cost
                / (sol.residual_count as f64
                    - (shooting.spec.fitted_count() + 8 * sol.local.len()) as f64)
                    .max(1.0);
            if (trial.cost - sol.cost) / variance > freed + 4.0 * (2.0 * freed).sqrt() {
                break;
            }
            (shooting, sol) = (longer, trial);
        }
        Ok(Refined { shooting, sol, iterations })
    }
}

impl Refined<'_> {
    /// Stage 7: the fitted values with their sigmas, the model's state at the first inner
    /// turning point, everything a caller may want to run or refit.
    fn into_result(
        self,
        data: &Data,
        coarse_c: Option<[f64; 3]>,
        clock: Instant,
    ) -> Result<FitResult, FitError> {
        let Refined { shooting, sol, iterations } = self;
        let dt = shooting.dt;
        let count = shooting.segments.len();
        let values = shooting.spec.to_values(&sol.global);
        let params = shooting.spec.fitted_count() + count * 8;
        let jac = shooting.spec.value_per_internal(&sol.global);
        let sigma = |i: usize| sol.global_sigma(i, params, &jac);
        let segment_states: Vec<StateVec> =
            sol.local.iter().map(|b| b.as_slice().try_into().unwrap_or([f64::NAN; 8])).collect();
        let (model, camera) = shooting.spec.build(&sol.global).ok_or(FitError::BadStart)?;
        let window = shooting.segments[0].len();
        let (start, start_t) =
            start_at_turning_point(&model, &shooting.run, dt, data.f0, window, &segment_states[0]);
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
            frames: data.tracks.recording.frames.len(),
            frames_fitted: data.moving_end - data.f0,
            noise_px: data.tracks.noise.map(|n| n.px),
            glitches: data.tracks.glitches.clone(),
            segments: shooting.segments.clone(),
            segment_states,
            coarse_c,
            iterations,
            model,
            camera,
            units: data.motion.units,
            dt,
            geometry: shooting.geometry,
            re_start: shooting.spec.re_start,
            run: shooting.run.clone(),
            compute_seconds: clock.elapsed().as_secs_f64(),
        })
    }
}
