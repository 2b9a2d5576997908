//! `ringlab fit`: the model fitted to a recording (drag and start state).

use anyhow::{Context, Result, bail};
use clap::Args;
use ringlab::analysis::fit::{FitOptions, FitProgress, FitStage, fit};
use ringlab::physics::EffectKind;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

#[derive(Args, Debug)]
pub struct FitArgs {
    /// The recording (format v1, or a tracker's file: see `ringlab import --help`)
    #[arg(value_name = "FILE")]
    pub file: PathBuf,
    #[command(flatten)]
    pub import: super::import_args::ImportArgs,
    /// Print the result as one JSON object
    #[arg(long)]
    pub json: bool,
    /// Frames per shooting segment at first (doubled while the data allow, see --merges)
    #[arg(long, default_value_t = 60)]
    pub segment_frames: usize,
    /// How many times the segments may be doubled in length
    #[arg(long, default_value_t = 2)]
    pub merges: usize,
    /// Leave out the coarse drag grid (start the least squares from --c-start)
    #[arg(long)]
    pub no_coarse: bool,
    /// Drag to start from, as C1,C2,C3
    #[arg(long, value_name = "C1,C2,C3", default_value = "0.03,0.063,0.085")]
    pub c_start: String,
    /// Fit an effect's strength too (see `ringlab synth --help` for the names)
    #[arg(long, value_name = "NAME")]
    pub effect: Option<String>,
    /// Starting strength of --effect
    #[arg(long, value_name = "X", default_value_t = 0.0, allow_negative_numbers = true)]
    pub effect_start: f64,
    /// The camera's radial distortion k1, when known
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub lens_k1: f64,
    /// Threads (default: all cores)
    #[arg(long)]
    pub threads: Option<usize>,
}

fn parse_c(s: &str) -> Result<[f64; 3]> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 3 {
        bail!("--c-start '{s}': expected C1,C2,C3");
    }
    let mut c = [0.0; 3];
    for (slot, p) in c.iter_mut().zip(parts) {
        let v: f64 =
            p.trim().parse().with_context(|| format!("--c-start '{s}': '{p}' is not a number"))?;
        if !(v.is_finite() && v > 0.0) {
            bail!("--c-start '{s}': every coefficient must be a positive number");
        }
        *slot = v;
    }
    Ok(c)
}

pub fn run(args: &FitArgs) -> Result<()> {
    let c_start = parse_c(&args.c_start)?;
    let effect = match &args.effect {
        None => None,
        Some(name) => {
            let kind = EffectKind::from_name(name).with_context(|| {
                let names: Vec<&str> = EffectKind::ALL.iter().map(|k| k.name()).collect();
                format!("--effect '{name}' is not one of {}", names.join(", "))
            })?;
            (kind != EffectKind::None).then_some((kind, args.effect_start))
        }
    };
    if !args.lens_k1.is_finite() {
        bail!("--lens-k1 = {}: must be a finite number", args.lens_k1);
    }
    let rec = super::import_args::load_one(&args.import, &args.file)?;
    let opts = FitOptions {
        segment_frames: args.segment_frames,
        merges: args.merges,
        c_start,
        coarse: !args.no_coarse,
        effect,
        lens_k1: args.lens_k1,
        ..FitOptions::default()
    };

    let bar = super::progress::LateBar::new(super::progress::COUNT_TEMPLATE);
    let progress = |p: &FitProgress| {
        let msg = match (p.stage, p.rms_px) {
            (FitStage::Refine, Some(rms)) => format!("{} {rms:.3} px", p.stage.describe()),
            (stage, _) => stage.describe().to_string(),
        };
        bar.update(p.done as u64, p.total as u64, msg);
    };
    let cancel = AtomicBool::new(false);
    let result =
        super::progress::with_threads(args.threads, || fit(&rec, &opts, &progress, &cancel))?;
    bar.finish();
    let r = result.with_context(|| format!("fitting {}", args.file.display()))?;
    let report = ringlab::analysis::json::FitReport::new(&r);
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    let pm = |x: f64, s: f64| {
        if s.is_finite() { format!("{x:.5} +- {s:.5}") } else { format!("{x:.5} (unconstrained)") }
    };
    println!(
        "{}: {} frames, {} fitted from the first inner turning point at frame {:.2} ({:.4} s)",
        args.file.display(),
        r.frames,
        r.frames_fitted,
        r.start_frame,
        report.start_time_s
    );
    println!(
        "drag  C1 = {}, C2 = {}, C3 = {}",
        pm(r.c[0], r.c_sigma[0]),
        pm(r.c[1], r.c_sigma[1]),
        pm(r.c[2], r.c_sigma[2])
    );
    if let Some((k, s, sd)) = r.effect {
        println!("effect {k} = {}  ({})", pm(s, sd), k.parameter());
    }
    println!(
        "start (first inner turning point, model units: length {:.4} mm, time {:.6} s): theta0 = {:.5}, phidot0 = {:.5}, psidot0 = {:.5}, thetadot0 = {:.2e}, phi0 = {:.4}",
        r.units.length_mm,
        r.units.time_s,
        r.start.theta,
        r.start.phi_dot,
        r.start.psi_dot,
        r.start.theta_dot,
        report.phi0
    );
    println!(
        "misfit {:.4} px rms over {} mark coordinates ({} segments of {} frames, {} parameters); pixel noise in the data {}",
        r.rms_px,
        r.residual_count,
        r.segments.len(),
        r.segments.first().map_or(0, |s| s.len()),
        r.parameter_count,
        r.noise_px.map_or("unknown".into(), |n| format!("{n:.3} px"))
    );
    println!("{} iterations, {:.2} s", r.iterations, r.compute_seconds);
    Ok(())
}
