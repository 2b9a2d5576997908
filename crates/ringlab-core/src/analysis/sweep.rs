//! The drag sweep: runs on a grid of `(C1, C2, C3)` in parallel (rayon), each classified by
//! its motion. This is the paper's search for "all orbits that resemble the experiment" and
//! the coarse stage of the fit.

use crate::physics::motion::analyze;
use crate::physics::{EndReason, Initial, Model, RunOptions, Sample, Simulation};
use rayon::prelude::*;
use serde::Serialize;
use std::io::{self, Write};
use std::sync::atomic::{AtomicUsize, Ordering};

/// One axis of the grid: `n` values from `lo` to `hi`, log-spaced (all positive) or linear.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis {
    pub lo: f64,
    pub hi: f64,
    pub n: usize,
    pub log: bool,
}

impl Axis {
    pub fn values(&self) -> Vec<f64> {
        if self.n == 1 {
            return vec![self.lo];
        }
        (0..self.n)
            .map(|i| {
                let f = i as f64 / (self.n - 1) as f64;
                if self.log {
                    (self.lo.ln() + f * (self.hi.ln() - self.lo.ln())).exp()
                } else {
                    self.lo + f * (self.hi - self.lo)
                }
            })
            .collect()
    }

    pub fn validate(&self, name: &str) -> Result<(), String> {
        if self.n == 0 {
            return Err(format!("{name}: the grid needs at least one point"));
        }
        if !(self.lo.is_finite() && self.hi.is_finite()) || self.lo < 0.0 || self.hi < self.lo {
            return Err(format!(
                "{name}: range [{}, {}] must be finite with 0 <= lo <= hi",
                self.lo, self.hi
            ));
        }
        if self.log && self.lo <= 0.0 {
            return Err(format!("{name}: a logarithmic range must start above 0"));
        }
        Ok(())
    }
}

/// How one run of the sweep went.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SweepRow {
    pub c: [f64; 3],
    pub retrograde_turn: bool,
    pub inflection_time: Option<f64>,
    pub prograde_cycles: usize,
    pub cycles_before_retrograde: usize,
    pub end_reason: &'static str,
    pub t_end: f64,
    pub steps: u64,
}

/// The grid points of three axes, `C1` slowest.
pub fn grid(axes: [Axis; 3]) -> Vec<[f64; 3]> {
    let [a1, a2, a3] = axes.map(|a| a.values());
    let mut grid = Vec::with_capacity(a1.len() * a2.len() * a3.len());
    for &c1 in &a1 {
        for &c2 in &a2 {
            for &c3 in &a3 {
                grid.push([c1, c2, c3]);
            }
        }
    }
    grid
}

/// Evaluates `f` at every grid point in parallel (rayon), in grid order; `progress` is called
/// with the number of points done so far. The machinery of the sweep, shared with the fit.
pub fn grid_map<T: Send>(
    axes: [Axis; 3],
    f: &(dyn Fn([f64; 3]) -> T + Sync),
    progress: &(dyn Fn(usize) + Sync),
) -> Vec<T> {
    let done = AtomicUsize::new(0);
    grid(axes)
        .par_iter()
        .map(|&c| {
            let out = f(c);
            progress(done.fetch_add(1, Ordering::Relaxed) + 1);
            out
        })
        .collect()
}

/// Runs every grid point; `progress` is called with the number of runs done so far.
pub fn run_sweep(
    model: &Model,
    initial: &Initial,
    opts: &RunOptions,
    axes: [Axis; 3],
    progress: &(dyn Fn(usize) + Sync),
) -> Vec<SweepRow> {
    run_sweep_points(model, initial, opts, &grid(axes), progress)
}

/// Runs the given drag points (a shard of a grid) in parallel, in their order.
pub fn run_sweep_points(
    model: &Model,
    initial: &Initial,
    opts: &RunOptions,
    points: &[[f64; 3]],
    progress: &(dyn Fn(usize) + Sync),
) -> Vec<SweepRow> {
    let opts = RunOptions { sample_dt: None, track_validity: false, ..opts.clone() };
    let done = AtomicUsize::new(0);
    points
        .par_iter()
        .map(|&c| {
            let row = classify(model, initial, &opts, c);
            progress(done.fetch_add(1, Ordering::Relaxed) + 1);
            row
        })
        .collect()
}

/// One run with drag `c`, classified.
pub fn classify(model: &Model, initial: &Initial, opts: &RunOptions, c: [f64; 3]) -> SweepRow {
    let mut m = model.clone();
    m.c_drag = c;
    let start = Sample::new(&m, 0.0, &initial.to_state());
    match Simulation::new(m, initial, opts.clone()) {
        Ok(sim) => {
            let summary = sim.run(&mut |_| {});
            let motion = analyze(&start, &summary.turning_points, summary.t_end);
            SweepRow {
                c,
                retrograde_turn: motion.retrograde_turn,
                inflection_time: motion.inflection_time,
                prograde_cycles: motion.prograde_cycles,
                cycles_before_retrograde: motion.cycles_before_retrograde,
                end_reason: summary.end_reason.as_str(),
                t_end: summary.t_end,
                steps: summary.stats.steps,
            }
        }
        Err(_) => SweepRow {
            c,
            retrograde_turn: false,
            inflection_time: None,
            prograde_cycles: 0,
            cycles_before_retrograde: 0,
            end_reason: EndReason::NonFinite.as_str(),
            t_end: 0.0,
            steps: 0,
        },
    }
}

/// The sweep table's columns: a row's place in the grid (`grid_index` of `grid_size`, C1
/// slowest) lets shards of one grid be joined and checked complete.
pub const CSV_COLUMNS: &str = "c1,c2,c3,retrograde_turn,inflection_time,prograde_cycles,cycles_before_retrograde,end_reason,t_end,steps,grid_index,grid_size";

/// Writes rows with their grid indices (`indices[i]` is row `i`'s place in a grid of `grid_size`).
pub fn write_csv(
    out: &mut impl Write,
    rows: &[SweepRow],
    indices: &[usize],
    grid_size: usize,
) -> io::Result<()> {
    writeln!(out, "{CSV_COLUMNS}")?;
    for (r, index) in rows.iter().zip(indices) {
        writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{index},{grid_size}",
            r.c[0],
            r.c[1],
            r.c[2],
            r.retrograde_turn,
            r.inflection_time.map(|t| t.to_string()).unwrap_or_default(),
            r.prograde_cycles,
            r.cycles_before_retrograde,
            r.end_reason,
            r.t_end,
            r.steps
        )?;
    }
    Ok(())
}
