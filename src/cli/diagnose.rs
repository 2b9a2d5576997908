//! `ringlab diagnose`: which physics the paper's model left out of a recording, if any.

use super::diagnose_report;
use super::progress::{LateBar, PERCENT_TEMPLATE, with_threads};
use anyhow::{Context, Result, bail};
use clap::Args;
use ringlab::analysis::diagnose::{
    CONSISTENT_RATIO, DiagnoseOptions, DiagnoseProgress, Diagnosis, Finding, diagnose,
};
use ringlab::physics::{EffectKind, SlipStart};
use ringlab::recording::glitches::GlitchKind;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

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

/// The JSON object of `ringlab diagnose --json`.
#[derive(Serialize, Debug)]
pub struct DiagnoseJson {
    /// `none`, `unexplained`, or the first effect named.
    pub left_out: &'static str,
    /// Every effect named, in order (empty for `none` and `unexplained`).
    pub left_out_all: Vec<&'static str>,
    /// For `unexplained`: the candidate that explains the largest share of the excess.
    pub partial: Option<PartialJson>,
    /// Tracked mark positions left out as the tracker's glitches.
    pub glitches: usize,
    /// Each of them: the frame number (as in the file), the mark (1 to 4) and what it was.
    pub glitch_marks: Vec<GlitchJson>,
    /// The baseline is `none` only within this many times the noise.
    pub consistent_ratio: f64,
    pub mismatch: Option<WindowJson>,
    pub before: FitJson,
    pub after: FitJson,
    pub candidates: Vec<CandidateJson>,
    /// The pairs of the forward selection, best first (empty when none were tried).
    pub pairs: Vec<PairJson>,
    pub explanation: String,
    pub compute_seconds: f64,
    pub noise_px: f64,
    /// Where the tracker's noise is correlated in time (the baseline's residual shows it and
    /// nothing else): what the tracks read, the correlation, and `noise_px` corrected for it.
    pub noise_correlation: Option<NoiseCorrelationJson>,
    pub windows: Vec<WindowJson>,
    pub frames: usize,
    pub frames_fitted: usize,
    pub segments_rms_px: f64,
}

#[derive(Serialize, Debug)]
pub struct NoiseCorrelationJson {
    /// The tracks' own reading (px), before the correction.
    pub tracks_px: f64,
    /// The correlation from one frame to the next, and the lag (frames) where it has died out.
    pub lag1: f64,
    pub range_frames: usize,
    /// The baseline's RMS that the corrected level agreed with (px).
    pub residual_px: f64,
}

#[derive(Serialize, Debug)]
pub struct GlitchJson {
    pub frame: u64,
    pub mark: usize,
    /// `outlier` (off its own track) or `swapped` (a label exchanged with another mark's).
    pub kind: &'static str,
}

#[derive(Serialize, Debug)]
pub struct PairJson {
    pub names: [&'static str; 2],
    pub rms_px: Option<f64>,
    pub delta_score: Option<f64>,
    pub strengths: [Option<f64>; 2],
    pub error: Option<String>,
}

#[derive(Serialize, Debug)]
pub struct PartialJson {
    /// One effect, or a pair.
    pub names: Vec<&'static str>,
    /// Share of the baseline's squared misfit beyond the noise that it removes.
    pub explained_share: f64,
    /// Its misfit, and the part of it beyond the noise (px).
    pub rms_px: f64,
    pub excess_px: f64,
}

#[derive(Serialize, Debug)]
pub struct WindowJson {
    pub start_s: f64,
    pub end_s: f64,
    pub rms_px: f64,
    pub share: f64,
}

#[derive(Serialize, Debug)]
pub struct FitJson {
    pub rms_px: f64,
    /// `sqrt(max(rms^2 - noise^2, 0))`: the misfit beyond the noise.
    pub excess_px: f64,
    pub score: f64,
    pub effect: &'static str,
    /// `C1..C3`, their sigmas, and the effect's strength with its sigma, by name.
    pub params: BTreeMap<String, Option<f64>>,
    pub end_s: Option<f64>,
    /// With slip: how its run begins, `cone` (sliding at once where the start needs more
    /// friction than `mu F_N`) or `held_rolling` (rolling until it first needs no more).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slip_start: Option<&'static str>,
}

#[derive(Serialize, Debug)]
pub struct CandidateJson {
    pub name: &'static str,
    pub rms_px: Option<f64>,
    pub score: Option<f64>,
    pub delta_score: Option<f64>,
    pub strength: Option<f64>,
    pub strength_sigma: Option<f64>,
    pub error: Option<String>,
    /// Where its whole-run path stopped (the segments of that stage), if it did.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stopped_at_segments: Option<usize>,
}

fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

impl DiagnoseJson {
    pub fn new(d: &Diagnosis) -> DiagnoseJson {
        let window = |w: &ringlab::analysis::diagnose::MismatchWindow| WindowJson {
            start_s: w.start_s,
            end_s: w.end_s,
            rms_px: w.rms_px,
            share: w.share,
        };
        let fit = |f: &ringlab::analysis::diagnose::ModelFit| {
            let mut params = BTreeMap::new();
            for i in 0..3 {
                params.insert(format!("C{}", i + 1), finite(f.c[i]));
                params.insert(format!("C{}_sigma", i + 1), finite(f.c_sigma[i]));
            }
            for (i, name) in ["R_mm", "h_mm"].iter().enumerate() {
                params.insert(name.to_string(), finite(f.body_mm[i].0));
                params.insert(format!("{name}_sigma"), finite(f.body_mm[i].1));
            }
            if let Some((v, s)) = f.strength {
                params.insert(f.effect.name().to_string(), finite(v));
                params.insert(format!("{}_sigma", f.effect.name()), finite(s));
            }
            if let Some((v, s)) = f.tilt_deg {
                params.insert("camera_tilt_deg".into(), finite(v));
                params.insert("camera_tilt_deg_sigma".into(), finite(s));
            }
            if let Some([along, across]) = f.slip_start_mm_s() {
                params.insert("slip_start_along_mm_s".into(), finite(along));
                params.insert("slip_start_across_mm_s".into(), finite(across));
            }
            if let Some((v, s)) = f.rim_share {
                params.insert("reynolds_rim_share".into(), finite(v));
                params.insert("reynolds_rim_share_sigma".into(), finite(s));
            }
            FitJson {
                rms_px: f.rms_px,
                excess_px: d.excess_px(f.rms_px),
                score: f.score,
                effect: f.effect.name(),
                params,
                end_s: f.end_s,
                slip_start: f.model.effects.slip_mu.map(|_| match f.model.effects.slip_start {
                    SlipStart::Cone => "cone",
                    SlipStart::HeldRolling => "held_rolling",
                }),
            }
        };
        DiagnoseJson {
            left_out: d.finding.name(),
            left_out_all: d.finding.named().iter().map(|k| k.name()).collect(),
            partial: match &d.finding {
                Finding::Unexplained { partial: Some(p) } => Some(PartialJson {
                    names: p.effects.iter().map(|k| k.name()).collect(),
                    explained_share: p.share,
                    rms_px: p.rms_px,
                    excess_px: d.excess_px(p.rms_px),
                }),
                _ => None,
            },
            glitches: d.glitches.len(),
            glitch_marks: d
                .glitches
                .iter()
                .map(|g| GlitchJson {
                    frame: d.first_frame + g.frame as u64,
                    mark: g.mark + 1,
                    kind: match g.kind {
                        GlitchKind::Outlier => "outlier",
                        GlitchKind::Swapped => "swapped",
                    },
                })
                .collect(),
            consistent_ratio: CONSISTENT_RATIO,
            mismatch: d.mismatch.as_ref().map(window),
            before: fit(&d.before),
            after: fit(&d.after),
            candidates: d
                .candidates
                .iter()
                .map(|c| CandidateJson {
                    name: c.effect.name(),
                    rms_px: finite(c.rms_px),
                    score: finite(c.score),
                    delta_score: finite(c.delta_score),
                    strength: c.strength.and_then(|s| finite(s.0)),
                    strength_sigma: c.strength.and_then(|s| finite(s.1)),
                    error: c.error.clone(),
                    stopped_at_segments: c.stopped_at_segments,
                })
                .collect(),
            pairs: d
                .pairs
                .iter()
                .map(|p| PairJson {
                    names: [p.first.name(), p.second.name()],
                    rms_px: finite(p.rms_px),
                    delta_score: finite(p.delta_score),
                    strengths: p.strengths.map(|s| finite(s.0)),
                    error: p.error.clone(),
                })
                .collect(),
            explanation: d.explanation.clone(),
            compute_seconds: d.compute_seconds,
            noise_px: d.noise_px,
            noise_correlation: d.noise_correlation.as_ref().map(|c| NoiseCorrelationJson {
                tracks_px: c.tracks_px,
                lag1: c.rho.get(1).copied().unwrap_or(0.0),
                range_frames: c.range_frames,
                residual_px: c.residual_px,
            }),
            windows: d.windows.iter().map(window).collect(),
            frames: d.frames,
            frames_fitted: d.frames_fitted,
            segments_rms_px: d.segments_rms_px,
        }
    }
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
