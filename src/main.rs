#![cfg_attr(windows, windows_subsystem = "windows")]
//! The `ringlab` command: without a subcommand it opens the window (`--config CASE.toml`: with
//! that case); subcommands run headless.

mod cli;

use anyhow::Result;
use clap::{Parser, Subcommand};

#[derive(Parser, Debug)]
#[command(
    name = "ringlab",
    version,
    about = "Rolling rings and disks: the terminal retrograde turn, simulated and explained"
)]
#[command(args_conflicts_with_subcommands = true)]
struct Cli {
    /// Open the window with this case (a TOML file of the presets' shape, as File > Save case
    /// writes it) instead of the one kept from the last session
    #[arg(long, value_name = "CASE.toml")]
    config: Option<std::path::PathBuf>,
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run the model once; write samples as CSV and a summary
    Simulate(cli::simulate::SimulateArgs),
    /// Run a grid of drag coefficients and classify each run
    Sweep(cli::sweep::SweepArgs),
    /// Make a recording (format v1) from the model: marks, camera, noise, effects
    Synth(cli::synth::SynthArgs),
    /// Find the four marks in a film (a video or a folder of frames) and write a recording
    Track(cli::track::TrackArgs),
    /// Recover the motion from a recording: A, theta, psi, heading, v_p, turning points
    Recover(cli::recover::RecoverArgs),
    /// Write a lab tracker's files (DeepLabCut, Tracker, TrackMate, a plain CSV) as a recording
    Import(cli::import::ImportCmdArgs),
    /// Fit the model (drag C1..C3 and the start state) to a recording
    Fit(cli::fit::FitArgs),
    /// Name the physics the model left out of a recording (or none), show the fit improve
    Diagnose(cli::diagnose_args::DiagnoseArgs),
    /// The diagnosis on recordings with a concealed effect: hit rates, misfits, false alarms
    DiagnoseBench(cli::diagnose_bench::DiagnoseBenchArgs),
    /// Measure the speed of the physics core
    Bench(cli::bench::BenchArgs),
    /// Measure the speed of the visualizer (offscreen, the integrator thread, the window)
    BenchView(cli::bench_view::BenchViewArgs),
    /// Draw a picture without a window (the 3D scene, the trace panel or the whole app)
    Render(cli::render::RenderArgs),
    /// List the presets
    Presets,
    /// List the effects beyond the paper's model, their strengths and realistic ranges
    Effects,
}

fn main() -> Result<()> {
    cli::windows_console::attach();
    let cli = Cli::parse();
    match cli.command {
        Some(Command::Simulate(a)) => cli::simulate::run(&a),
        Some(Command::Sweep(a)) => cli::sweep::run(&a),
        Some(Command::Synth(a)) => cli::synth::run(&a),
        Some(Command::Track(a)) => cli::track::run(&a),
        Some(Command::Recover(a)) => cli::recover::run(&a),
        Some(Command::Import(a)) => cli::import::run(&a),
        Some(Command::Fit(a)) => cli::fit::run(&a),
        Some(Command::Diagnose(a)) => cli::diagnose::run(&a),
        Some(Command::DiagnoseBench(a)) => cli::diagnose_bench::run(&a),
        Some(Command::Bench(a)) => cli::bench::run(&a),
        Some(Command::Effects) => {
            use ringlab::physics::EffectKind;
            for k in EffectKind::ALL {
                let (lo, hi) = k.realistic_range();
                println!("{:<20} {:<52} realistic {lo} .. {hi}", k.name(), k.parameter());
                for x in k.descriptor().extras {
                    let ((lo, hi), (a, b)) = (x.realistic, x.bounds);
                    println!(
                        "{:<20} + {:<50} realistic {lo} .. {hi}, bounds {a} .. {b}",
                        "", x.name
                    );
                }
            }
            Ok(())
        }
        Some(Command::Render(a)) => cli::render::run(&a),
        Some(Command::BenchView(a)) => cli::bench_view::run(&a),
        Some(Command::Presets) => {
            for name in ringlab::config::preset_names() {
                let f = ringlab::config::load_preset(name)?;
                println!("{name:<16} {}", f.description);
            }
            Ok(())
        }
        None => {
            // A bad file stops here, with its error, before any window opens.
            let case = cli.config.as_deref().map(ringlab::config::load_case_file).transpose()?;
            ringlab::ui::run_window(case)
                .map_err(|e| anyhow::anyhow!("cannot open the window: {e}"))
        }
    }
}
