//! `ringlab recover`: the motion recovered from a recording, frame by frame.

use anyhow::{Context, Result};
use clap::Args;
use ringlab::physics::TurnKind;
use ringlab::recording::motion_table::write_motion_csv;
use ringlab::recording::recover;
use serde::Serialize;
use std::io::{BufWriter, Write};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct RecoverArgs {
    /// The recording (format v1, or a tracker's file: see `ringlab import --help`)
    #[arg(value_name = "FILE")]
    pub file: PathBuf,
    #[command(flatten)]
    pub import: super::import_args::ImportArgs,
    /// Write the motion frame by frame (A, angles, v_p with sigmas; mm, s and model units)
    #[arg(long, value_name = "MOTION.csv")]
    pub out: Option<PathBuf>,
    /// Print the summary as one JSON object
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct TurnJson {
    kind: &'static str,
    frame: f64,
    frame_sigma: f64,
    t_s: f64,
    theta: f64,
    theta_sigma: f64,
}

#[derive(Serialize)]
struct RecoverReport {
    frames: usize,
    noise_px: Option<f64>,
    pose_scatter_px: Option<f64>,
    mark_order: &'static str,
    spin: &'static str,
    first_inner_turn: Option<TurnJson>,
    rest_from_frame: Option<u64>,
    time_unit_s: f64,
    length_unit_mm: f64,
    turning_points: Vec<TurnJson>,
}

pub fn run(args: &RecoverArgs) -> Result<()> {
    let rec = super::import_args::load_one(&args.import, &args.file)?;
    let m = recover(&rec)
        .with_context(|| format!("recovering the motion in {}", args.file.display()))?;
    let first = rec.first_frame as f64;
    let turn = |p: &ringlab::recording::recover::DataTurningPoint| TurnJson {
        kind: if p.kind == TurnKind::ThetaMin { "theta_min" } else { "theta_max" },
        frame: first + p.at,
        frame_sigma: p.at_sigma,
        t_s: p.t_s,
        theta: p.theta,
        theta_sigma: p.theta_sigma,
    };
    let report = RecoverReport {
        frames: m.frames.len(),
        noise_px: m.noise_px,
        pose_scatter_px: m.pose_scatter_px,
        mark_order: m.mark_order.name(),
        spin: if m.spin_sign > 0.0 {
            "counter-clockwise seen from above"
        } else {
            "clockwise seen from above"
        },
        first_inner_turn: m.first_inner_turn.as_ref().map(turn),
        rest_from_frame: m.rest_from.map(|i| rec.frame_number(i)),
        time_unit_s: m.units.time_s,
        length_unit_mm: m.units.length_mm,
        turning_points: m.turning_points.iter().map(turn).collect(),
    };
    if let Some(path) = &args.out {
        let file = std::fs::File::create(path)
            .with_context(|| format!("cannot create {}", path.display()))?;
        let mut w = BufWriter::new(file);
        write_motion_csv(&mut w, &m, rec.first_frame)
            .with_context(|| format!("writing {}", path.display()))?;
        w.flush().with_context(|| format!("writing {}", path.display()))?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    println!("{}: {} frames at {} fps", args.file.display(), report.frames, rec.header.fps);
    println!(
        "pixel noise {}",
        report.noise_px.map_or("unknown (too few marks tracked)".into(), |n| format!("{n:.3} px"))
    );
    if let Some(note) = m.pose_scatter_note() {
        println!("{note}");
    }
    println!("marks numbered {}; the ring spins {}", report.mark_order, report.spin);
    match &report.first_inner_turn {
        Some(t) => println!(
            "first inner turning point: frame {:.2}, theta = {:.4} +- {:.4} rad",
            t.frame, t.theta, t.theta_sigma
        ),
        None => println!("no inner turning point found"),
    }
    let (mins, maxs) = m.turning_points.iter().fold((0, 0), |(a, b), p| {
        if p.kind == TurnKind::ThetaMin { (a + 1, b) } else { (a, b + 1) }
    });
    println!("{} turning points ({mins} theta minima, {maxs} maxima)", m.turning_points.len());
    match report.rest_from_frame {
        Some(f) => println!("still from frame {f}"),
        None => println!("the ring does not come to rest in the recording"),
    }
    Ok(())
}
