//! `ringlab diagnose-bench`: the diagnosis on recordings with a concealed effect, many seeds
//! per effect; how often it names the effect, how much the misfit falls, how often it
//! raises a false alarm on `none`, and how long it takes. Writes the README's table.

use super::diagnose::parse_candidates;
use anyhow::{Context, Result, bail};
use clap::Args;
use ringlab::analysis::diagnose::concealed::{concealed_case, concealed_recording};
use ringlab::analysis::diagnose::{DiagnoseOptions, diagnose};
use ringlab::physics::EffectKind;
use ringlab::recording::synth::synthesize;
use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

/// Markers of the table's place in the README.
const BEGIN: &str = "<!-- diagnose-bench begin -->";
const END: &str = "<!-- diagnose-bench end -->";

#[derive(Args, Debug)]
pub struct DiagnoseBenchArgs {
    /// Recordings per effect
    #[arg(long, default_value_t = 20)]
    pub seeds: u64,
    /// First seed
    #[arg(long, default_value_t = 1)]
    pub first_seed: u64,
    /// Effects to conceal, comma-separated, `none` included (default: all)
    #[arg(long, value_name = "NAME,..")]
    pub effects: Option<String>,
    /// Conceal every effect at this strength instead of a random one in its realistic range
    #[arg(long, allow_negative_numbers = true)]
    pub strength: Option<f64>,
    /// One row per recording, as CSV
    #[arg(long, value_name = "FILE.csv")]
    pub out: Option<PathBuf>,
    /// Replace the table between the diagnose-bench markers of this README
    #[arg(long, value_name = "README.md")]
    pub readme: Option<PathBuf>,
    /// Keep the recordings the diagnosis got wrong in this folder
    #[arg(long, value_name = "DIR")]
    pub keep_wrong: Option<PathBuf>,
    /// Diagnose nothing: make the table from the rows of these CSV files (written by --out by
    /// earlier runs, e.g. one per effect), comma-separated
    #[arg(long, value_name = "FILE.csv,..", value_delimiter = ',', conflicts_with_all = ["out", "keep_wrong", "strength"])]
    pub from_csv: Vec<PathBuf>,
}

struct Row {
    effect: EffectKind,
    seed: u64,
    named: EffectKind,
    before: f64,
    after: f64,
    seconds: f64,
    frames: usize,
}

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) }
}

fn table(rows: &[Row], effects: &[EffectKind], fixed: Option<f64>) -> String {
    let mut out = String::new();
    out.push_str("| concealed | strength | recordings | named correctly | named instead | misfit before -> after, median (when named) | lowest improvement | time median / max |\n");
    out.push_str("|---|---|---|---|---|---|---|---|\n");
    for &k in effects {
        let r: Vec<&Row> = rows.iter().filter(|r| r.effect == k).collect();
        if r.is_empty() {
            continue;
        }
        let ok = r.iter().filter(|r| r.named == k).count();
        let mut wrong: Vec<String> = Vec::new();
        for w in r.iter().filter(|r| r.named != k) {
            let name = w.named.name().to_string();
            if !wrong.contains(&name) {
                wrong.push(name);
            }
        }
        let named: Vec<&&Row> = r.iter().filter(|r| r.named == k && k != EffectKind::None).collect();
        let mut ratios: Vec<f64> = named.iter().map(|r| r.before / r.after).collect();
        let mut before: Vec<f64> = named.iter().map(|r| r.before).collect();
        let mut after: Vec<f64> = named.iter().map(|r| r.after).collect();
        let lowest = ratios.iter().copied().fold(f64::INFINITY, f64::min);
        let mut secs: Vec<f64> = r.iter().map(|r| r.seconds).collect();
        let max_s = secs.iter().copied().fold(0.0, f64::max);
        let (lo, hi) = k.realistic_range();
        let strength = match (k, fixed) {
            (EffectKind::None, _) => "-".to_string(),
            (_, Some(s)) => format!("{s}"),
            _ => format!("{lo} .. {hi}"),
        };
        let rate = if k == EffectKind::None {
            format!("{ok}/{} (false alarms {:.0}%)", r.len(), 100.0 * (r.len() - ok) as f64 / r.len() as f64)
        } else {
            format!("{ok}/{} ({:.0}%)", r.len(), 100.0 * ok as f64 / r.len() as f64)
        };
        let improvement = if named.is_empty() {
            "-".to_string()
        } else {
            format!("{:.2} -> {:.3} px ({:.1}x)", median(&mut before), median(&mut after), median(&mut ratios))
        };
        let lowest = if named.is_empty() { "-".to_string() } else { format!("{lowest:.1}x") };
        out.push_str(&format!(
            "| {} | {strength} | {} | {rate} | {} | {improvement} | {lowest} | {:.1} / {:.1} s |\n",
            k.name(),
            r.len(),
            if wrong.is_empty() { "-".to_string() } else { wrong.join(", ") },
            median(&mut secs),
            max_s
        ));
    }
    out
}

const CSV_HEADER: &str = "effect,seed,strength,named,before_rms_px,after_rms_px,improvement,seconds,frames";

/// The rows of a CSV file that `--out` wrote (every one of its lines checked).
fn read_rows(path: &std::path::Path) -> Result<Vec<Row>> {
    let text = std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, h)) if h.trim() == CSV_HEADER => {}
        _ => bail!("{}:1: not a diagnose-bench table (its first line must be '{CSV_HEADER}')", path.display()),
    }
    let mut rows = Vec::new();
    for (i, line) in lines.filter(|(_, l)| !l.trim().is_empty()) {
        let at = format!("{}:{}", path.display(), i + 1);
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        if f.len() != 9 {
            bail!("{at}: expected 9 fields, found {}", f.len());
        }
        let kind = |s: &str| EffectKind::from_name(s).ok_or_else(|| anyhow::anyhow!("{at}: '{s}' is not an effect"));
        let num = |k: usize, what: &str| -> Result<f64> {
            f[k].parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(|| anyhow::anyhow!("{at}: {what} '{}' is not a number", f[k]))
        };
        rows.push(Row {
            effect: kind(f[0])?,
            seed: f[1].parse().map_err(|_| anyhow::anyhow!("{at}: seed '{}' is not a whole number", f[1]))?,
            named: kind(f[3])?,
            before: num(4, "before_rms_px")?,
            after: num(5, "after_rms_px")?,
            seconds: num(7, "seconds")?,
            frames: f[8].parse().map_err(|_| anyhow::anyhow!("{at}: frames '{}' is not a count", f[8]))?,
        });
    }
    Ok(rows)
}

/// Replaces the table between the markers of `readme`.
fn write_readme(readme: &std::path::Path, t: &str) -> Result<()> {
    let text = std::fs::read_to_string(readme).with_context(|| format!("reading {}", readme.display()))?;
    let (Some(a), Some(b)) = (text.find(BEGIN), text.find(END)) else {
        bail!("{} has no '{BEGIN}' ... '{END}' markers", readme.display());
    };
    if b < a {
        bail!("{}: the diagnose-bench markers are out of order", readme.display());
    }
    let new = format!("{}{BEGIN}\n{t}{}", &text[..a], &text[b..]);
    std::fs::write(readme, new).with_context(|| format!("writing {}", readme.display()))
}

pub fn run(args: &DiagnoseBenchArgs) -> Result<()> {
    let effects: Vec<EffectKind> = match &args.effects {
        None => EffectKind::ALL.to_vec(),
        Some(list) => {
            let mut v = parse_candidates(list)?;
            if list.split(',').any(|s| s.trim() == "none") {
                v.insert(0, EffectKind::None);
            }
            v
        }
    };
    if !args.from_csv.is_empty() {
        let mut rows = Vec::new();
        for p in &args.from_csv {
            for r in read_rows(p)? {
                if rows.iter().any(|o: &Row| o.effect == r.effect && o.seed == r.seed) {
                    bail!("{}: {} seed {} is in the table twice (a recording counts once)", p.display(), r.effect.name(), r.seed);
                }
                rows.push(r);
            }
        }
        rows.retain(|r| effects.contains(&r.effect));
        if rows.is_empty() {
            bail!("no rows of the effects asked for in {}", args.from_csv.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", "));
        }
        let t = table(&rows, &effects, None);
        println!("{t}");
        return args.readme.as_deref().map_or(Ok(()), |r| write_readme(r, &t));
    }
    if args.seeds == 0 {
        bail!("--seeds must be at least 1");
    }
    if let Some(s) = args.strength
        && !s.is_finite()
    {
        bail!("--strength = {s}: must be a finite number");
    }
    let mut csv = match &args.out {
        Some(p) => {
            let mut f = std::fs::File::create(p).with_context(|| format!("creating {}", p.display()))?;
            writeln!(f, "{CSV_HEADER}")?;
            Some(f)
        }
        None => None,
    };
    if let Some(d) = &args.keep_wrong {
        std::fs::create_dir_all(d).with_context(|| format!("creating {}", d.display()))?;
    }
    let cancel = AtomicBool::new(false);
    let mut rows = Vec::new();
    for &k in &effects {
        for seed in args.first_seed..args.first_seed + args.seeds {
            let (rec, strength) = match args.strength {
                Some(s) if k != EffectKind::None => {
                    let (case, mut opts, _) = concealed_case(k, seed).map_err(anyhow::Error::msg)?;
                    opts.effect = Some((k, s));
                    let mut rec = synthesize(&case, &opts).with_context(|| format!("{k} seed {seed}"))?.recording;
                    rec.header.extra.clear();
                    (rec, s)
                }
                _ => {
                    let (rec, truth) = concealed_recording(k, seed).map_err(anyhow::Error::msg)?;
                    (rec, truth.strength)
                }
            };
            let d = diagnose(&rec, &DiagnoseOptions::default(), &|_| {}, &cancel);
            let row = match d {
                Ok(d) => Row {
                    effect: k,
                    seed,
                    named: d.finding.first(),
                    before: d.before.rms_px,
                    after: d.after.rms_px,
                    seconds: d.compute_seconds,
                    frames: d.frames,
                },
                Err(e) => {
                    eprintln!("{k} seed {seed}: diagnosis failed: {e}");
                    continue;
                }
            };
            eprintln!(
                "{:<20} seed {:>3} strength {:>9.5}: named {:<20} {:>8.3} -> {:>7.3} px  {:>5.1} s  {} frames{}",
                k.name(),
                seed,
                strength,
                row.named.name(),
                row.before,
                row.after,
                row.seconds,
                row.frames,
                if row.named == k { "" } else { "  WRONG" }
            );
            if let Some(f) = csv.as_mut() {
                writeln!(
                    f,
                    "{},{},{},{},{},{},{},{},{}",
                    k.name(),
                    seed,
                    strength,
                    row.named.name(),
                    row.before,
                    row.after,
                    row.before / row.after,
                    row.seconds,
                    row.frames
                )?;
                f.flush()?;
            }
            if row.named != k
                && let Some(dir) = &args.keep_wrong
            {
                let p = dir.join(format!("{}-seed{}.csv", k.name(), seed));
                let mut f = std::fs::File::create(&p).with_context(|| format!("creating {}", p.display()))?;
                ringlab::recording::write_recording(&mut f, &rec)?;
            }
            rows.push(row);
        }
    }
    let t = table(&rows, &effects, args.strength);
    println!("{t}");
    args.readme.as_deref().map_or(Ok(()), |r| write_readme(r, &t))
}
