//! `ringlab sweep`: the drag grid, classified run by run.

use super::case_args::CaseArgs;
use anyhow::{Context, Result, bail};
use clap::Args;
use ringlab::analysis::sweep::{Axis, run_sweep, write_csv};
use ringlab::physics::integrator::Tolerances;
use ringlab::physics::RunOptions;
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
    /// Output CSV
    #[arg(long, value_name = "FILE.csv")]
    pub out: PathBuf,
}

pub fn parse_range(s: &str, flag: &str) -> Result<(f64, f64)> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 2 {
        bail!("{flag} '{s}': expected LO,HI");
    }
    let lo: f64 = parts[0].trim().parse().with_context(|| format!("{flag} '{s}': LO is not a number"))?;
    let hi: f64 = parts[1].trim().parse().with_context(|| format!("{flag} '{s}': HI is not a number"))?;
    Ok((lo, hi))
}

pub fn run(args: &SweepArgs) -> Result<()> {
    let case = args.case.case()?;
    if !(args.sweep_rtol > 0.0 && args.sweep_rtol < 1.0) {
        bail!("--sweep-rtol = {}: must lie in (0, 1)", args.sweep_rtol);
    }
    let mut axes = Vec::new();
    for (s, flag) in [(&args.c1_range, "--c1-range"), (&args.c2_range, "--c2-range"), (&args.c3_range, "--c3-range")] {
        let (lo, hi) = parse_range(s, flag)?;
        let axis = Axis { lo, hi, n: args.n, log: true };
        axis.validate(flag).map_err(anyhow::Error::msg)?;
        axes.push(axis);
    }
    let axes = [axes[0], axes[1], axes[2]];
    let pool = rayon::ThreadPoolBuilder::new().num_threads(args.threads.unwrap_or(0)).build()?;
    let opts = RunOptions { tol: Tolerances { rtol: args.sweep_rtol, atol: 1e-10 }, ..case.opts.clone() };
    let total = args.n.pow(3);
    let clock = Instant::now();
    let rows = pool.install(|| {
        run_sweep(&case.model, &case.initial, &opts, axes, &|done| {
            if done % 1024 == 0 || done == total {
                eprint!("\r{done}/{total} runs");
            }
        })
    });
    let secs = clock.elapsed().as_secs_f64();
    eprintln!();
    let file = std::fs::File::create(&args.out).with_context(|| format!("cannot create {}", args.out.display()))?;
    let mut w = std::io::BufWriter::new(file);
    write_csv(&mut w, &rows)?;
    w.flush()?;
    let retro = rows.iter().filter(|r| r.retrograde_turn).count();
    println!(
        "{total} runs in {secs:.2} s on {} threads ({:.2} ms per run); {retro} make the retrograde turn; written to {}",
        pool.current_num_threads(),
        secs * 1e3 / total as f64,
        args.out.display()
    );
    Ok(())
}
