//! The integrator's figures of `ringlab bench` without the app's build: the right-hand side,
//! one sine and cosine, and the paper's ring from start to flat at rtol 1e-10.
//!
//!     cargo run --release -p ringlab-core --example integrator_speed [EVALUATIONS [RUNS]]

use ringlab_core::physics::integrator::Tolerances;
use ringlab_core::physics::speed::{fastest, median, rhs_ns, sin_cos_ns, time_runs};
use ringlab_core::physics::{RunOptions, paper};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1).map(|a| a.parse::<usize>());
    let evaluations = args.next().transpose()?.unwrap_or(2_000_000);
    let runs = args.next().transpose()?.unwrap_or(51);
    let model = paper::ring_model(paper::C_RING);
    let initial = paper::initial();
    if evaluations > 0 {
        let y0 = initial.to_state();
        println!("right-hand side: {:.1} ns per evaluation", rhs_ns(&model, &y0, evaluations));
        println!("sin_cos:         {:.1} ns per sine and cosine", sin_cos_ns(evaluations));
    }
    if runs > 0 {
        let tol = Tolerances { rtol: 1e-10, atol: 1e-12 };
        let opts =
            RunOptions { tol, sample_dt: None, track_validity: false, ..RunOptions::default() };
        let (times, s) = time_runs(&model, &initial, &opts, runs)?;
        println!(
            "run to flat:     {:.3} ms median of {runs}, fastest {:.3} ms ({} evaluations, {} steps + {} rejected, ended {} at t = {:?})",
            median(&times),
            fastest(&times),
            s.stats.rhs_evaluations,
            s.stats.steps,
            s.stats.rejected,
            s.end_reason.as_str(),
            s.t_end
        );
    }
    Ok(())
}
