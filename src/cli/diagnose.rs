//! `ringlab diagnose`: which physics the paper's model left out of a recording, if any. Its
//! flags are `diagnose_args.rs`, its JSON `analysis::json` (the core's); more than one file (or a table)
//! goes to `diagnose_batch.rs`.

use super::diagnose_args::{DiagnoseArgs, options};
use super::diagnose_report;
use super::progress::{LateBar, PERCENT_TEMPLATE, with_threads};
use anyhow::{Context, Result};
use ringlab::analysis::diagnose::{DiagnoseProgress, Diagnosis, Finding, diagnose};
use ringlab::analysis::json::DiagnoseJson;
use std::sync::atomic::AtomicBool;

pub fn run(args: &DiagnoseArgs) -> Result<()> {
    if !args.merge.is_empty() {
        return super::diagnose_batch::merge(
            &args.merge,
            args.table.as_deref().context("--merge needs --table")?,
        );
    }
    let opts = options(args)?;
    if args.files.len() > 1 || args.table.is_some() || args.shard.is_some() {
        return super::diagnose_batch::run(args, &opts);
    }
    let file = &args.files[0];
    let rec = super::import_args::load_one(&args.import, file)?;
    let bar = LateBar::new(PERCENT_TEMPLATE);
    let progress = |p: &DiagnoseProgress| {
        bar.update((p.fraction.clamp(0.0, 1.0) * 1000.0) as u64, 1000, p.message.clone())
    };
    let cancel = AtomicBool::new(false);
    let result = with_threads(args.threads, || diagnose(&rec, &opts, &progress, &cancel))?;
    bar.finish();
    let d = result.with_context(|| format!("diagnosing {}", file.display()))?;
    if let Some(dir) = &args.report {
        diagnose_report::write(dir, file, &rec, &d)
            .with_context(|| format!("writing the report into {}", dir.display()))?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&DiagnoseJson::new(&d))?);
        return Ok(());
    }
    print_summary(file, &d);
    if let Some(dir) = &args.report {
        println!("report: {}", dir.join("report.md").display());
    }
    Ok(())
}

fn print_summary(file: &std::path::Path, d: &Diagnosis) {
    println!(
        "{}: {} frames, {} fitted; pixel noise {:.3} px; {} glitch{} left out",
        file.display(),
        d.frames,
        d.frames_fitted,
        d.noise_px,
        d.glitches.len(),
        if d.glitches.len() == 1 { "" } else { "es" }
    );
    match &d.finding {
        Finding::Named(k) => {
            println!("left out: {}", k.iter().map(|k| k.name()).collect::<Vec<_>>().join(" + "))
        }
        Finding::Unexplained { partial: Some(p) } => {
            println!(
                "left out: unexplained ({p} explains {:.0}% of the excess, partially: it leaves {:.3} px beyond the noise)",
                100.0 * p.share,
                d.excess_px(p.rms_px)
            )
        }
        f => println!("left out: {}", f.name()),
    }
    match &d.mismatch {
        Some(m) => println!(
            "mismatch: {:.3} s to {:.3} s ({:.2} px rms, {:.0}% of the excess)",
            m.start_s,
            m.end_s,
            m.rms_px,
            100.0 * m.share
        ),
        None => println!("mismatch: none beyond the noise"),
    }
    println!(
        "misfit over the whole run: before {:.3} px, after {:.3} px (beyond the noise: {:.3} -> {:.3} px)",
        d.before.rms_px,
        d.after.rms_px,
        d.excess_px(d.before.rms_px),
        d.excess_px(d.after.rms_px)
    );
    println!("candidates (BIC, lower is better; baseline 0):");
    for c in &d.candidates {
        let strength =
            c.strength.map_or(String::new(), |(v, s)| format!("  strength {v:.5} +- {s:.5}"));
        match &c.error {
            Some(e) => println!("  {:<20} failed: {e}", c.effect.name()),
            None => {
                let stopped = c.stopped_note().map_or(String::new(), |n| format!("  ({n})"));
                println!(
                    "  {:<20} {:>9.3} px  {:>+10.1}  ({:.1} s){strength}{stopped}",
                    c.effect.name(),
                    c.rms_px,
                    c.delta_score,
                    c.seconds
                )
            }
        }
    }
    if !d.pairs.is_empty() {
        println!("pairs (forward selection; BIC against the baseline):");
        for p in &d.pairs {
            // One effect twice: a camera effect alone, fitted again through the camera the
            // segments see.
            let name = if p.first == p.second {
                format!("{} alone, again", p.first)
            } else {
                format!("{} + {}", p.first, p.second)
            };
            match &p.error {
                Some(e) => println!("  {name:<36} failed: {e}"),
                None => println!(
                    "  {name:<36} {:>9.3} px  {:>+10.1}  ({:.1} s)",
                    p.rms_px, p.delta_score, p.seconds
                ),
            }
        }
    }
    println!();
    println!("{}", d.explanation);
    let stages: Vec<String> =
        d.stage_seconds.iter().map(|(n, s)| format!("{n} {s:.1} s")).collect();
    println!("{:.1} s ({})", d.compute_seconds, stages.join(", "));
}
