//! `ringlab import`: a lab tracker's files written as a format v1 recording.

use super::import_args::{ImportArgs, describe};
use anyhow::{Context, Result};
use clap::Args;
use ringlab::recording::write_recording;
use std::io::Write;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct ImportCmdArgs {
    /// The tracker's file(s): one DeepLabCut CSV, TrackMate spots CSV, plain CSV or Tracker
    /// project; or one Tracker data table per mark
    #[arg(value_name = "FILE", required = true)]
    pub files: Vec<PathBuf>,
    #[command(flatten)]
    pub import: ImportArgs,
    /// The recording to write (format v1)
    #[arg(long, value_name = "REC.csv")]
    pub out: PathBuf,
}

pub fn run(args: &ImportCmdArgs) -> Result<()> {
    let imported = args.import.load(&args.files)?;
    let mut bytes = Vec::new();
    write_recording(&mut bytes, &imported.recording)?;
    // Read back what was written: the file on disk is what every command will see.
    ringlab::recording::parse_recording(&bytes, &args.out)
        .context("the written recording does not read back")?;
    let mut f = std::fs::File::create(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    f.write_all(&bytes).with_context(|| format!("cannot write {}", args.out.display()))?;
    for line in describe(&imported) {
        println!("{line}");
    }
    println!("written: {}", args.out.display());
    Ok(())
}
