//! `ringlab diagnose-bench`: the diagnosis on concealed recordings, many seeds per family
//! (`analysis::diagnose::concealed::Family`: one effect, one effect with a tracker's glitches,
//! pairs, a withheld candidate, no effect under a known camera); how often it says what it
//! should, how much of the misfit beyond the noise the named model removes, how often it
//! raises a false alarm, and how long it takes. Writes the table of `docs/diagnosis.md`.

use anyhow::{Context, Result, bail};
use clap::Args;
use ringlab::analysis::diagnose::concealed::{Family, family_recording};
use ringlab::analysis::diagnose::{DiagnoseOptions, Diagnosis, Finding, diagnose, excess_px};
use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

/// Markers of the table's place in a Markdown file (`docs/diagnosis.md`), each on a line of its
/// own: HTML comments, so the rendered page does not show them.
const BEGIN: &str = "<!-- diagnose-bench begin -->";
const END: &str = "<!-- diagnose-bench end -->";

#[derive(Args, Debug)]
pub struct DiagnoseBenchArgs {
    /// Recordings per family
    #[arg(long, default_value_t = 20)]
    pub seeds: u64,
    /// First seed
    #[arg(long, default_value_t = 1)]
    pub first_seed: u64,
    /// Families, comma-separated: single:NAME, glitches:NAME, pair:A+B, withheld:NAME,
    /// camera-known:pinhole|tilted, or the groups single, glitches, pairs, withheld,
    /// camera-known (default: every family)
    #[arg(long, value_name = "FAMILY,..")]
    pub families: Option<String>,
    /// One row per recording, as CSV
    #[arg(long, value_name = "FILE.csv")]
    pub out: Option<PathBuf>,
    /// Replace the table between the diagnose-bench markers of this Markdown file (the
    /// project's is docs/diagnosis.md)
    #[arg(long, value_name = "FILE.md")]
    pub readme: Option<PathBuf>,
    /// Keep the recordings the diagnosis got wrong in this folder
    #[arg(long, value_name = "DIR")]
    pub keep_wrong: Option<PathBuf>,
    /// Keep every recording, right or wrong, in this folder (to rerun or profile one)
    #[arg(long, value_name = "DIR")]
    pub keep: Option<PathBuf>,
    /// Diagnose nothing: make the table from the rows of these CSV files (written by --out by
    /// earlier runs), comma-separated
    #[arg(long, value_name = "FILE.csv,..", value_delimiter = ',', conflicts_with_all = ["out", "keep_wrong", "keep"])]
    pub from_csv: Vec<PathBuf>,
}

/// One recording's result.
struct Row {
    family: String,
    seed: u64,
    /// What it should say and what it said: effect names joined by `+`, `none`, `unexplained`.
    expected: String,
    said: String,
    before: f64,
    after: f64,
    noise: f64,
    glitches: usize,
    seconds: f64,
    frames: usize,
}

impl Row {
    fn right(&self) -> bool {
        sorted(&self.expected) == sorted(&self.said)
    }
    fn named(&self) -> bool {
        !matches!(self.said.as_str(), "none" | "unexplained" | FAILED)
    }
    /// The diagnosis's time scaled to a recording of 2,000 frames (the speed goal's unit).
    fn seconds_per_2000_frames(&self) -> f64 {
        self.seconds * 2000.0 / self.frames.max(1) as f64
    }
    fn excess(&self) -> (f64, f64) {
        (excess_px(self.before, self.noise), excess_px(self.after, self.noise))
    }
}

/// The speed goal: seconds of diagnosis per 2,000 frames, every candidate and the pairs, on 2
/// cores.
const SPEED_GOAL_S: f64 = 30.0;

/// A row's `said` where the diagnosis returned an error (its numbers are then zero).
const FAILED: &str = "failed";

fn sorted(s: &str) -> Vec<&str> {
    let mut v: Vec<&str> = s.split('+').collect();
    v.sort_unstable();
    v
}

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) }
}

/// What a diagnosis said, as a row's text.
fn said(d: &Diagnosis) -> String {
    match &d.finding {
        Finding::Named(k) => k.iter().map(|k| k.name()).collect::<Vec<_>>().join("+"),
        f => f.name().to_string(),
    }
}

/// The bench's table: one line per family in the order first met, then the goals' checks.
fn table(rows: &[Row]) -> String {
    let mut families: Vec<&str> = Vec::new();
    for r in rows {
        if !families.contains(&r.family.as_str()) {
            families.push(&r.family);
        }
    }
    let mut out = String::new();
    out.push_str("| family | should say | recordings | right | said instead | excess beyond the noise before -> after, median (when right and named) | smallest cut | time median / max | per 2,000 frames median / max |\n");
    out.push_str("|---|---|---|---|---|---|---|---|---|\n");
    for f in &families {
        let r: Vec<&Row> = rows.iter().filter(|r| r.family == *f).collect();
        let ok = r.iter().filter(|r| r.right()).count();
        let mut wrong: Vec<&str> = Vec::new();
        for w in r.iter().filter(|r| !r.right()) {
            if !wrong.contains(&w.said.as_str()) {
                wrong.push(&w.said);
            }
        }
        let named: Vec<&&Row> = r.iter().filter(|r| r.right() && r.named()).collect();
        let mut before: Vec<f64> = named.iter().map(|r| r.excess().0).collect();
        let mut after: Vec<f64> = named.iter().map(|r| r.excess().1).collect();
        let cut = |r: &Row| {
            let (b, a) = r.excess();
            b / a.max(1e-3 * r.noise)
        };
        let smallest = named.iter().map(|r| cut(r)).fold(f64::INFINITY, f64::min);
        let mut secs: Vec<f64> = r.iter().map(|r| r.seconds).collect();
        let max_s = secs.iter().copied().fold(0.0, f64::max);
        let mut per: Vec<f64> = r.iter().map(|r| r.seconds_per_2000_frames()).collect();
        let max_per = per.iter().copied().fold(0.0, f64::max);
        let share = 100.0 * ok as f64 / r.len() as f64;
        let rate = if r[0].expected == "none" {
            // Something said missing where nothing is (a failed diagnosis said nothing).
            let alarms = r.iter().filter(|r| !r.right() && r.said != FAILED).count();
            format!(
                "{ok}/{} (false alarms {:.0}%)",
                r.len(),
                100.0 * alarms as f64 / r.len() as f64
            )
        } else {
            format!("{ok}/{} ({share:.0}%)", r.len())
        };
        let improvement = if named.is_empty() {
            "-".to_string()
        } else {
            format!("{:.2} -> {:.3} px", median(&mut before), median(&mut after))
        };
        let smallest = if named.is_empty() {
            "-".to_string()
        } else if smallest > 999.0 {
            ">999x".to_string()
        } else {
            format!("{smallest:.1}x")
        };
        out.push_str(&format!(
            "| {f} | {} | {} | {rate} | {} | {improvement} | {smallest} | {:.1} / {:.1} s | {:.1} / {:.1} s |\n",
            r[0].expected,
            r.len(),
            if wrong.is_empty() { "-".to_string() } else { wrong.join(", ") },
            median(&mut secs),
            max_s,
            median(&mut per),
            max_per
        ));
    }
    let none_far = rows.iter().filter(|r| r.said == "none" && r.before >= 2.0 * r.noise).count();
    let weak = rows.iter().filter(|r| r.right() && r.named()).filter(|r| {
        let (b, a) = r.excess();
        a * 4.0 > b && a >= 0.15 * r.noise
    });
    let fast = rows.iter().filter(|r| r.seconds_per_2000_frames() <= SPEED_GOAL_S).count();
    out.push_str(&format!(
        "\n`none` said where the baseline missed by twice the noise or more: {none_far}. Named rightly but the excess cut less than 4x and left above 0.15 noise: {}. Diagnosed within {SPEED_GOAL_S:.0} s per 2,000 frames: {fast} of {}.\n",
        weak.count(),
        rows.len()
    ));
    out
}

const CSV_HEADER: &str =
    "family,seed,expected,said,before_rms_px,after_rms_px,noise_px,glitches,seconds,frames";

/// A row's `said` or `expected` field: effect names joined by `+`, `none`, `unexplained`
/// (`said` may also be [`FAILED`]).
fn finding_field(s: &str) -> bool {
    s == "unexplained" || s.split('+').all(|n| ringlab::physics::EffectKind::from_name(n).is_some())
}

/// The rows of a CSV file that `--out` wrote (every one of its lines checked).
fn read_rows(path: &std::path::Path) -> Result<Vec<Row>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, h)) if h.trim() == CSV_HEADER => {}
        _ => bail!(
            "{}:1: not a diagnose-bench table (its first line must be '{CSV_HEADER}')",
            path.display()
        ),
    }
    let mut rows = Vec::new();
    for (i, line) in lines.filter(|(_, l)| !l.trim().is_empty()) {
        let at = format!("{}:{}", path.display(), i + 1);
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        if f.len() != 10 {
            bail!("{at}: expected 10 fields, found {}", f.len());
        }
        if Family::from_name(f[0]).is_none() {
            bail!("{at}: '{}' is not a family", f[0]);
        }
        for (k, what) in [(2, "expected"), (3, "said")] {
            let failed = k == 3 && f[k] == FAILED;
            if !failed && !finding_field(f[k]) {
                bail!("{at}: {what} '{}' is not an effect, none or unexplained", f[k]);
            }
        }
        let num = |k: usize, what: &str| -> Result<f64> {
            f[k].parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| anyhow::anyhow!("{at}: {what} '{}' is not a number", f[k]))
        };
        let count = |k: usize, what: &str| -> Result<usize> {
            f[k].parse().map_err(|_| anyhow::anyhow!("{at}: {what} '{}' is not a count", f[k]))
        };
        rows.push(Row {
            family: f[0].to_string(),
            seed: f[1]
                .parse()
                .map_err(|_| anyhow::anyhow!("{at}: seed '{}' is not a whole number", f[1]))?,
            expected: f[2].to_string(),
            said: f[3].to_string(),
            before: num(4, "before_rms_px")?,
            after: num(5, "after_rms_px")?,
            noise: num(6, "noise_px")?,
            glitches: count(7, "glitches")?,
            seconds: num(8, "seconds")?,
            frames: count(9, "frames")?,
        });
    }
    Ok(rows)
}

/// Where `marker` stands alone on a line of `text` (the byte offset of that line). A marker
/// quoted inside a sentence, as a page describing the markers would quote it, does not count.
fn marker_line(text: &str, marker: &str) -> Option<usize> {
    let mut at = 0;
    for line in text.split_inclusive('\n') {
        if line.trim() == marker {
            return Some(at + (line.len() - line.trim_start().len()));
        }
        at += line.len();
    }
    None
}

/// Replaces the table between the markers of `readme` (a Markdown file: `docs/diagnosis.md`).
fn write_readme(readme: &std::path::Path, t: &str) -> Result<()> {
    let text =
        std::fs::read_to_string(readme).with_context(|| format!("reading {}", readme.display()))?;
    let (Some(a), Some(b)) = (marker_line(&text, BEGIN), marker_line(&text, END)) else {
        bail!(
            "{} has no '{BEGIN}' ... '{END}' markers, each on a line of its own",
            readme.display()
        );
    };
    if b < a {
        bail!("{}: the diagnose-bench markers are out of order", readme.display());
    }
    let new = format!("{}{BEGIN}\n{t}{}", &text[..a], &text[b..]);
    std::fs::write(readme, new).with_context(|| format!("writing {}", readme.display()))
}

/// The families of `--families` (groups expanded).
fn parse_families(list: Option<&str>) -> Result<Vec<Family>> {
    let Some(list) = list else { return Ok(Family::all()) };
    let mut out: Vec<Family> = Vec::new();
    for item in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let group: Vec<Family> = match item {
            "single" | "glitches" | "withheld" | "camera-known" => {
                Family::all().into_iter().filter(|f| f.name().starts_with(&format!("{item}:"))).collect()
            }
            "pairs" => Family::all().into_iter().filter(|f| matches!(f, Family::Pair(..))).collect(),
            _ => vec![Family::from_name(item).with_context(|| {
                format!("--families: '{item}' is not a family (single:NAME, glitches:NAME, pair:A+B, withheld:NAME, camera-known:pinhole|tilted, or a group)")
            })?],
        };
        for f in group {
            if !out.contains(&f) {
                out.push(f);
            }
        }
    }
    if out.is_empty() {
        bail!("--families: no family given");
    }
    Ok(out)
}

pub fn run(args: &DiagnoseBenchArgs) -> Result<()> {
    let families = parse_families(args.families.as_deref())?;
    if !args.from_csv.is_empty() {
        let mut rows: Vec<Row> = Vec::new();
        for p in &args.from_csv {
            for r in read_rows(p)? {
                if rows.iter().any(|o| o.family == r.family && o.seed == r.seed) {
                    bail!(
                        "{}: {} seed {} is in the table twice (a recording counts once)",
                        p.display(),
                        r.family,
                        r.seed
                    );
                }
                rows.push(r);
            }
        }
        if args.families.is_some() {
            let names: Vec<String> = families.iter().map(Family::name).collect();
            rows.retain(|r| names.contains(&r.family));
        }
        if rows.is_empty() {
            bail!(
                "no rows of the families asked for in {}",
                args.from_csv
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
        let t = table(&rows);
        println!("{t}");
        return args.readme.as_deref().map_or(Ok(()), |r| write_readme(r, &t));
    }
    if args.seeds == 0 {
        bail!("--seeds must be at least 1");
    }
    let mut csv = match &args.out {
        Some(p) => {
            let mut f =
                std::fs::File::create(p).with_context(|| format!("creating {}", p.display()))?;
            writeln!(f, "{CSV_HEADER}")?;
            Some(f)
        }
        None => None,
    };
    for d in [&args.keep_wrong, &args.keep].into_iter().flatten() {
        std::fs::create_dir_all(d).with_context(|| format!("creating {}", d.display()))?;
    }
    let cancel = AtomicBool::new(false);
    let mut rows = Vec::new();
    for family in &families {
        for seed in args.first_seed..args.first_seed + args.seeds {
            let rec = family_recording(*family, seed)
                .map_err(anyhow::Error::msg)
                .with_context(|| format!("{} seed {seed}", family.name()))?;
            let opts =
                DiagnoseOptions { candidates: family.candidates(), ..DiagnoseOptions::default() };
            let clock = std::time::Instant::now();
            let row = match diagnose(&rec, &opts, &|_| {}, &cancel) {
                Ok(d) => Row {
                    family: family.name(),
                    seed,
                    expected: family.expected().join("+"),
                    said: said(&d),
                    before: d.before.rms_px,
                    after: d.after.rms_px,
                    noise: d.noise_px,
                    glitches: d.glitches.len(),
                    seconds: d.compute_seconds,
                    frames: d.frames,
                },
                // A failure is a wrong answer, counted in its family, not a recording left out.
                Err(e) => {
                    eprintln!("{} seed {seed}: diagnosis failed: {e}", family.name());
                    Row {
                        family: family.name(),
                        seed,
                        expected: family.expected().join("+"),
                        said: FAILED.to_string(),
                        before: 0.0,
                        after: 0.0,
                        noise: 0.0,
                        glitches: 0,
                        seconds: clock.elapsed().as_secs_f64(),
                        frames: rec.frames.len(),
                    }
                }
            };
            eprintln!(
                "{:<42} seed {:>3}: said {:<40} {:>8.3} -> {:>7.3} px (noise {:.3})  {:>5.1} s  {} frames{}",
                row.family,
                seed,
                row.said,
                row.before,
                row.after,
                row.noise,
                row.seconds,
                row.frames,
                if row.right() { "" } else { "  WRONG" }
            );
            if let Some(f) = csv.as_mut() {
                let r = &row;
                writeln!(
                    f,
                    "{},{},{},{},{},{},{},{},{},{}",
                    r.family,
                    r.seed,
                    r.expected,
                    r.said,
                    r.before,
                    r.after,
                    r.noise,
                    r.glitches,
                    r.seconds,
                    r.frames
                )?;
                f.flush()?;
            }
            // A wrong one is kept in --keep-wrong, else in --keep; a right one only in --keep.
            let keep_in =
                if row.right() { None } else { args.keep_wrong.as_ref() }.or(args.keep.as_ref());
            if let Some(dir) = keep_in {
                let p = dir.join(format!(
                    "{}-seed{}.csv",
                    family.name().replace([':', '+'], "-"),
                    seed
                ));
                let mut f = std::fs::File::create(&p)
                    .with_context(|| format!("creating {}", p.display()))?;
                // Exactly as diagnosed, so that diagnosing the file gives this row again.
                ringlab::recording::write_recording_exact(&mut f, &rec)?;
            }
            rows.push(row);
        }
    }
    let t = table(&rows);
    println!("{t}");
    args.readme.as_deref().map_or(Ok(()), |r| write_readme(r, &t))
}
