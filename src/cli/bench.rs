//! `ringlab bench`: the speed figures of the physics core (`docs/speed.md`), measured on this
//! machine.

use super::bench_scipy::{self, ScipyFigures};
use super::case_args::CaseArgs;
use anyhow::Result;
use clap::Args;
use ringlab::analysis::sweep::{Axis, run_sweep};
use ringlab::physics::effects::apply;
use ringlab::physics::integrator::Tolerances;
use ringlab::physics::speed::{self, fastest, median};
use ringlab::physics::{EffectKind, Model, RunOptions, Sample};
use serde::Serialize;
use std::time::Instant;

#[derive(Args, Debug)]
pub struct BenchArgs {
    #[command(flatten)]
    pub case: CaseArgs,
    /// Repetitions of the single run (the median is reported)
    #[arg(long, default_value_t = 31)]
    pub repeats: usize,
    /// Grid points per coefficient in the sweep benchmark
    #[arg(long, default_value_t = 32)]
    pub sweep_n: usize,
    /// Threads for the sweep
    #[arg(long, default_value_t = 2)]
    pub threads: usize,
    /// Leave out the sweep (about half a minute)
    #[arg(long)]
    pub skip_sweep: bool,
    /// Leave out the cost of each effect beyond the paper's model (a few seconds)
    #[arg(long)]
    pub skip_effects: bool,
    /// Print the figures as JSON
    #[arg(long)]
    pub json: bool,
    /// Measure the recording side instead: reader (100,000 frames), recovery, fit of a recording
    #[arg(long)]
    pub recording: bool,
    /// The recording to fit with --recording (default: the repository's copy of the sample)
    #[arg(long, value_name = "FILE.csv", default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/sample-ring.csv"))]
    pub sample: std::path::PathBuf,
    /// Measure the tracking of a film instead: decoding and tracking, tracked again until
    /// 2,000 frames have passed, and the memory it held
    #[arg(long)]
    pub track: bool,
    /// The film for --track (default: the repository's cut of a shared film, 1280x1024)
    #[arg(long, value_name = "VIDEO", default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/video/colours-none-mid.mp4"))]
    pub film: std::path::PathBuf,
    /// With --recording: leave out the fit
    #[arg(long)]
    pub skip_fit: bool,
    /// Time scipy's DOP853 on the same run through this Python (it needs numpy and scipy) and
    /// print ringlab's speed-up over it
    #[arg(long, value_name = "PYTHON")]
    pub scipy: Option<std::path::PathBuf>,
    /// The reference script for --scipy
    #[arg(long, value_name = "FILE.py", default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/bench/scipy_vs_ringlab.py"))]
    pub scipy_script: std::path::PathBuf,
    /// With --scipy: scipy's solves (about 5 s each; the fastest is reported)
    #[arg(long, default_value_t = 1)]
    pub scipy_repeats: usize,
}

#[derive(Serialize, Debug)]
struct BenchReport {
    case: String,
    rhs_ns: f64,
    /// One sine and cosine of an angle ([`ringlab::physics::trig::sin_cos`]): two of them are
    /// the right-hand side's floor.
    sin_cos_ns: f64,
    run_to_rest_ms: f64,
    /// The fastest of the runs (the median is `run_to_rest_ms`).
    run_to_rest_fastest_ms: f64,
    run_to_rest_with_events_ms: f64,
    run_with_samples_ms: f64,
    run_t_end: f64,
    run_end_reason: &'static str,
    run_rhs_evaluations: u64,
    run_steps: u64,
    run_rejected_steps: u64,
    rtol: f64,
    atol: f64,
    sweep_runs: Option<usize>,
    sweep_seconds: Option<f64>,
    sweep_threads: usize,
    sweep_retrograde: Option<usize>,
    /// The run to the end with each effect on, same tolerances, no samples or validity.
    effects: Vec<EffectBench>,
    /// scipy's DOP853 on the same run (`--scipy`).
    scipy: Option<ScipyFigures>,
    /// scipy's wall time over ringlab's median, and fastest over fastest.
    scipy_ratio: Option<f64>,
    scipy_ratio_fastest: Option<f64>,
}

#[derive(Serialize, Debug)]
struct EffectBench {
    effect: &'static str,
    strength: f64,
    ms: f64,
    /// Time relative to the run without effects.
    cost_ratio: f64,
    rhs_evaluations: u64,
    /// Right-hand-side evaluations per unit of simulated time, relative to the run without
    /// effects (independent of the machine's load; the runs end at different times).
    evaluations_per_time_ratio: f64,
    steps: u64,
    t_end: f64,
    end_reason: &'static str,
    sliding_intervals: usize,
}

pub fn run(args: &BenchArgs) -> Result<()> {
    if args.track {
        return super::bench_track::run(&args.film, args.json);
    }
    if args.recording {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(args.threads).build()?;
        return pool.install(|| {
            super::bench_recording::run(&args.sample, args.repeats.min(7), args.skip_fit, args.json)
        });
    }
    let case = args.case.case()?;
    if args.scipy.is_some() {
        bench_scipy::check_paper_ring(&case)?;
    }
    let model = case.model.clone();
    let y0 = case.initial.to_state();

    // Right-hand side: evaluations on slightly varied states so nothing is hoisted.
    let rhs_ns = speed::rhs_ns(&model, &y0, 2_000_000);
    let sin_cos_ns = speed::sin_cos_ns(2_000_000);

    let tol = Tolerances { rtol: 1e-10, atol: 1e-12 };
    let bare = RunOptions { tol, sample_dt: None, track_validity: false, ..case.opts.clone() };
    let time_runs = |opts: &RunOptions| speed::time_runs(&model, &case.initial, opts, args.repeats);
    let (run_times, summary) = time_runs(&bare)?;
    let run_ms = median(&run_times);
    let (events, _) = time_runs(&RunOptions { track_validity: true, ..bare.clone() })?;
    let (samples, _) =
        time_runs(&RunOptions { track_validity: true, sample_dt: Some(case.dt), ..bare.clone() })?;

    let mut report = BenchReport {
        case: case.name.clone(),
        rhs_ns,
        sin_cos_ns,
        run_to_rest_ms: run_ms,
        run_to_rest_fastest_ms: fastest(&run_times),
        run_to_rest_with_events_ms: median(&events),
        run_with_samples_ms: median(&samples),
        run_t_end: summary.t_end,
        run_end_reason: summary.end_reason.as_str(),
        run_rhs_evaluations: summary.stats.rhs_evaluations,
        run_steps: summary.stats.steps,
        run_rejected_steps: summary.stats.rejected,
        rtol: tol.rtol,
        atol: tol.atol,
        sweep_runs: None,
        sweep_seconds: None,
        sweep_threads: args.threads,
        sweep_retrograde: None,
        effects: Vec::new(),
        scipy: None,
        scipy_ratio: None,
        scipy_ratio_fastest: None,
    };
    if let Some(python) = &args.scipy {
        let figures = bench_scipy::run(python, &args.scipy_script, args.scipy_repeats)?;
        report.scipy_ratio = Some(figures.seconds * 1e3 / run_ms);
        report.scipy_ratio_fastest = Some(figures.seconds * 1e3 / report.run_to_rest_fastest_ms);
        report.scipy = Some(figures);
    }
    if !args.skip_effects {
        // Each effect in the middle of its realistic range (geometric), slip at both ends.
        let start = Sample::new(&model, 0.0, &y0);
        let mut cases: Vec<(EffectKind, f64)> = Vec::new();
        for k in EffectKind::ALL.into_iter().filter(|k| k.is_physical()) {
            let (lo, hi) = k.realistic_range();
            if k == EffectKind::Slip {
                cases.push((k, hi));
                cases.push((k, lo));
            } else {
                cases.push((k, (lo * hi).sqrt()));
            }
        }
        let repeats = args.repeats.clamp(1, 11);
        for (kind, x) in cases {
            let mut m: Model = model.clone();
            apply(kind, x, m.body.r, start.reynolds, &mut m.effects)?;
            let (times, summary) = speed::time_runs(&m, &case.initial, &bare, repeats)?;
            let ms = median(&times);
            report.effects.push(EffectBench {
                effect: kind.name(),
                strength: x,
                ms,
                cost_ratio: ms / run_ms,
                rhs_evaluations: summary.stats.rhs_evaluations,
                evaluations_per_time_ratio: (summary.stats.rhs_evaluations as f64 / summary.t_end)
                    / (report.run_rhs_evaluations as f64 / report.run_t_end),
                steps: summary.stats.steps,
                t_end: summary.t_end,
                end_reason: summary.end_reason.as_str(),
                sliding_intervals: summary.sliding.len(),
            });
        }
    }
    if !args.skip_sweep {
        let axis = Axis { lo: 0.005, hi: 0.5, n: args.sweep_n, log: true };
        let opts = RunOptions { tol: Tolerances { rtol: 1e-8, atol: 1e-10 }, ..case.opts.clone() };
        let pool = rayon::ThreadPoolBuilder::new().num_threads(args.threads).build()?;
        let clock = Instant::now();
        let rows = pool.install(|| run_sweep(&model, &case.initial, &opts, [axis; 3], &|_| {}));
        report.sweep_seconds = Some(clock.elapsed().as_secs_f64());
        report.sweep_runs = Some(rows.len());
        report.sweep_retrograde = Some(rows.iter().filter(|r| r.retrograde_turn).count());
    }

    print_report(&report, args.repeats, case.dt, args.json)
}

fn print_report(report: &BenchReport, repeats: usize, dt: f64, json: bool) -> Result<()> {
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!("case {}", report.case);
        println!("right-hand side:                 {:.1} ns per evaluation", report.rhs_ns);
        println!(
            "  one sine and cosine:           {:.1} ns (two per evaluation)",
            report.sin_cos_ns
        );
        println!(
            "run to the end (rtol {:.0e}):     {:.2} ms median of {} ({} evaluations, {} steps + {} rejected, ended {} at t = {:.4})",
            report.rtol,
            report.run_to_rest_ms,
            repeats,
            report.run_rhs_evaluations,
            report.run_steps,
            report.run_rejected_steps,
            report.run_end_reason,
            report.run_t_end
        );
        println!("  fastest of the runs:           {:.2} ms", report.run_to_rest_fastest_ms);
        if let (Some(sp), Some(ratio), Some(ratio_fast)) =
            (&report.scipy, report.scipy_ratio, report.scipy_ratio_fastest)
        {
            println!(
                "scipy DOP853 (numpy right-hand side): {:.2} s ({:.2} s of CPU; fastest of {}), {} evaluations, ended at t = {:.4}",
                sp.seconds, sp.cpu_seconds, sp.repeats, sp.evaluations, sp.t_end
            );
            println!(
                "  ringlab is {ratio:.0} times faster (median run), {ratio_fast:.0} times (fastest run)"
            );
        }
        println!("  + turning points and validity: {:.2} ms", report.run_to_rest_with_events_ms);
        println!("  + samples every {}:         {:.2} ms", dt, report.run_with_samples_ms);
        for e in &report.effects {
            println!(
                "  with {:<18} {:<7.4}: {:>7.2} ms ({:>4.1}x; {} evaluations, {:.1}x per time unit, {} steps, ended {} at t = {:.3}{})",
                e.effect,
                e.strength,
                e.ms,
                e.cost_ratio,
                e.rhs_evaluations,
                e.evaluations_per_time_ratio,
                e.steps,
                e.end_reason,
                e.t_end,
                if e.effect == "slip" {
                    format!(", {} sliding intervals", e.sliding_intervals)
                } else {
                    String::new()
                }
            );
        }
        if let (Some(n), Some(s), Some(r)) =
            (report.sweep_runs, report.sweep_seconds, report.sweep_retrograde)
        {
            println!(
                "drag sweep {n} runs (rtol 1e-8): {s:.2} s on {} threads; {r} make the retrograde turn",
                report.sweep_threads
            );
        }
    }
    Ok(())
}
