//! `ringlab synth`: a recording (format v1) made from the model.

use super::case_args::CaseArgs;
use super::effect_args::{SlipStartArg, slip_start_for};
use anyhow::{Context, Result, bail};
use clap::Args;
use ringlab::physics::EffectKind;
use ringlab::recording::marks::MarkOrder;
use ringlab::recording::synth::{SynthOptions, synthesize};
use ringlab::recording::write_recording;
use std::io::{BufWriter, Write};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct SynthArgs {
    #[command(flatten)]
    pub case: CaseArgs,
    /// Gaussian noise on each pixel coordinate (px)
    #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
    pub noise_px: f64,
    /// Frame rate (frames per second)
    #[arg(long, default_value_t = 300.0, allow_negative_numbers = true)]
    pub fps: f64,
    /// Scale at the table (px per mm); default the paper's 135.6 px = 40.3 mm
    #[arg(long, default_value_t = 3.364764, allow_negative_numbers = true)]
    pub px_per_mm: f64,
    /// Radial lens distortion k1 (relative to the image half-diagonal; negative: barrel)
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub lens_k1: f64,
    /// An effect beyond the baseline model: none, reynolds_drag, rolling_friction,
    /// pivot_friction, slip, translational_drag, camera_distortion
    #[arg(long, value_name = "NAME")]
    pub effect: Option<String>,
    /// Strength of --effect (see `physics::effects` for each effect's meaning)
    #[arg(long, value_name = "X", allow_negative_numbers = true, requires = "effect")]
    pub effect_strength: Option<f64>,
    /// The --effect's extra numbers beyond its strength, in order (repeatable; `ringlab
    /// effects` lists them: table_slope's direction in degrees, ...)
    #[arg(long, value_name = "X", allow_negative_numbers = true, requires = "effect")]
    pub effect_extra: Vec<f64>,
    /// With --effect slip: how a start that needs more friction than mu F_N begins: cone
    /// (slides at once) or held (rolls on until it needs no more)
    #[arg(long, value_enum, value_name = "HOW")]
    pub slip_start: Option<SlipStartArg>,
    /// Seed of the pixel noise
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Frames of the ring lying still after the motion ends
    #[arg(long, default_value_t = 60)]
    pub rest_frames: usize,
    /// Image size in pixels as WIDTHxHEIGHT (the table's origin is at its centre)
    #[arg(long, default_value = "1280x1024", value_name = "WxH")]
    pub image: String,
    /// Probability that a mark is not tracked in a frame
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub drop_marks: f64,
    /// Number the marks counter-clockwise seen from above (the sample runs clockwise)
    #[arg(long)]
    pub reverse_marks: bool,
    /// Film through a pinhole camera this far from the table (mm, along its optical axis);
    /// default: orthographic
    #[arg(long, value_name = "D", allow_negative_numbers = true)]
    pub camera_distance_mm: Option<f64>,
    /// Tilt of the camera's axis from the table normal (degrees, about the image's horizontal
    /// axis; positive: the camera towards the table's +Y)
    #[arg(long, default_value_t = 0.0, value_name = "T", allow_negative_numbers = true)]
    pub camera_tilt_deg: f64,
    /// Write the camera's distance and tilt into the header (by default it does not say)
    #[arg(long)]
    pub camera_in_header: bool,
    /// Output file (format v1); '-' for standard output
    #[arg(long, value_name = "FILE.csv")]
    pub out: PathBuf,
}

fn parse_image(s: &str) -> Result<(f64, f64)> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .with_context(|| format!("--image '{s}': expected WIDTHxHEIGHT, e.g. 1280x1024"))?;
    let w: f64 =
        w.trim().parse().with_context(|| format!("--image '{s}': width is not a number"))?;
    let h: f64 =
        h.trim().parse().with_context(|| format!("--image '{s}': height is not a number"))?;
    Ok((w, h))
}

/// The camera, where it is not the default orthographic one.
fn camera_note(opts: &SynthOptions) -> String {
    if opts.camera_distance_mm.is_none() && opts.camera_tilt_deg == 0.0 {
        return String::new();
    }
    let distance = opts
        .camera_distance_mm
        .map_or("orthographic".to_string(), |d| format!("pinhole at {d} mm"));
    let header = if opts.camera_in_header { "in the header" } else { "not in the header" };
    format!("; camera {distance}, tilt {} deg ({header})", opts.camera_tilt_deg)
}

pub fn run(args: &SynthArgs) -> Result<()> {
    let mut case = args.case.case()?;
    let effect = match (&args.effect, args.effect_strength) {
        (None, _) => None,
        (Some(name), strength) => {
            let kind = EffectKind::from_name(name).with_context(|| {
                let names: Vec<&str> = EffectKind::ALL.iter().map(|k| k.name()).collect();
                format!("--effect '{name}' is not one of {}", names.join(", "))
            })?;
            match (kind, strength) {
                (EffectKind::None, _) => None,
                (_, None) => {
                    bail!("--effect {name} needs --effect-strength X ({})", kind.parameter())
                }
                (_, Some(x)) => Some((kind, x)),
            }
        }
    };
    let slip = effect.is_some_and(|(k, _)| k == EffectKind::Slip);
    if let Some(start) = slip_start_for(args.slip_start, slip)? {
        case.model.effects.slip_start = start;
    }
    let (image_width_px, image_height_px) = parse_image(&args.image)?;
    let opts = SynthOptions {
        fps: args.fps,
        px_per_mm: args.px_per_mm,
        noise_px: args.noise_px,
        lens_k1: args.lens_k1,
        effect,
        effect_extras: args.effect_extra.clone(),
        seed: args.seed,
        rest_frames: args.rest_frames,
        image_width_px,
        image_height_px,
        mark_order: if args.reverse_marks { MarkOrder::Reverse } else { MarkOrder::Forward },
        missing_fraction: args.drop_marks,
        camera_distance_mm: args.camera_distance_mm,
        camera_tilt_deg: args.camera_tilt_deg,
        camera_in_header: args.camera_in_header,
    };
    let synth = synthesize(&case, &opts)
        .with_context(|| format!("synthesizing a recording of case '{}'", case.name))?;
    let rec = &synth.recording;
    if args.out.as_os_str() == "-" {
        let stdout = std::io::stdout();
        let mut w = BufWriter::new(stdout.lock());
        write_recording(&mut w, rec).context("writing the recording to standard output")?;
        w.flush()?;
    } else {
        let file = std::fs::File::create(&args.out)
            .with_context(|| format!("cannot create {}", args.out.display()))?;
        let mut w = BufWriter::new(file);
        write_recording(&mut w, rec).with_context(|| format!("writing {}", args.out.display()))?;
        w.flush().with_context(|| format!("writing {}", args.out.display()))?;
    }
    let moving = synth.samples.len()
        - if synth.summary.end_reason.is_natural() { args.rest_frames } else { 0 };
    eprintln!(
        "{}: {} frames at {} fps ({} moving, then {}); run ended {} at t = {:.4} ({:.3} s); noise {} px{}{}{}",
        args.out.display(),
        rec.frames.len(),
        args.fps,
        moving,
        if synth.summary.end_reason.is_natural() {
            format!("{} at rest", args.rest_frames)
        } else {
            "none at rest".into()
        },
        synth.summary.end_reason,
        synth.summary.t_end,
        synth.summary.t_end * synth.time_s,
        args.noise_px,
        effect.map(|(k, x)| format!("; effect {k} = {x}")).unwrap_or_default(),
        if synth.camera.k1 != 0.0 {
            format!("; lens k1 = {}", synth.camera.k1)
        } else {
            String::new()
        },
        camera_note(&opts),
    );
    Ok(())
}
