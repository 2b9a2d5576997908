//! The diagnosis's misfit: one prediction of the whole run from one start state (single
//! shooting), reached from the multiple-shooting fit by merging its segments pairwise until
//! one is left (see the module doc of `analysis::diagnose` for why).

use super::options::SLIP_TOLERANCES;
use super::result::ExtraFit;
use crate::analysis::fit::lm::{self, LmError, LmOptions};
use crate::analysis::fit::shooting::{PredictedMarks, Shooting, predict_samples};
use crate::analysis::fit::{Free, ModelSpec};
use crate::physics::effects::EffectKind;
use crate::physics::integrator::Tolerances;
use crate::physics::slip::painleve_mu_limit;
use crate::physics::{Model, Sample, StateVec};
use crate::recording::Camera;
use crate::recording::marks::{MarkGeometry, mark_radius};
use rayon::prelude::*;
use std::ops::Range;

/// Iterations allowed at each intermediate segmentation (they only need to keep the path in
/// the right valley), and at the final single segment.
pub const LEVEL_ITERATIONS: usize = 6;
/// Fresh Jacobians allowed at the final single segment, and the Broyden steps allowed after
/// each (see `lm`): over the whole run the fit creeps along a curved valley in many small
/// steps, and a secant step costs one run where a fresh Jacobian costs 14 to 16.
pub(super) const FINAL_ITERATIONS: usize = 20;
const FINAL_SECANT_STEPS: usize = 3;
/// The last stage stops when an iteration gains less than this share of the misfit: a BIC
/// difference of 0.1 over 10,000 coordinates is a share of 1e-5.
pub(super) const FINAL_REL_TOL: f64 = 1e-5;

/// A model fitted to the whole run from one state.
#[derive(Clone, Debug)]
pub struct WholeFit {
    /// The effect fitted (`None` for the baseline; the last one added for a pair).
    pub kind: EffectKind,
    /// Effects fitted beside it, before it (a pair's first), with their strengths and sigmas.
    pub also: Vec<(EffectKind, (f64, f64))>,
    pub c: [f64; 3],
    pub c_sigma: [f64; 3],
    /// The effect's strength and its sigma (infinite where the data do not constrain it).
    pub strength: Option<(f64, f64)>,
    /// The effects' extra numbers as fitted, with their sigmas (each effect's
    /// `Descriptor::extras`).
    pub extras: Vec<ExtraFit>,
    /// The body's outer radius and width (model units) and their sigmas.
    pub body: [(f64, f64); 2],
    /// The start state at the first frame of `span` (model units).
    pub start: StateVec,
    /// Frames predicted: from the first inner turning point to the still end.
    pub span: Range<usize>,
    /// Sum of squared pixel residuals, their number, and the free parameters (drag, effect,
    /// start state).
    pub cost: f64,
    pub residual_count: usize,
    pub parameter_count: usize,
    pub model: Model,
    pub camera: Camera,
    pub iterations: usize,
    /// The internal parameters (`ln C`, the body, the effect's numbers): where a refit can start.
    pub internal: Vec<f64>,
    /// Time this fit took (s), its path included.
    pub seconds: f64,
    /// Where its path stopped short of one segment (the segments of that stage), because the
    /// stage fitted worse than its ceiling ([`fit_path`]); None for a path walked to the end.
    pub stopped_at: Option<usize>,
}

impl WholeFit {
    /// RMS of model minus recording over every tracked mark coordinate of the span (px).
    pub fn rms_px(&self) -> f64 {
        (self.cost / self.residual_count.max(1) as f64).sqrt()
    }

    /// The model's samples at the span's frames (the final pose repeated after its end).
    pub fn samples(&self, sh: &Shooting) -> Option<Vec<Sample>> {
        predict_samples(&self.model, &sh.run, sh.dt, &self.start, self.span.clone())
    }

    /// Its effects in the order fitted: those beside it, then its own.
    pub fn kinds(&self) -> Vec<EffectKind> {
        self.also.iter().map(|(k, _)| *k).chain([self.kind]).collect()
    }

    /// The predicted marks at the span's frames (px), on the marks' circle of this fit's body.
    pub fn marks(&self, sh: &Shooting) -> Option<PredictedMarks> {
        let geometry = MarkGeometry {
            radius: mark_radius(&self.model.body),
            r_outer: self.model.body.r,
            h: self.model.body.h,
            order: sh.geometry.order,
        };
        Some(self.samples(sh)?.iter().map(|s| sh.project(&geometry, &self.camera, s)).collect())
    }
}

/// The multiple-shooting problem `ms` with the drag, the body's outer radius and width, and
/// `kind`'s strength free, in that order (the strength last). The header's dimensions are
/// caliper readings: over a whole run a width off by 1.5% (the sample's header says 18 mm of a
/// 17.74 mm ring) misses by 3 px, a misfit that an effect would otherwise be named for.
pub fn with_effect<'a>(ms: &Shooting<'a>, kind: EffectKind) -> Shooting<'a> {
    with_effects(ms, &[kind])
}

/// [`with_effect`] for several effects at once, their numbers in the order given (a pair of
/// the forward selection: the effect named first, then the one tried beside it).
pub fn with_effects<'a>(ms: &Shooting<'a>, kinds: &[EffectKind]) -> Shooting<'a> {
    let mut free: Vec<Free> = (0..3).map(Free::Drag).collect();
    free.extend([Free::Body(0), Free::Body(1)]);
    let mu_max = painleve_mu_limit(&ms.spec.base);
    let mut strength_ranges = Vec::new();
    for &kind in kinds.iter().filter(|&&k| k.free_count() > 0) {
        free.extend(Free::of_effect(kind));
        strength_ranges.push((kind, search_range(kind, mu_max)));
    }
    let mut run = ms.run.clone();
    // Slip's runs switch between rolling and sliding: their own tolerances.
    if kinds.contains(&EffectKind::Slip) {
        run.tol = Tolerances {
            rtol: run.tol.rtol.min(SLIP_TOLERANCES.rtol),
            atol: run.tol.atol.min(SLIP_TOLERANCES.atol),
        };
    }
    Shooting { spec: ModelSpec { free, strength_ranges, ..ms.spec.clone() }, run, ..ms.clone() }
}

/// Where the diagnosis looks for an effect's strength: from its baseline strength (zero; the
/// lens: either sign) to four times its realistic range's far end; slip from a quarter of its
/// low end to just below the Painleve limit `mu_max`. Beyond, the physics is no longer the
/// effect's (a ring that skids through its whole run, drag ten times the paper's) and the runs
/// crawl: a trial step there would cost a hundred ordinary ones.
pub fn search_range(kind: EffectKind, mu_max: f64) -> (f64, f64) {
    let d = kind.descriptor();
    (d.search)(d.realistic, mu_max)
}

/// The multiple-shooting cost of `sh` at `global` with the segments' states held (infinite
/// where the model cannot run): how well a strength suits the data before any refit.
pub fn segment_cost(sh: &Shooting, global: &[f64], states: &[StateVec]) -> f64 {
    sh.settle_budget();
    let costs: Vec<f64> = (0..sh.segments.len())
        .into_par_iter()
        .map(|s| {
            sh.segment_residuals(s, global, &states[s])
                .map_or(f64::INFINITY, |r| r.iter().map(|x| x * x).sum())
        })
        .collect();
    costs.iter().sum()
}

/// One stage of a path: its segments, globals and segment states after its fit, and its
/// misfit (sum of squares) there.
#[derive(Clone, Debug)]
pub struct Level {
    pub segments: Vec<Range<usize>>,
    pub global: Vec<f64>,
    pub states: Vec<StateVec>,
    pub cost: f64,
}

/// No ceiling on a path's stages (see [`fit_path`]).
pub fn no_ceiling(_segments: usize) -> f64 {
    f64::INFINITY
}

/// Fits the whole run with `sh`'s globals free from `global` (see [`with_effect`]), the
/// segments' start states from `states`: the segments are merged pairwise, each time
/// refitted, until one prediction spans the run. Every candidate walks the same path from the
/// baseline's segments, so the misfits compare. With one segment it is plain single shooting.
pub fn fit_whole(
    sh: &Shooting,
    global: Vec<f64>,
    states: &[StateVec],
    on_iteration: &mut dyn FnMut(usize, f64),
) -> Result<WholeFit, LmError> {
    fit_path(sh, global, states, &no_ceiling, on_iteration).map(|(w, _)| w)
}

/// [`fit_whole`], and the fitted stages of its path (for other paths to start from). A stage
/// with `n` segments that ends with a misfit above `ceiling(n)` ends the path there: the fit
/// returned is that stage's globals run over the whole span from its first segment's state,
/// without uncertainties (a candidate that fits far worse than the baseline at the same
/// segments has left the baseline's valley, and its later stages only cost time).
pub fn fit_path(
    sh: &Shooting,
    global: Vec<f64>,
    states: &[StateVec],
    ceiling: &dyn Fn(usize) -> f64,
    on_iteration: &mut dyn FnMut(usize, f64),
) -> Result<(WholeFit, Vec<Level>), LmError> {
    let clock = web_time::Instant::now();
    let kinds = fitted_kinds(sh);
    let kind = kinds.last().copied().unwrap_or(EffectKind::None);
    let walked = walk(sh, global, states, ceiling, on_iteration, kind)?;
    let mut fit = whole_fit(&walked, &kinds)?;
    fit.seconds = clock.elapsed().as_secs_f64();
    Ok((fit, walked.levels))
}

/// Where a path's walk ended: its last stage's problem (one segment) and solution, every
/// stage, the iterations spent, and the stage whose ceiling stopped it.
struct Walked<'a> {
    sh: Shooting<'a>,
    sol: lm::LmSolution,
    levels: Vec<Level>,
    iterations: usize,
    stopped_at: Option<usize>,
}

/// The stages of [`fit_path`]: the segments merged pairwise, each stage refitted (or taken as
/// it starts where the merged segments follow the data already), down to one segment or to a
/// stage above its ceiling.
fn walk<'a>(
    sh: &Shooting<'a>,
    global: Vec<f64>,
    states: &[StateVec],
    ceiling: &dyn Fn(usize) -> f64,
    on_iteration: &mut dyn FnMut(usize, f64),
    kind: EffectKind,
) -> Result<Walked<'a>, LmError> {
    let mut sh = sh.clone();
    let mut global = global;
    let mut locals: Vec<Vec<f64>> = states.iter().map(|y| y.to_vec()).collect();
    let (mut iterations, mut levels) = (0, Vec::new());
    // The previous stage's cost, residual count and free numbers.
    let mut previous: Option<(f64, usize, usize)> = None;
    loop {
        let segments = sh.segments.len();
        let last = segments == 1;
        if !last && let Some(level) = as_it_starts(&sh, &global, &locals, previous) {
            on_iteration(segments, level.cost);
            previous = previous
                .map(|(_, count, _)| (level.cost, count, sh.spec.fitted_count() + 8 * segments));
            levels.push(level);
            sh.segments = merged(&sh.segments);
            locals = locals.iter().step_by(2).cloned().collect();
            continue;
        }
        let opts = stage_options(last, kind);
        let mut on_stage = |_, cost| on_iteration(segments, cost);
        let sol = lm::solve(&sh, global, locals, &opts, &mut on_stage, sh.cancel)?;
        iterations += sol.iterations;
        levels.push(Level {
            segments: sh.segments.clone(),
            global: sol.global.clone(),
            states: as_states(&sol.local),
            cost: sol.cost,
        });
        if last {
            return Ok(Walked { sh, sol, levels, iterations, stopped_at: None });
        }
        if sol.cost > ceiling(segments) {
            let sol = over_the_whole_span(&mut sh, sol)?;
            return Ok(Walked { sh, sol, levels, iterations, stopped_at: Some(segments) });
        }
        previous = Some((sol.cost, sol.residual_count, sh.spec.fitted_count() + 8 * segments));
        sh.segments = merged(&sh.segments);
        locals = sol.local.iter().step_by(2).cloned().collect();
        global = sol.global;
    }
}

/// A path stopped at the stage `sh` holds (solved as `sol`): that stage's globals run over the
/// whole span from its first segment's state, without uncertainties (as [`fit_path`] ends a
/// stage above its ceiling).
pub fn stopped_at_stage(sh: &Shooting, sol: lm::LmSolution) -> Result<WholeFit, LmError> {
    let mut sh = sh.clone();
    let stopped_at = Some(sh.segments.len());
    let iterations = sol.iterations;
    let sol = over_the_whole_span(&mut sh, sol)?;
    let walked = Walked { sh, sol, levels: Vec::new(), iterations, stopped_at };
    whole_fit(&walked, &fitted_kinds(&walked.sh))
}

/// `sol`'s globals and first segment's state as one segment over all of `sh`'s, and its cost.
fn over_the_whole_span(sh: &mut Shooting, sol: lm::LmSolution) -> Result<lm::LmSolution, LmError> {
    let (first, last) = match (sh.segments.first(), sh.segments.last()) {
        (Some(a), Some(b)) => (a.start, b.end),
        _ => return Err(LmError::BadStart),
    };
    sh.segments = vec![first..last];
    let start: Vec<f64> = sol.local.first().cloned().ok_or(LmError::BadStart)?;
    let cost = segment_cost(sh, &sol.global, &as_states(std::slice::from_ref(&start)));
    Ok(lm::LmSolution { local: vec![start], cost, global_cov_unscaled: None, ..sol })
}

/// The effects `sh` fits, in order.
fn fitted_kinds(sh: &Shooting) -> Vec<EffectKind> {
    sh.spec
        .free
        .iter()
        .filter_map(|f| if let Free::Effect(k) = f { Some(*k) } else { None })
        .collect()
}

/// The segments merged pairwise (an odd last one alone).
fn merged(segments: &[Range<usize>]) -> Vec<Range<usize>> {
    segments.chunks(2).map(|p| p[0].start..p[p.len() - 1].end).collect()
}

fn as_states(locals: &[Vec<f64>]) -> Vec<StateVec> {
    locals.iter().map(|b| b.as_slice().try_into().unwrap_or([f64::NAN; 8])).collect()
}

/// The stage at `sh`'s segments as it starts, where the longer segments fit as they start
/// within what the freed states allow (the fit's merge rule): then it needs no refit, the model
/// follows the data over them already. Saves most of the work for a model that is right.
fn as_it_starts(
    sh: &Shooting,
    global: &[f64],
    locals: &[Vec<f64>],
    previous: Option<(f64, usize, usize)>,
) -> Option<Level> {
    let (cost, count, params) = previous?;
    let segments = sh.segments.len();
    let start = segment_cost(sh, global, &as_states(locals));
    let freed = (params - sh.spec.fitted_count() - 8 * segments) as f64;
    let variance = cost / count.saturating_sub(params).max(1) as f64;
    (start - cost <= (freed + 4.0 * (2.0 * freed).sqrt()) * variance).then(|| Level {
        segments: sh.segments.clone(),
        global: global.to_vec(),
        states: as_states(locals),
        cost: start,
    })
}

/// The least squares' options for a stage of a path: a few iterations to keep an intermediate
/// stage in the right valley, more (and the uncertainties) at the last.
fn stage_options(last: bool, kind: EffectKind) -> LmOptions {
    LmOptions {
        max_iterations: if last { FINAL_ITERATIONS } else { LEVEL_ITERATIONS },
        rel_tol: if last { FINAL_REL_TOL } else { 1e-4 },
        covariance: last,
        secant_steps: if last { FINAL_SECANT_STEPS } else { 0 },
        // The baseline's misfit is what every candidate's is measured against: its last
        // stage stops where the exact gradient vanishes (`lm`'s cheaper columns).
        exact_finish: last && kind == EffectKind::None,
        ..LmOptions::default()
    }
}

/// The fit a walk ended with, its numbers as values with their sigmas (`kinds`: the effects
/// fitted, in order).
fn whole_fit(walked: &Walked, kinds: &[EffectKind]) -> Result<WholeFit, LmError> {
    let (sh, sol) = (&walked.sh, &walked.sol);
    let kind = kinds.last().copied().unwrap_or(EffectKind::None);
    let values = sh.spec.to_values(&sol.global);
    let jac = sh.spec.value_per_internal(&sol.global);
    let params = sh.spec.fitted_count() + 8;
    let sigma = |i: usize| sol.global_sigma(i, params, &jac);
    let (model, camera) = sh.spec.build(&sol.global).ok_or(LmError::BadStart)?;
    let at = |want: Free| sh.spec.free.iter().position(|f| *f == want);
    let value = |want: Free, default: f64| {
        at(want).map_or((default, f64::INFINITY), |i| (values[i], sigma(i)))
    };
    let start: StateVec =
        sol.local.first().and_then(|b| b.as_slice().try_into().ok()).ok_or(LmError::BadStart)?;
    Ok(WholeFit {
        kind,
        c: [values[0], values[1], values[2]],
        c_sigma: [sigma(0), sigma(1), sigma(2)],
        strength: (kind != EffectKind::None).then(|| value(Free::Effect(kind), f64::NAN)),
        extras: sh
            .spec
            .free
            .iter()
            .filter_map(|f| match *f {
                Free::Extra(k, i) if !sh.spec.is_held(*f) => {
                    Some(ExtraFit { kind: k, index: i, value: value(*f, 0.0) })
                }
                _ => None,
            })
            .collect(),
        also: kinds[..kinds.len().saturating_sub(1)]
            .iter()
            .map(|&k| (k, value(Free::Effect(k), f64::NAN)))
            .collect(),
        body: [value(Free::Body(0), model.body.r), value(Free::Body(1), model.body.h)],
        start,
        span: sh.segments[0].clone(),
        cost: sol.cost,
        residual_count: sol.residual_count,
        parameter_count: params,
        model,
        camera,
        iterations: walked.iterations,
        internal: sol.global.clone(),
        seconds: 0.0,
        stopped_at: walked.stopped_at,
    })
}
