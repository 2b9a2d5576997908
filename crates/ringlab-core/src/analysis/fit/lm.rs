//! Levenberg-Marquardt for least squares with shared and block-local parameters.
//!
//! The residuals come in blocks `r_s(g, b_s)`: every block sees the global parameters `g`
//! and its own `b_s` (multiple shooting: the drag and each segment's start state). The
//! normal matrix is then an arrowhead, solved through the Schur complement on `g`:
//! `(N_gg - sum N_gs N_ss^-1 N_sg) dg = a_g - sum N_gs N_ss^-1 a_s`, then each `db_s`.
//! Damping: Marquardt's `lambda diag(N)`. Jacobians by forward differences, in parallel
//! over blocks and columns (rayon), after one evaluation per block at the point
//! ([`BlockProblem::at_point`]) whose work the columns may share (a model run's steps). A
//! problem without blocks is plain LM on `g`. Bounds ([`BlockProblem::project_global`]): a
//! global at its bound whose step points out is held there, the step solved for the rest.
//!
//! Secant steps ([`LmOptions::secant_steps`]): a forward-difference Jacobian costs one
//! evaluation per column (14 whole runs for a diagnosis candidate), a step one. Between fresh
//! Jacobians each block's is carried by Broyden's rank-one update to each accepted step's
//! secant (Madsen, Nielsen & Tingleff, "Methods for non-linear least squares problems", 2004,
//! sec. 3.4). It is refreshed after a secant step fails, after the allowed number of them, and
//! before the fit may stop: it stops only where a fresh Jacobian finds no gain.

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use thiserror::Error;

/// What [`BlockProblem::at_point`] works out at the point of a Jacobian, for its columns.
#[derive(Clone, Debug, Default)]
pub struct AtPoint {
    /// Forward-difference columns (steps from [`BlockProblem::local_step`]) for
    /// [`BlockProblem::symmetric_locals`], in that order.
    pub symmetry: Vec<Vec<f64>>,
    /// What the columns' evaluations share: the model run's step ends, which the runs of the
    /// columns follow (`physics::run`'s `steps.rs`: a smooth difference at any tolerance).
    pub step_ends: Option<Arc<[f64]>>,
    /// The residuals the integrated columns are differenced against, where their runs take
    /// another scheme than the point's ([`BlockProblem::column_residuals`]): that scheme's run
    /// at the point. None: the point's own residuals.
    pub column_base: Option<Vec<f64>>,
    /// Forward-difference columns of globals that move no run (a camera's numbers, a number
    /// held at zero), by their index: the point's run seen again, the global stepped by
    /// [`BlockProblem::global_step`]. Those globals' runs are not made.
    pub unrun: Vec<(usize, Vec<f64>)>,
    /// The work the unrun columns' runs would have cost, charged as if they were made
    /// ([`BlockProblem::charge_deferred`]), so that a budget stops a fit where it did with them.
    pub deferred_work: u64,
}

/// Residuals in blocks; each block's length must not depend on the parameters.
pub trait BlockProblem: Sync {
    fn global_count(&self) -> usize;
    fn block_count(&self) -> usize;
    fn block_size(&self) -> usize;
    /// Residuals of block `s`; None where the parameters leave the model's domain.
    fn residuals(&self, s: usize, global: &[f64], local: &[f64]) -> Option<Vec<f64>>;
    /// Forward-difference step for global parameter `i` at `value`.
    fn global_step(&self, i: usize, value: f64) -> f64;
    /// Forward-difference step for local parameter `i` at `value`.
    fn local_step(&self, i: usize, value: f64) -> f64;
    /// Local parameters whose Jacobian columns [`BlockProblem::at_point`] gives without
    /// re-evaluating the block (a symmetry of the problem). Default: none.
    fn symmetric_locals(&self) -> &[usize] {
        &[]
    }
    /// Once per block where a Jacobian is made, before its columns: the columns of
    /// [`BlockProblem::symmetric_locals`] and what the other columns' evaluations share. None
    /// where it cannot be had. Default: nothing shared (and no symmetric locals). With
    /// `cheap`, the other columns may be evaluated by a cheaper, less exact scheme
    /// ([`AtPoint::column_base`]); [`solve`] asks for exact ones before it stops.
    fn at_point(
        &self,
        _s: usize,
        _global: &[f64],
        _local: &[f64],
        _cheap: bool,
    ) -> Option<AtPoint> {
        Some(AtPoint::default())
    }
    /// Residuals of block `s` for a forward-difference column at `at`'s point. Default: as
    /// [`BlockProblem::residuals`].
    fn column_residuals(
        &self,
        s: usize,
        global: &[f64],
        local: &[f64],
        _at: &AtPoint,
    ) -> Option<Vec<f64>> {
        self.residuals(s, global, local)
    }
    /// Brings a trial step's globals back into their box, where some are bounded (a projected
    /// Levenberg-Marquardt step: the others still move where one sits at its bound). Default:
    /// none bounded.
    fn project_global(&self, _global: &mut [f64]) {}
    /// Called before each batch of parallel evaluations, so that a problem with a shared work
    /// budget decides once per batch whether it is spent, not in the threads' order.
    fn settle(&self) {}
    /// After the settle that follows [`BlockProblem::at_point`], where the columns' runs would
    /// be charged: the work of the columns it gave without runs ([`AtPoint::deferred_work`]).
    fn charge_deferred(&self, _work: u64) {}
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LmOptions {
    pub max_iterations: usize,
    /// Stop when an accepted step lowers the cost by less than this fraction.
    pub rel_tol: f64,
    pub lambda0: f64,
    /// Whether to linearize once more at the solution for the globals' covariance
    /// ([`LmSolution::global_cov_unscaled`]). A fit that only leads to the next one (a stage
    /// of a path) goes without: that last Jacobian costs as much as an iteration.
    pub covariance: bool,
    /// Steps allowed on a Broyden-updated Jacobian before a fresh one (0: every step on a
    /// fresh one). `max_iterations` counts fresh Jacobians; steps in all are capped at
    /// `max_iterations * (1 + secant_steps)`.
    pub secant_steps: usize,
    /// Whether a fit on cheaper columns ([`AtPoint::column_base`]) goes on with exact ones
    /// where they stall, to stop where the exact gradient vanishes. A fit that only leads to
    /// the next one (a stage of a path) can stop where the cheaper ones stall.
    pub exact_finish: bool,
}

impl Default for LmOptions {
    fn default() -> Self {
        LmOptions {
            max_iterations: 50,
            rel_tol: 1e-6,
            lambda0: 1e-3,
            covariance: true,
            secant_steps: 0,
            exact_finish: true,
        }
    }
}

#[derive(Debug, Error, Clone, PartialEq)]
pub enum LmError {
    #[error("cancelled")]
    Cancelled,
    #[error("the model cannot be evaluated at the starting parameters")]
    BadStart,
}

/// The solution and what its uncertainty needs.
#[derive(Clone, Debug)]
pub struct LmSolution {
    pub global: Vec<f64>,
    pub local: Vec<Vec<f64>>,
    /// Sum of squared residuals.
    pub cost: f64,
    pub residual_count: usize,
    pub iterations: usize,
    /// `(J^T J)^-1` restricted to the globals (the inverse Schur complement), unscaled:
    /// multiply by the residual variance for the covariance. None unless asked for
    /// ([`LmOptions::covariance`]).
    pub global_cov_unscaled: Option<DMatrix<f64>>,
}

impl LmSolution {
    /// One-sigma uncertainty of global `i` in value space: its unscaled covariance times the
    /// residual variance (`params` free numbers in all, locals included), through
    /// `value_per_internal` (`d value / d internal` at the solution); infinite where the data
    /// do not constrain it.
    pub fn global_sigma(&self, i: usize, params: usize, value_per_internal: &[f64]) -> f64 {
        let variance = self.cost / self.residual_count.saturating_sub(params).max(1) as f64;
        self.global_cov_unscaled
            .as_ref()
            .map(|c| c[(i, i)])
            .filter(|v| v.is_finite() && *v >= 0.0)
            .map_or(f64::INFINITY, |v| value_per_internal[i] * (variance * v).sqrt())
    }
}

struct Linearized {
    blocks: Vec<BlockJacobian>,
    cost: f64,
    /// Whether some block's columns came from the cheaper scheme.
    cheap: bool,
}

struct BlockJacobian {
    r: DVector<f64>,
    jg: DMatrix<f64>,
    jb: DMatrix<f64>,
}

/// Cost and residuals of every block, None where any block fails.
fn evaluate(p: &dyn BlockProblem, g: &[f64], b: &[Vec<f64>]) -> Option<(f64, Vec<Vec<f64>>)> {
    p.settle();
    let res: Option<Vec<Vec<f64>>> =
        (0..p.block_count()).into_par_iter().map(|s| p.residuals(s, g, &b[s])).collect();
    let res = res?;
    let cost = res.iter().flatten().map(|x| x * x).sum();
    Some((cost, res))
}

fn linearize(
    p: &dyn BlockProblem,
    g: &[f64],
    b: &[Vec<f64>],
    base: Vec<Vec<f64>>,
    cost: f64,
    cheap: bool,
) -> Option<Linearized> {
    p.settle();
    let (ng, nb) = (p.global_count(), p.block_size());
    let sym = p.symmetric_locals();
    let at: Option<Vec<AtPoint>> =
        (0..p.block_count()).into_par_iter().map(|s| p.at_point(s, g, &b[s], cheap)).collect();
    let at = at?;
    let cheap = at.iter().any(|a| a.column_base.is_some());
    p.settle();
    p.charge_deferred(at.iter().map(|a| a.deferred_work).sum());
    // One job per (block, column) left after the symmetry's and the unrun globals'.
    let given = |s: usize, c: usize| at[s].unrun.iter().any(|(i, _)| *i == c);
    let jobs: Vec<(usize, usize)> = (0..p.block_count())
        .flat_map(|s| {
            (0..ng + nb)
                .filter(move |&c| if c < ng { !given(s, c) } else { !sym.contains(&(c - ng)) })
                .map(move |c| (s, c))
        })
        .collect();
    let results: Option<Vec<(usize, Vec<f64>)>> = jobs
        .par_iter()
        .map(|&(s, c)| {
            let (mut gg, mut bb) = (g.to_vec(), b[s].clone());
            let h = if c < ng {
                let h = p.global_step(c, gg[c]);
                gg[c] += h;
                h
            } else {
                let h = p.local_step(c - ng, bb[c - ng]);
                bb[c - ng] += h;
                h
            };
            let r = p.column_residuals(s, &gg, &bb, &at[s])?;
            let r0 = at[s].column_base.as_ref().unwrap_or(&base[s]);
            Some((c, r.iter().zip(r0).map(|(a, r0)| (a - r0) / h).collect()))
        })
        .collect();
    let mut cols: Vec<Vec<Vec<f64>>> = vec![vec![Vec::new(); ng + nb]; p.block_count()];
    for (&(s, _), (c, col)) in jobs.iter().zip(results?) {
        cols[s][c] = col;
    }
    for (s, at) in at.into_iter().enumerate() {
        if at.symmetry.len() != sym.len() {
            return None;
        }
        for (&i, col) in sym.iter().zip(at.symmetry) {
            cols[s][ng + i] = col;
        }
        for (c, col) in at.unrun {
            cols[s][c] = col;
        }
    }
    let blocks = base
        .into_iter()
        .enumerate()
        .map(|(s, r)| {
            let m = r.len();
            let col = |c: usize| &cols[s][c];
            BlockJacobian {
                jg: DMatrix::from_fn(m, ng, |i, c| col(c)[i]),
                jb: DMatrix::from_fn(m, nb, |i, c| col(ng + c)[i]),
                r: DVector::from_vec(r),
            }
        })
        .collect();
    Some(Linearized { blocks, cost, cheap })
}

/// A damped step and the inverse of the damped Schur complement.
struct Step {
    dg: DVector<f64>,
    db: Vec<DVector<f64>>,
    schur_inverse: DMatrix<f64>,
}

/// The normal equations of a linearization, undamped, block by block: `N_gg = J_g^T J_g`,
/// `a_g = -J_g^T r`, and where the block has locals `(N_ss, N_gs, a_s)`. Made once for every
/// damping a step tries (each `lambda`, each active set), not once per try: over the whole run
/// a block has some 14,000 rows, and these products were most of a step's cost. The same
/// products, summed in the same order, as when each try made them.
struct Normals(Vec<BlockNormals>);

struct BlockNormals {
    n_gg: DMatrix<f64>,
    a_g: DVector<f64>,
    local: Option<(DMatrix<f64>, DMatrix<f64>, DVector<f64>)>,
}

impl Normals {
    fn of(lin: &Linearized) -> Normals {
        Normals(
            lin.blocks
                .iter()
                .map(|blk| {
                    let jg_t = blk.jg.transpose();
                    let local = (blk.jb.ncols() > 0).then(|| {
                        let jb_t = blk.jb.transpose();
                        (&jb_t * &blk.jb, &jg_t * &blk.jb, -(&jb_t * &blk.r))
                    });
                    BlockNormals { n_gg: &jg_t * &blk.jg, a_g: -(&jg_t * &blk.r), local }
                })
                .collect(),
        )
    }
}

/// The damped step, or None where the damped system is not positive definite. The globals
/// flagged in `held` do not move (their rows of the reduced system are set aside).
fn step(normals: &Normals, ng: usize, lambda: f64, held: &[bool]) -> Option<Step> {
    let damp = |mut n: DMatrix<f64>| {
        let top = (0..n.nrows()).map(|i| n[(i, i)]).fold(0.0, f64::max).max(1e-300);
        for i in 0..n.nrows() {
            n[(i, i)] += lambda * n[(i, i)].max(1e-12 * top);
        }
        n
    };
    let mut schur = DMatrix::<f64>::zeros(ng, ng);
    let mut rhs = DVector::<f64>::zeros(ng);
    let mut parts = Vec::with_capacity(normals.0.len());
    for blk in &normals.0 {
        schur += &blk.n_gg;
        rhs += &blk.a_g;
        let Some((n_ss, n_gs, a_s)) = &blk.local else {
            parts.push(None);
            continue;
        };
        let chol = damp(n_ss.clone()).cholesky()?;
        let x = chol.solve(&n_gs.transpose());
        let y = chol.solve(a_s);
        schur -= n_gs * &x;
        rhs -= n_gs * &y;
        parts.push(Some((x, y)));
    }
    for (i, _) in held.iter().enumerate().filter(|(_, h)| **h) {
        schur.row_mut(i).fill(0.0);
        schur.column_mut(i).fill(0.0);
        schur[(i, i)] = 1.0;
        rhs[i] = 0.0;
    }
    let (dg, schur_inv) = if ng > 0 {
        let chol = damp(schur).cholesky()?;
        (chol.solve(&rhs), chol.inverse())
    } else {
        (DVector::zeros(0), DMatrix::zeros(0, 0))
    };
    let db = parts
        .into_iter()
        .map(|p| match p {
            Some((x, y)) => y - x * &dg,
            None => DVector::zeros(0),
        })
        .collect();
    Some(Step { dg, db, schur_inverse: schur_inv })
}

/// The globals at a bound of [`BlockProblem::project_global`]'s box that the step `dg` would
/// take out of it.
fn held_at_bounds(p: &dyn BlockProblem, g: &[f64], dg: &DVector<f64>) -> Vec<bool> {
    let mut g_t: Vec<f64> = g.iter().zip(dg.iter()).map(|(a, d)| a + d).collect();
    p.project_global(&mut g_t);
    g_t.iter().zip(g).zip(dg.iter()).map(|((t, g), d)| *d != 0.0 && t == g).collect()
}

/// The globals that [`BlockProblem::project_global`]'s box pins where they are (a box of one
/// point): the residuals do not depend on them.
fn pinned(p: &dyn BlockProblem, g: &[f64]) -> Vec<bool> {
    (0..g.len())
        .map(|i| {
            [1.0, -1.0].iter().all(|d| {
                let mut moved = g.to_vec();
                moved[i] += d;
                p.project_global(&mut moved);
                moved[i] == g[i]
            })
        })
        .collect()
}

/// Broyden's update of each block's Jacobian to the secant of the trial step `(dg, db)` with
/// residuals `r_t`: `J += (dr - J dx) dx^T / |dx|^2`, block `s` seeing `dx = (dg, db_s)`.
fn secant_update(lin: &mut Linearized, dg: &DVector<f64>, db: &[DVector<f64>], r_t: &[Vec<f64>]) {
    for ((blk, db_s), r_s) in lin.blocks.iter_mut().zip(db).zip(r_t) {
        let norm2 = dg.norm_squared() + db_s.norm_squared();
        // A block without locals has `db_s` and `jb` both empty.
        if norm2.is_nan() || norm2 <= 0.0 || r_s.len() != blk.r.len() {
            continue;
        }
        let predicted = &blk.jg * dg + &blk.jb * db_s;
        let u = (DVector::from_column_slice(r_s) - &blk.r - predicted) / norm2;
        blk.jg += &u * dg.transpose();
        blk.jb += &u * db_s.transpose();
    }
}

/// Minimizes the sum of squared residuals from `(global, local)`. `on_iteration(k, cost)`
/// reports progress; `cancel` stops the solver between evaluations.
pub fn solve(
    p: &dyn BlockProblem,
    global: Vec<f64>,
    local: Vec<Vec<f64>>,
    opts: &LmOptions,
    on_iteration: &mut dyn FnMut(usize, f64),
    cancel: &AtomicBool,
) -> Result<LmSolution, LmError> {
    let (cost, res) = evaluate(p, &global, &local).ok_or(LmError::BadStart)?;
    let mut s = Solver {
        p,
        opts,
        residual_count: res.iter().map(Vec::len).sum(),
        g: global,
        b: local,
        cost,
        res,
        lambda: opts.lambda0,
        iterations: 0,
        cov: None,
        current: None,
        fresh_jacobians: 0,
        cheap: true,
    };
    let max_steps = opts.max_iterations * (1 + opts.secant_steps);
    while s.iterations < max_steps {
        if cancel.load(Ordering::Relaxed) {
            return Err(LmError::Cancelled);
        }
        let Some((lin, secants)) = s.linearization() else { break };
        s.iterations += 1;
        if s.iterate(lin, secants, on_iteration, cancel)? == Flow::Stop {
            break;
        }
    }
    Ok(s.finish())
}

/// The solver's state between iterations.
struct Solver<'p> {
    p: &'p dyn BlockProblem,
    opts: &'p LmOptions,
    g: Vec<f64>,
    b: Vec<Vec<f64>>,
    cost: f64,
    res: Vec<Vec<f64>>,
    residual_count: usize,
    lambda: f64,
    iterations: usize,
    /// The last step's Schur complement inverse (the covariance, unscaled and damped).
    cov: Option<DMatrix<f64>>,
    /// The current linearization, and the secant steps taken on it since it was fresh.
    current: Option<(Linearized, usize)>,
    fresh_jacobians: usize,
    /// Jacobians of the cheaper columns while they lead somewhere, exact ones from where one
    /// stalls: the fit stops where the exact gradient vanishes (with large residuals, a few
    /// percent off in the Jacobian moves that point).
    cheap: bool,
}

/// What an iteration leaves the solver to do: go on, or stop where it is.
#[derive(PartialEq)]
enum Flow {
    Next,
    Stop,
}

impl Solver<'_> {
    /// The linearization to step from: the current one while secant steps go on, else a fresh
    /// Jacobian (exact where the cheaper columns cannot be had); None where none is left.
    fn linearization(&mut self) -> Option<(Linearized, usize)> {
        if let Some(c) = self.current.take() {
            return Some(c);
        }
        if self.fresh_jacobians == self.opts.max_iterations {
            return None;
        }
        self.fresh_jacobians += 1;
        let (p, g, b) = (self.p, &self.g, &self.b);
        let lin = match linearize(p, g, b, self.res.clone(), self.cost, self.cheap) {
            Some(lin) => lin,
            None if self.cheap => {
                self.cheap = false;
                linearize(p, g, b, self.res.clone(), self.cost, false)?
            }
            None => return None,
        };
        self.cheap &= lin.cheap;
        Some((lin, 0))
    }

    /// Steps from `lin`, the damping raised until one lowers the cost (a secant
    /// linearization that fails is refreshed before the damping grows).
    fn iterate(
        &mut self,
        lin: Linearized,
        secants: usize,
        on_iteration: &mut dyn FnMut(usize, f64),
        cancel: &AtomicBool,
    ) -> Result<Flow, LmError> {
        let fresh = secants == 0;
        let normals = Normals::of(&lin);
        loop {
            if cancel.load(Ordering::Relaxed) {
                return Err(LmError::Cancelled);
            }
            let Some(Step { dg, db, schur_inverse }) =
                bounded_step(self.p, &normals, self.lambda, &self.g)
            else {
                self.lambda *= 10.0;
                if self.lambda > 1e16 {
                    return Ok(self.damped_out(&lin));
                }
                continue;
            };
            self.cov = Some(schur_inverse);
            let (g_t, dg, b_t) = trial(self.p, &self.g, &self.b, &dg, &db);
            match evaluate(self.p, &g_t, &b_t) {
                Some((c_t, r_t)) if c_t < lin.cost => {
                    let accepted = Accepted { g: g_t, b: b_t, dg, db, cost: c_t, res: r_t };
                    return Ok(self.accept(lin, secants, accepted, on_iteration));
                }
                _ if !fresh => return Ok(Flow::Next),
                _ => {
                    self.lambda *= 4.0;
                    if self.lambda > 1e16 {
                        return Ok(self.damped_out(&lin));
                    }
                }
            }
        }
    }

    /// No damping helps: from the cheaper columns, exact ones next (where the fit should end
    /// where the exact gradient vanishes); else the end.
    fn damped_out(&mut self, lin: &Linearized) -> Flow {
        if lin.cheap && self.opts.exact_finish {
            (self.cheap, self.lambda) = (false, self.opts.lambda0);
            Flow::Next
        } else {
            Flow::Stop
        }
    }

    /// A step that lowered the cost taken: the linearization moved to it (Broyden's update
    /// where secant steps are allowed), and whether the gain says the fit is done.
    fn accept(
        &mut self,
        mut lin: Linearized,
        secants: usize,
        t: Accepted,
        on_iteration: &mut dyn FnMut(usize, f64),
    ) -> Flow {
        let gain = (lin.cost - t.cost) / lin.cost.max(1e-300);
        if self.opts.secant_steps > 0 {
            secant_update(&mut lin, &t.dg, &t.db, &t.res);
        }
        for (blk, r) in lin.blocks.iter_mut().zip(&t.res) {
            blk.r = DVector::from_column_slice(r);
        }
        lin.cost = t.cost;
        (self.g, self.b, self.cost, self.res) = (t.g, t.b, t.cost, t.res);
        self.lambda = (self.lambda / 3.0).max(1e-12);
        on_iteration(self.iterations, self.cost);
        let fresh = secants == 0;
        if gain < self.opts.rel_tol {
            if fresh && lin.cheap && self.opts.exact_finish {
                self.cheap = false;
                return Flow::Next;
            }
            // A secant Jacobian's small gain may be its own staleness.
            return if fresh { Flow::Stop } else { Flow::Next };
        }
        if secants < self.opts.secant_steps {
            self.current = Some((lin, secants + 1));
        }
        Flow::Next
    }

    /// The solution, with the covariance at it undamped (the last damped one where that
    /// fails).
    fn finish(self) -> LmSolution {
        let Solver { p, opts, g, b, cost, res, mut cov, .. } = self;
        let ng = p.global_count();
        if !opts.covariance {
            cov = None;
        } else if let Some(lin) = linearize(p, &g, &b, res, cost, false)
            && let Some(step) = step(&Normals::of(&lin), ng, 0.0, &pinned(p, &g))
        {
            cov = Some(step.schur_inverse);
        }
        LmSolution {
            global: g,
            local: b,
            cost,
            residual_count: self.residual_count,
            iterations: self.iterations,
            global_cov_unscaled: cov.filter(|c| c.nrows() > 0),
        }
    }
}

/// A trial point that lowered the cost: the globals and locals, the step that reached them,
/// its cost and residuals.
struct Accepted {
    g: Vec<f64>,
    b: Vec<Vec<f64>>,
    dg: DVector<f64>,
    db: Vec<DVector<f64>>,
    cost: f64,
    res: Vec<Vec<f64>>,
}

/// The damped step from `lin`; a bounded global at its bound whose step points out of the box
/// is held there and the step solved again for the rest (an active set): projected alone, the
/// others would move as if it had moved.
fn bounded_step(p: &dyn BlockProblem, normals: &Normals, lambda: f64, g: &[f64]) -> Option<Step> {
    let ng = p.global_count();
    let free = step(normals, ng, lambda, &[]);
    let held = free.as_ref().map(|s| held_at_bounds(p, g, &s.dg));
    match held.filter(|h| h.contains(&true)) {
        Some(held) => step(normals, ng, lambda, &held),
        None => free,
    }
}

/// The point the step `(dg, db)` reaches from `(g, b)`, the globals projected into their box,
/// and the globals' step as projected.
fn trial(
    p: &dyn BlockProblem,
    g: &[f64],
    b: &[Vec<f64>],
    dg: &DVector<f64>,
    db: &[DVector<f64>],
) -> (Vec<f64>, DVector<f64>, Vec<Vec<f64>>) {
    let mut g_t: Vec<f64> = g.iter().zip(dg.iter()).map(|(a, d)| a + d).collect();
    p.project_global(&mut g_t);
    let dg = DVector::from_iterator(p.global_count(), g_t.iter().zip(g).map(|(a, b)| a - b));
    let b_t: Vec<Vec<f64>> = b
        .iter()
        .zip(db)
        .map(|(bs, d)| bs.iter().zip(d.iter()).map(|(a, d)| a + d).collect())
        .collect();
    (g_t, dg, b_t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rosenbrock as residuals: no blocks.
    struct Rosenbrock;
    impl BlockProblem for Rosenbrock {
        fn global_count(&self) -> usize {
            2
        }
        fn block_count(&self) -> usize {
            1
        }
        fn block_size(&self) -> usize {
            0
        }
        fn residuals(&self, _: usize, g: &[f64], _: &[f64]) -> Option<Vec<f64>> {
            Some(vec![10.0 * (g[1] - g[0] * g[0]), 1.0 - g[0]])
        }
        fn global_step(&self, _: usize, v: f64) -> f64 {
            1e-7 * v.abs().max(1.0)
        }
        fn local_step(&self, _: usize, _: f64) -> f64 {
            unreachable!()
        }
    }

    #[test]
    fn minimizes_rosenbrock() {
        let opts = LmOptions { max_iterations: 200, rel_tol: 1e-14, ..LmOptions::default() };
        let sol = solve(
            &Rosenbrock,
            vec![-1.2, 1.0],
            vec![vec![]],
            &opts,
            &mut |_, _| {},
            &AtomicBool::new(false),
        )
        .unwrap();
        assert!(
            (sol.global[0] - 1.0).abs() < 1e-5 && (sol.global[1] - 1.0).abs() < 1e-5,
            "{:?}",
            sol.global
        );
        assert!(sol.cost < 1e-10);
    }

    /// Decays `a_s exp(-k t) + c_s` sharing the rate `k`: an arrowhead problem with a known
    /// answer and a covariance to check.
    struct Decays {
        t: Vec<f64>,
        data: Vec<Vec<f64>>,
    }
    impl BlockProblem for Decays {
        fn global_count(&self) -> usize {
            1
        }
        fn block_count(&self) -> usize {
            self.data.len()
        }
        fn block_size(&self) -> usize {
            2
        }
        fn residuals(&self, s: usize, g: &[f64], b: &[f64]) -> Option<Vec<f64>> {
            Some(
                self.t
                    .iter()
                    .zip(&self.data[s])
                    .map(|(t, y)| b[0] * (-g[0] * t).exp() + b[1] - y)
                    .collect(),
            )
        }
        fn global_step(&self, _: usize, v: f64) -> f64 {
            1e-7 * v.abs().max(1e-3)
        }
        fn local_step(&self, _: usize, v: f64) -> f64 {
            1e-7 * v.abs().max(1e-3)
        }
    }

    #[test]
    fn fits_shared_and_local_parameters() {
        let mut rng = crate::recording::rng::Rng::new(11);
        let t: Vec<f64> = (0..50).map(|i| i as f64 * 0.1).collect();
        let truth = [(2.0, 0.5), (-1.0, 0.2), (3.0, -0.4), (1.5, 0.0)];
        let noise = 0.01;
        let data = truth
            .iter()
            .map(|(a, c)| {
                t.iter().map(|t| a * (-0.7 * t).exp() + c + noise * rng.normal()).collect()
            })
            .collect();
        let p = Decays { t, data };
        let start = vec![vec![1.0, 0.0]; 4];
        let sol = solve(
            &p,
            vec![0.3],
            start,
            &LmOptions::default(),
            &mut |_, _| {},
            &AtomicBool::new(false),
        )
        .unwrap();
        let sigma2 = sol.cost / (sol.residual_count - 9) as f64;
        let k_sigma = (sigma2 * sol.global_cov_unscaled.as_ref().unwrap()[(0, 0)]).sqrt();
        assert!((sol.global[0] - 0.7).abs() < 4.0 * k_sigma, "k = {} +- {k_sigma}", sol.global[0]);
        assert!(k_sigma > 1e-4 && k_sigma < 0.02, "k sigma {k_sigma}");
        assert!((sigma2.sqrt() - noise).abs() < 0.2 * noise);
        for (b, (a, c)) in sol.local.iter().zip(truth) {
            assert!((b[0] - a).abs() < 0.05 && (b[1] - c).abs() < 0.05, "{b:?} vs {a}, {c}");
        }
    }

    /// A decay fitted to data of another shape (large residuals), its columns optionally by a
    /// "cheaper scheme": the model with its rate 10% off, differenced against its own residuals.
    struct Skewed {
        t: Vec<f64>,
        data: Vec<f64>,
        offers_cheap: bool,
    }
    impl Skewed {
        fn residuals_at(&self, k: f64, a: f64) -> Vec<f64> {
            self.t.iter().zip(&self.data).map(|(t, y)| a * (-k * t).exp() - y).collect()
        }
    }
    impl BlockProblem for Skewed {
        fn global_count(&self) -> usize {
            2
        }
        fn block_count(&self) -> usize {
            1
        }
        fn block_size(&self) -> usize {
            0
        }
        fn residuals(&self, _: usize, g: &[f64], _: &[f64]) -> Option<Vec<f64>> {
            Some(self.residuals_at(g[0], g[1]))
        }
        fn global_step(&self, _: usize, v: f64) -> f64 {
            1e-7 * v.abs().max(1e-3)
        }
        fn local_step(&self, _: usize, _: f64) -> f64 {
            0.0
        }
        fn at_point(&self, _: usize, g: &[f64], _: &[f64], cheap: bool) -> Option<AtPoint> {
            let column_base =
                (cheap && self.offers_cheap).then(|| self.residuals_at(1.1 * g[0], g[1]));
            Some(AtPoint { column_base, ..AtPoint::default() })
        }
        fn column_residuals(
            &self,
            _: usize,
            g: &[f64],
            _: &[f64],
            at: &AtPoint,
        ) -> Option<Vec<f64>> {
            let k = if at.column_base.is_some() { 1.1 * g[0] } else { g[0] };
            Some(self.residuals_at(k, g[1]))
        }
    }

    #[test]
    fn cheaper_columns_finish_on_exact_ones_where_the_fit_stops() {
        let t: Vec<f64> = (0..60).map(|i| i as f64 * 0.1).collect();
        let data = t.iter().map(|t| 2.0 * (-0.7 * t).exp() + 0.3 * (3.0 * t).sin()).collect();
        let mut p = Skewed { t, data, offers_cheap: false };
        let fit = |p: &Skewed, exact_finish: bool| {
            let opts = LmOptions {
                max_iterations: 100,
                rel_tol: 1e-12,
                exact_finish,
                ..LmOptions::default()
            };
            solve(p, vec![0.3, 1.0], vec![vec![]], &opts, &mut |_, _| {}, &AtomicBool::new(false))
                .unwrap()
                .global
        };
        let exact = fit(&p, true);
        p.offers_cheap = true;
        let finished = fit(&p, true);
        let cheap_only = fit(&p, false);
        let apart =
            |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        // On the cheaper columns alone the fit stops where their gradient vanishes, not the
        // exact one's; finished on exact columns, where the exact fit stops.
        assert!(apart(&cheap_only, &exact) > 2e-4, "{cheap_only:?} vs {exact:?}");
        assert!(apart(&finished, &exact) < 1e-7, "{finished:?} vs {exact:?}");
    }

    /// Counts the evaluations of a problem.
    struct Counted<'a, P: BlockProblem>(&'a P, std::sync::atomic::AtomicUsize);
    impl<P: BlockProblem> BlockProblem for Counted<'_, P> {
        fn global_count(&self) -> usize {
            self.0.global_count()
        }
        fn block_count(&self) -> usize {
            self.0.block_count()
        }
        fn block_size(&self) -> usize {
            self.0.block_size()
        }
        fn residuals(&self, s: usize, g: &[f64], b: &[f64]) -> Option<Vec<f64>> {
            self.1.fetch_add(1, Ordering::Relaxed);
            self.0.residuals(s, g, b)
        }
        fn global_step(&self, i: usize, v: f64) -> f64 {
            self.0.global_step(i, v)
        }
        fn local_step(&self, i: usize, v: f64) -> f64 {
            self.0.local_step(i, v)
        }
    }

    #[test]
    fn secant_steps_reach_the_same_minimum_with_fewer_evaluations() {
        let cancel = AtomicBool::new(false);
        let run = |secant_steps: usize| {
            let p = Counted(&Rosenbrock, Default::default());
            let opts = LmOptions {
                max_iterations: 200,
                rel_tol: 1e-12,
                covariance: false,
                secant_steps,
                ..LmOptions::default()
            };
            let sol =
                solve(&p, vec![-1.2, 1.0], vec![vec![]], &opts, &mut |_, _| {}, &cancel).unwrap();
            (sol, p.1.load(Ordering::Relaxed))
        };
        let (fresh, fresh_evals) = run(0);
        let (secant, secant_evals) = run(3);
        for sol in [&fresh, &secant] {
            assert!((sol.global[0] - 1.0).abs() < 1e-5 && (sol.global[1] - 1.0).abs() < 1e-5);
        }
        // Secant steps come between fresh Jacobians, not instead of the last one.
        assert!(secant.iterations > 0 && secant.cost < 1e-10, "{}", secant.cost);
        assert!(secant_evals < fresh_evals, "{secant_evals} evaluations against {fresh_evals}");
    }

    /// `(x - 2, 10 (y - x))` with `x <= 1`: the box's minimum is `(1, 1)`.
    struct Bounded;
    impl BlockProblem for Bounded {
        fn global_count(&self) -> usize {
            2
        }
        fn block_count(&self) -> usize {
            1
        }
        fn block_size(&self) -> usize {
            0
        }
        fn residuals(&self, _: usize, g: &[f64], _: &[f64]) -> Option<Vec<f64>> {
            Some(vec![g[0] - 2.0, 10.0 * (g[1] - g[0])])
        }
        fn global_step(&self, _: usize, _: f64) -> f64 {
            1e-7
        }
        fn local_step(&self, _: usize, _: f64) -> f64 {
            0.0
        }
        fn project_global(&self, g: &mut [f64]) {
            g[0] = g[0].min(1.0);
        }
    }

    #[test]
    fn a_global_at_its_bound_is_held_and_the_rest_solved_for() {
        // From x at its bound, the free step goes to (2, 2), projected (1, 2): no better than
        // the start. Held at x = 1, the step solves y alone and lands on the minimum.
        let opts = LmOptions { max_iterations: 1, lambda0: 1e-9, ..LmOptions::default() };
        let sol = solve(
            &Bounded,
            vec![1.0, 0.0],
            vec![vec![]],
            &opts,
            &mut |_, _| {},
            &AtomicBool::new(false),
        )
        .unwrap();
        assert_eq!(sol.global[0], 1.0);
        assert!((sol.global[1] - 1.0).abs() < 1e-6, "{:?}", sol.global);
        assert!((sol.cost - 1.0).abs() < 1e-9, "{}", sol.cost);
    }

    /// `(x - 2, x)` with `y` pinned at 0 by its box and seen by no residual.
    struct Pinned;
    impl BlockProblem for Pinned {
        fn global_count(&self) -> usize {
            2
        }
        fn block_count(&self) -> usize {
            1
        }
        fn block_size(&self) -> usize {
            0
        }
        fn residuals(&self, _: usize, g: &[f64], _: &[f64]) -> Option<Vec<f64>> {
            Some(vec![g[0] - 2.0, g[0]])
        }
        fn global_step(&self, _: usize, _: f64) -> f64 {
            1e-7
        }
        fn local_step(&self, _: usize, _: f64) -> f64 {
            0.0
        }
        fn project_global(&self, g: &mut [f64]) {
            g[1] = 0.0;
        }
    }

    #[test]
    fn a_pinned_global_leaves_the_undamped_covariance_of_the_rest() {
        let opts = LmOptions { rel_tol: 1e-12, ..LmOptions::default() };
        let sol = solve(
            &Pinned,
            vec![0.0, 0.0],
            vec![vec![]],
            &opts,
            &mut |_, _| {},
            &AtomicBool::new(false),
        )
        .unwrap();
        assert!((sol.global[0] - 1.0).abs() < 1e-6 && sol.global[1] == 0.0, "{:?}", sol.global);
        // (J^T J)^-1 = 1/2 for x, undamped: the damped fallback would be 1 / (2 (1 + lambda)).
        let cov = sol.global_cov_unscaled.expect("a covariance");
        assert!((cov[(0, 0)] - 0.5).abs() < 1e-9, "{}", cov[(0, 0)]);
    }

    #[test]
    fn the_covariance_only_when_asked_for() {
        let cancel = AtomicBool::new(false);
        let at = |covariance: bool| {
            let opts = LmOptions {
                max_iterations: 200,
                rel_tol: 1e-14,
                covariance,
                ..LmOptions::default()
            };
            solve(&Rosenbrock, vec![-1.2, 1.0], vec![vec![]], &opts, &mut |_, _| {}, &cancel)
                .unwrap()
        };
        let (with, without) = (at(true), at(false));
        assert!(with.global_cov_unscaled.is_some_and(|c| c.nrows() == 2));
        assert!(without.global_cov_unscaled.is_none());
        assert_eq!(with.global, without.global, "the same solution either way");
        assert!(without.global_sigma(0, 2, &[1.0, 1.0]).is_infinite());
    }

    #[test]
    fn stops_when_cancelled() {
        let cancel = AtomicBool::new(true);
        let r = solve(
            &Rosenbrock,
            vec![-1.2, 1.0],
            vec![vec![]],
            &LmOptions::default(),
            &mut |_, _| {},
            &cancel,
        );
        assert_eq!(r.unwrap_err(), LmError::Cancelled);
    }
}
