//! `ringlab diagnose`'s flags, and the diagnosis's options from them (one file or a table of
//! many: `diagnose.rs` and `diagnose_batch.rs` both read them).

use anyhow::{Context, Result, bail};
use clap::Args;
use ringlab::analysis::diagnose::DiagnoseOptions;
use ringlab::physics::EffectKind;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct DiagnoseArgs {
    /// The recordings: format v1 or a tracker's file (see `ringlab import --help`). With more
    /// than one (or --table, --shard) each gets a row, files in sorted order
    #[arg(value_name = "FILE", required_unless_present = "merge")]
    pub files: Vec<PathBuf>,
    #[command(flatten)]
    pub import: super::import_args::ImportArgs,
    /// Write one row per recording to this CSV (left_out, misfits, excess, noise, glitches,
    /// mismatch window, seconds, error)
    #[arg(long, value_name = "OUT.csv")]
    pub table: Option<PathBuf>,
    /// Diagnose only every N-th file from the I-th (I from 0), e.g. `--shard
    /// $SLURM_ARRAY_TASK_ID/N` in a Slurm job array
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Join shard tables into --table (sorted by file; a file in two shards is an error)
    #[arg(long, value_name = "TABLE.csv", num_args = 1.., requires = "table", conflicts_with_all = ["files", "shard"])]
    pub merge: Vec<PathBuf>,
    /// Print the result as one JSON object
    #[arg(long)]
    pub json: bool,
    /// Write figures (PNG) and report.md into this folder
    #[arg(long, value_name = "DIR")]
    pub report: Option<PathBuf>,
    /// Only these candidates, comma-separated (default: every effect of `ringlab effects`)
    #[arg(long, value_name = "NAME,..")]
    pub candidates: Option<String>,
    /// BIC drop an effect needs over the baseline to be named
    #[arg(long, default_value_t = ringlab::analysis::diagnose::DEFAULT_EVIDENCE, allow_negative_numbers = true)]
    pub evidence: f64,
    /// Threads (default: all cores)
    #[arg(long)]
    pub threads: Option<usize>,
}
/// The candidates named on the command line.
pub fn parse_candidates(list: &str) -> Result<Vec<EffectKind>> {
    let mut out = Vec::new();
    for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let kind = EffectKind::from_name(name).with_context(|| {
            let names: Vec<&str> = EffectKind::ALL.iter().map(|k| k.name()).collect();
            format!("--candidates: '{name}' is not one of {}", names.join(", "))
        })?;
        if kind != EffectKind::None && !out.contains(&kind) {
            out.push(kind);
        }
    }
    Ok(out)
}

/// The options from the flags.
pub fn options(args: &DiagnoseArgs) -> Result<DiagnoseOptions> {
    if !(args.evidence.is_finite() && args.evidence >= 0.0) {
        bail!("--evidence = {}: must be a number >= 0", args.evidence);
    }
    let mut opts = DiagnoseOptions { evidence: args.evidence, ..DiagnoseOptions::default() };
    if let Some(list) = &args.candidates {
        opts.candidates = parse_candidates(list)?;
    }
    Ok(opts)
}
