//! `ringlab diagnose FILE... --table OUT.csv [--shard I/N]`: a folder of recordings, one row
//! each, and `--merge` to join the shards' tables.

use super::diagnose_args::DiagnoseArgs;
use super::progress::{COUNT_TEMPLATE, LateBar, with_threads};
use super::shard::{Shard, read_tables, write_table};
use anyhow::{Context, Result, bail};
use ringlab::analysis::diagnose::{DiagnoseOptions, Diagnosis, diagnose};
use ringlab::analysis::json::DiagnoseJson;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// The table's columns.
pub const COLUMNS: [&str; 14] = [
    "file",
    "left_out",
    "left_out_all",
    "misfit_before_px",
    "misfit_after_px",
    "excess_before_px",
    "excess_after_px",
    "noise_px",
    "glitches",
    "mismatch_start_s",
    "mismatch_end_s",
    "frames",
    "seconds",
    "error",
];

fn row(file: &Path, d: &Diagnosis, seconds: f64) -> Vec<String> {
    let f = |x: f64| format!("{x:.4}");
    let named: Vec<&str> = d.finding.named().iter().map(|k| k.name()).collect();
    vec![
        file.display().to_string(),
        d.finding.name().to_string(),
        named.join("+"),
        f(d.before.rms_px),
        f(d.after.rms_px),
        f(d.excess_px(d.before.rms_px)),
        f(d.excess_px(d.after.rms_px)),
        f(d.noise_px),
        d.glitches.len().to_string(),
        d.mismatch.as_ref().map_or(String::new(), |m| f(m.start_s)),
        d.mismatch.as_ref().map_or(String::new(), |m| f(m.end_s)),
        d.frames.to_string(),
        format!("{seconds:.1}"),
        String::new(),
    ]
}

fn error_row(file: &Path, e: &anyhow::Error, seconds: f64) -> Vec<String> {
    let mut r = vec![String::new(); COLUMNS.len()];
    r[0] = file.display().to_string();
    r[1] = "error".into();
    r[12] = format!("{seconds:.1}");
    r[13] = format!("{e:#}");
    r
}

#[derive(Serialize)]
struct FileJson<'a> {
    file: String,
    #[serde(flatten)]
    diagnosis: Option<&'a DiagnoseJson>,
    error: Option<String>,
}

pub fn run(args: &DiagnoseArgs, opts: &DiagnoseOptions) -> Result<()> {
    let shard = args.shard.as_deref().map(Shard::parse).transpose()?;
    let mut files = args.files.clone();
    files.sort();
    if let Some(dup) = files.windows(2).find(|w| w[0] == w[1]) {
        bail!("{} is given twice", dup[0].display());
    }
    let mine = Shard::pick(shard, &files);
    let mut table = match &args.table {
        Some(p) => {
            let mut w = csv::Writer::from_path(p)
                .with_context(|| format!("cannot create {}", p.display()))?;
            w.write_record(COLUMNS)?;
            w.flush()?;
            Some(w)
        }
        None => None,
    };
    if let Some(s) = shard {
        eprintln!("shard {}/{}: {} of {} files", s.index, s.count, mine.len(), files.len());
    }
    let bar = LateBar::new(COUNT_TEMPLATE);
    let mut failed = 0usize;
    for (i, file) in mine.iter().enumerate() {
        let name = file
            .file_name()
            .map_or(file.display().to_string(), |n| n.to_string_lossy().into_owned());
        let clock = Instant::now();
        let outcome = diagnose_file(args, opts, file, &|fraction| {
            bar.update(
                (1000.0 * (i as f64 + fraction.clamp(0.0, 1.0))) as u64,
                1000 * mine.len() as u64,
                name.clone(),
            )
        });
        let seconds = clock.elapsed().as_secs_f64();
        let (cells, json, error) = match &outcome {
            Ok(d) => (row(file, d, seconds), Some(DiagnoseJson::new(d)), None),
            Err(e) => {
                failed += 1;
                (error_row(file, e, seconds), None, Some(format!("{e:#}")))
            }
        };
        if let Some(w) = table.as_mut() {
            // Flushed row by row: a job killed at its time limit keeps the rows it finished.
            w.write_record(&cells)?;
            w.flush()?;
        }
        if args.json {
            let line =
                FileJson { file: file.display().to_string(), diagnosis: json.as_ref(), error };
            bar.println(&serde_json::to_string(&line)?);
        } else {
            let said = match &outcome {
                Ok(d) => {
                    let name = if cells[2].is_empty() { &cells[1] } else { &cells[2] };
                    let (before, after, noise) = (d.before.rms_px, d.after.rms_px, d.noise_px);
                    format!(
                        "{name} ({before:.3} -> {after:.3} px, noise {noise:.3} px, {} glitches)",
                        d.glitches.len()
                    )
                }
                Err(e) => format!("error: {e:#}"),
            };
            match &outcome {
                Ok(_) => bar.println(&format!("{}: {said} [{seconds:.1} s]", file.display())),
                Err(_) => bar.println(&format!("{said} [{seconds:.1} s]")),
            }
        }
    }
    bar.finish();
    if let Some(p) = &args.table {
        eprintln!("{} rows written to {}", mine.len(), p.display());
    }
    if failed > 0 {
        bail!(
            "{failed} of {} files could not be diagnosed (the error column says why)",
            mine.len()
        );
    }
    Ok(())
}

/// One file read and diagnosed; `progress` gets the fraction done.
fn diagnose_file(
    args: &DiagnoseArgs,
    opts: &DiagnoseOptions,
    file: &Path,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Diagnosis> {
    let rec = super::import_args::load_one(&args.import, file)?;
    let cancel = AtomicBool::new(false);
    let d =
        with_threads(args.threads, || diagnose(&rec, opts, &|p| progress(p.fraction), &cancel))?
            .with_context(|| format!("diagnosing {}", file.display()))?;
    if let Some(dir) = &args.report {
        let stem =
            file.file_stem().map_or("recording".into(), |s| s.to_string_lossy().into_owned());
        let sub = dir.join(stem);
        super::diagnose_report::write(&sub, file, &rec, &d)
            .with_context(|| format!("writing the report into {}", sub.display()))?;
    }
    Ok(d)
}

/// Joins shard tables: rows sorted by file, every file once.
pub fn merge(tables: &[PathBuf], out: &Path) -> Result<()> {
    let (header, rows) = read_tables(tables)?;
    if header != COLUMNS {
        bail!(
            "{}: not a table of `ringlab diagnose --table` (its columns are {})",
            tables[0].display(),
            header.join(",")
        );
    }
    let mut sorted: Vec<_> = rows.iter().collect();
    sorted.sort_by(|a, b| a.cells[0].cmp(&b.cells[0]));
    for w in sorted.windows(2) {
        if w[0].cells[0] == w[1].cells[0] {
            bail!(
                "{} is in two shards: {}:{} and {}:{}",
                w[0].cells[0],
                w[0].file.display(),
                w[0].line,
                w[1].file.display(),
                w[1].line
            );
        }
    }
    write_table(out, &header, &sorted)?;
    let errors = sorted.iter().filter(|r| r.cells.get(1).is_some_and(|c| c == "error")).count();
    println!(
        "{} rows from {} tables written to {} ({errors} with errors)",
        sorted.len(),
        tables.len(),
        out.display()
    );
    Ok(())
}
