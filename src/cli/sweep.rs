//! `ringlab sweep`: the drag grid, classified run by run.

use super::case_args::CaseArgs;
use super::progress::{COUNT_TEMPLATE, LateBar, with_threads};
use super::shard::{Shard, read_tables, write_table};
use anyhow::{Context, Result, bail};
use clap::Args;
use ringlab::analysis::sweep::{Axis, CSV_COLUMNS, grid, run_sweep_points, write_csv};
use ringlab::physics::RunOptions;
use ringlab::physics::integrator::Tolerances;
use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Args, Debug)]
pub struct SweepArgs {
    #[command(flatten)]
    pub case: CaseArgs,
    /// Grid points per coefficient
    #[arg(long, default_value_t = 32)]
    pub n: usize,
    /// Range of C1 as LO,HI (log-spaced)
    #[arg(long, value_name = "LO,HI", default_value = "0.005,0.5")]
    pub c1_range: String,
    /// Range of C2 as LO,HI
    #[arg(long, value_name = "LO,HI", default_value = "0.005,0.5")]
    pub c2_range: String,
    /// Range of C3 as LO,HI
    #[arg(long, value_name = "LO,HI", default_value = "0.005,0.5")]
    pub c3_range: String,
    /// Relative tolerance of each run (the sweep's default is coarser than a single run's)
    #[arg(long = "sweep-rtol", default_value_t = 1e-8)]
    pub sweep_rtol: f64,
    /// Threads (default: all cores)
    #[arg(long)]
    pub threads: Option<usize>,
    /// Run only every N-th grid point from the I-th (I from 0, C1 slowest), e.g. `--shard
    /// $SLURM_ARRAY_TASK_ID/N` in a Slurm job array; join the tables with --merge
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Join shard tables into --out (sorted as the grid; a missing or repeated point is an error)
    #[arg(long, value_name = "TABLE.csv", num_args = 1.., conflicts_with = "shard")]
    pub merge: Vec<PathBuf>,
    /// Output CSV
    #[arg(long, value_name = "FILE.csv")]
    pub out: PathBuf,
}

pub fn parse_range(s: &str, flag: &str) -> Result<(f64, f64)> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 2 {
        bail!("{flag} '{s}': expected LO,HI");
    }
    let lo: f64 =
        parts[0].trim().parse().with_context(|| format!("{flag} '{s}': LO is not a number"))?;
    let hi: f64 =
        parts[1].trim().parse().with_context(|| format!("{flag} '{s}': HI is not a number"))?;
    Ok((lo, hi))
}

pub fn run(args: &SweepArgs) -> Result<()> {
    if !args.merge.is_empty() {
        return merge(&args.merge, &args.out);
    }
    let shard = args.shard.as_deref().map(Shard::parse).transpose()?;
    let case = args.case.case()?;
    if !(args.sweep_rtol > 0.0 && args.sweep_rtol < 1.0) {
        bail!("--sweep-rtol = {}: must lie in (0, 1)", args.sweep_rtol);
    }
    let mut axes = Vec::new();
    for (s, flag) in [
        (&args.c1_range, "--c1-range"),
        (&args.c2_range, "--c2-range"),
        (&args.c3_range, "--c3-range"),
    ] {
        let (lo, hi) = parse_range(s, flag)?;
        let axis = Axis { lo, hi, n: args.n, log: true };
        axis.validate(flag).map_err(anyhow::Error::msg)?;
        axes.push(axis);
    }
    let axes = [axes[0], axes[1], axes[2]];
    let opts =
        RunOptions { tol: Tolerances { rtol: args.sweep_rtol, atol: 1e-10 }, ..case.opts.clone() };
    let all = grid(axes);
    let indices = Shard::pick(shard, &(0..all.len()).collect::<Vec<_>>());
    let points: Vec<[f64; 3]> = indices.iter().map(|&i| all[i]).collect();
    let total = points.len();
    let clock = Instant::now();
    let bar = LateBar::new(COUNT_TEMPLATE);
    let (rows, threads) = with_threads(args.threads, || {
        let rows = run_sweep_points(&case.model, &case.initial, &opts, &points, &|done| {
            bar.update(done as u64, total as u64, "runs".into())
        });
        (rows, rayon::current_num_threads())
    })?;
    bar.finish();
    let secs = clock.elapsed().as_secs_f64();
    let file = std::fs::File::create(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let mut w = std::io::BufWriter::new(file);
    write_csv(&mut w, &rows, &indices, all.len())?;
    w.flush()?;
    let retro = rows.iter().filter(|r| r.retrograde_turn).count();
    println!(
        "{total} runs in {secs:.2} s on {} threads ({:.2} ms per run); {retro} make the retrograde turn; written to {}",
        threads,
        secs * 1e3 / total as f64,
        args.out.display()
    );
    Ok(())
}

/// Joins shard tables of one grid: rows in grid order, each point once, none missing.
fn merge(tables: &[PathBuf], out: &std::path::Path) -> Result<()> {
    let (header, rows) = read_tables(tables)?;
    if header.join(",") != CSV_COLUMNS {
        bail!(
            "{}: not a table of `ringlab sweep` (its columns are {})",
            tables[0].display(),
            header.join(",")
        );
    }
    let n = header.len();
    let whole = |r: &super::shard::TableRow, k: usize| -> Result<usize> {
        let cell = r.cells.get(k).map_or("", String::as_str);
        cell.parse().with_context(|| {
            format!(
                "{}:{}: {} = '{cell}' is not a whole number",
                r.file.display(),
                r.line,
                header[k]
            )
        })
    };
    let mut size = None;
    let mut keyed = Vec::with_capacity(rows.len());
    for r in &rows {
        let (index, this) = (whole(r, n - 2)?, whole(r, n - 1)?);
        match size {
            None => size = Some((this, r)),
            Some((s, first)) if s != this => bail!(
                "{}:{} is from a grid of {this} points, {}:{} from one of {s}: tables of different sweeps",
                r.file.display(),
                r.line,
                first.file.display(),
                first.line
            ),
            _ => {}
        }
        if index >= this {
            bail!(
                "{}:{}: grid_index {index} is not below grid_size {this}",
                r.file.display(),
                r.line
            );
        }
        keyed.push((index, r));
    }
    keyed.sort_by_key(|(i, _)| *i);
    for w in keyed.windows(2) {
        if w[0].0 == w[1].0 {
            let (a, b) = (w[0].1, w[1].1);
            bail!(
                "grid point {} is in two tables: {}:{} and {}:{}",
                w[0].0,
                a.file.display(),
                a.line,
                b.file.display(),
                b.line
            );
        }
    }
    let size = size.map_or(0, |s| s.0);
    if keyed.len() != size {
        let missing =
            (0..size).find(|i| keyed.binary_search_by_key(i, |(k, _)| *k).is_err()).unwrap_or(0);
        bail!(
            "the tables hold {} of the {size} points of their grid (point {missing} is missing): is a shard missing?",
            keyed.len()
        );
    }
    let sorted: Vec<_> = keyed.iter().map(|(_, r)| *r).collect();
    write_table(out, &header, &sorted)?;
    println!("{} runs from {} tables written to {}", sorted.len(), tables.len(), out.display());
    Ok(())
}
