//! `ringlab simulate`: one run, written as CSV and summarised.

use super::case_args::CaseArgs;
use super::effect_args::EffectArgs;
use anyhow::{Context, Result};
use clap::Args;
use ringlab::physics::{Sample, Simulation};
use ringlab::report::{RunReport, analyze, write_samples_csv};
use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::time::Instant;

#[derive(Args, Debug)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub case: CaseArgs,
    #[command(flatten)]
    pub effects: EffectArgs,
    /// Write the samples as CSV to this file ('-' for standard output)
    #[arg(long, value_name = "FILE.csv")]
    pub out: Option<PathBuf>,
    /// Print the run's summary as one JSON object
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &SimulateArgs) -> Result<()> {
    let mut case = args.case.case()?;
    let effects = args.effects.apply_to(&mut case)?;
    let start = Sample::new(&case.model, 0.0, &case.initial.to_state());
    let clock = Instant::now();
    let sim = Simulation::new(case.model.clone(), &case.initial, case.opts.clone())?;
    let mut samples = Vec::new();
    let summary = sim.run(&mut |s| samples.push(*s));
    let motion = analyze(&start, &summary);
    let seconds = clock.elapsed().as_secs_f64();
    let mut report = RunReport::new(
        &case.name,
        case.units.label(),
        case.opts.mu,
        &start,
        &summary,
        &motion,
        seconds,
    );
    report.set_effects(&case.model.effects, &effects);

    if let Some(path) = &args.out {
        if path.as_os_str() == "-" {
            let stdout = std::io::stdout();
            let mut w = BufWriter::new(stdout.lock());
            write_samples_csv(&mut w, &samples).context("writing CSV to standard output")?;
            w.flush()?;
        } else {
            let file = std::fs::File::create(path)
                .with_context(|| format!("cannot create {}", path.display()))?;
            let mut w = BufWriter::new(file);
            write_samples_csv(&mut w, &samples)
                .with_context(|| format!("writing {}", path.display()))?;
            w.flush().with_context(|| format!("writing {}", path.display()))?;
        }
    }
    let to_stdout_csv = args.out.as_ref().is_some_and(|p| p.as_os_str() == "-");
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else if to_stdout_csv {
        eprint!("{}", report.human());
    } else {
        print!("{}", report.human());
    }
    Ok(())
}
