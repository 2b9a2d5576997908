//! The paper's phenomena: the ring's retrograde turn and the disk's prograde spiral, the sign
//! of F_f at the theta_max turning points (Fig. 4), energy, and mirror symmetry.

use ringlab_core::physics::integrator::Tolerances;
use ringlab_core::physics::motion::{Phase, analyze};
use ringlab_core::physics::{Initial, RunOptions, Sample, paper, simulate};

fn run(
    c: [f64; 3],
    initial: &Initial,
    dt: f64,
) -> (ringlab_core::physics::RunSummary, Vec<Sample>) {
    let opts = RunOptions { sample_dt: Some(dt), ..Default::default() };
    simulate(paper::ring_model(c), initial, opts).expect("runs")
}

#[test]
fn ring_drag_makes_prograde_cycles_a_walk_then_a_retrograde_turn() {
    let (summary, samples) = run(paper::C_RING, &paper::initial(), 0.05);
    let m = analyze(&samples[0], &summary.turning_points, summary.t_end);
    assert!(m.retrograde_turn, "no retrograde turn: {:?}", m.phases);
    let order: Vec<Phase> = m.phases.iter().map(|p| p.phase).collect();
    assert_eq!(order, vec![Phase::Prograde, Phase::Walk, Phase::Retrograde]);
    // Several prograde cycles before the walk, and the inflection well inside the run.
    assert!(m.prograde_cycles >= 5, "only {} prograde cycles", m.prograde_cycles);
    assert!(m.cycles_before_retrograde > m.prograde_cycles);
    let t_infl = m.inflection_time.expect("an inflection");
    assert!(t_infl > 10.0 && t_infl < 0.5 * summary.t_end, "inflection at {t_infl}");
    // The terminal spiral turns back by more than a full revolution.
    assert!(
        m.retrograde_total_deg > 360.0,
        "retrograde turning only {} deg",
        m.retrograde_total_deg
    );
}

#[test]
fn ring_friction_at_theta_max_flips_from_positive_to_negative() {
    let (summary, samples) = run(paper::C_RING, &paper::initial(), 0.05);
    let m = analyze(&samples[0], &summary.turning_points, summary.t_end);
    let ff: Vec<f64> = m.theta_max_points.iter().map(|p| p.f_f).collect();
    assert!(ff.len() > 20);
    assert!(ff[0] > 0.5, "F_f at the first theta_max is {}", ff[0]);
    let flip = ff.iter().position(|&f| f < 0.0).expect("F_f turns negative");
    assert!(ff[flip..].iter().all(|&f| f < 0.0), "F_f does not stay negative after the flip");
    // The flip comes before the inflection of the mean path (it causes it).
    let t_flip = m.theta_max_points[flip].t;
    assert!(t_flip < m.inflection_time.expect("inflection"), "flip at {t_flip}");
}

#[test]
fn disk_like_drag_spirals_prograde_with_positive_friction() {
    let (summary, samples) = run(paper::C_DISK_LIKE, &paper::initial(), 0.05);
    let m = analyze(&samples[0], &summary.turning_points, summary.t_end);
    assert!(!m.retrograde_turn, "disk-like drag turned back: {:?}", m.phases);
    assert!(m.phases.iter().all(|p| p.phase == Phase::Prograde), "{:?}", m.phases);
    assert!(m.cycles.iter().skip(1).all(|c| c.turn_deg > 0.0), "a cycle turned retrograde");
    assert!(m.theta_max_points.iter().all(|p| p.f_f > 0.0), "F_f at theta_max went negative");
}

#[test]
fn energy_never_increases_with_drag() {
    for c in [paper::C_RING, paper::C_DISK_LIKE, [0.01, 0.3, 0.02]] {
        let (_, samples) = run(c, &paper::initial(), 0.01);
        for w in samples.windows(2) {
            assert!(
                w[1].energy <= w[0].energy + 1e-12 * w[0].energy.abs(),
                "C = {c:?}: energy rose from {} to {} at t = {}",
                w[0].energy,
                w[1].energy,
                w[1].t
            );
        }
    }
}

#[test]
fn reversed_spin_gives_the_mirrored_path() {
    // Reflection in the vertical plane through C that holds the ring's axis: rates of the
    // angles about Z and e2 change sign, theta and theta' do not.
    let a0 = paper::initial();
    let b0 = Initial { phi_dot: -a0.phi_dot, psi_dot: -a0.psi_dot, ..a0 };
    let (sa, pa) = run(paper::C_RING, &a0, 0.05);
    let (sb, pb) = run(paper::C_RING, &b0, 0.05);
    assert!((sa.t_end - sb.t_end).abs() < 1e-6 * sa.t_end);
    // Mirror line through the origin along E2' = (-sin phi0, cos phi0).
    let (ux, uy) = (-a0.phi.sin(), a0.phi.cos());
    let mirror = |x: f64, y: f64| {
        let d = x * ux + y * uy;
        (2.0 * d * ux - x, 2.0 * d * uy - y)
    };
    let n = pa.len().min(pb.len());
    let mut worst: f64 = 0.0;
    for (a, b) in pa[..n].iter().zip(&pb[..n]) {
        assert!((a.theta() - b.theta()).abs() < 1e-6, "theta differs at t = {}", a.t);
        let (mx, my) = mirror(a.x_a, a.y_a);
        worst = worst.max((mx - b.x_a).hypot(my - b.y_a));
    }
    assert!(worst < 1e-5, "mirrored path off by {worst}");
    let ma = analyze(&pa[0], &sa.turning_points, sa.t_end);
    let mb = analyze(&pb[0], &sb.turning_points, sb.t_end);
    assert_eq!(ma.spin_sign, -mb.spin_sign);
    assert_eq!(ma.retrograde_turn, mb.retrograde_turn);
    assert_eq!(ma.prograde_cycles, mb.prograde_cycles);
}

#[test]
fn without_drag_energy_is_conserved_and_the_orbit_stays_quasi_periodic() {
    let opts = RunOptions {
        t_end: 1000.0,
        sample_dt: Some(0.5),
        tol: Tolerances { rtol: 1e-12, atol: 1e-14 },
        ..Default::default()
    };
    let (summary, samples) =
        simulate(paper::ring_model([0.0; 3]), &paper::initial(), opts).expect("runs");
    assert_eq!(summary.end_reason, ringlab_core::physics::EndReason::TEnd);
    let e0 = samples[0].energy;
    let drift = samples.iter().map(|s| ((s.energy - e0) / e0).abs()).fold(0.0, f64::max);
    assert!(drift < 1e-7, "relative energy drift {drift:e}");
    // Bounded: A stays within a fixed annulus (Fig. 1b), and theta keeps oscillating
    // between the same limits.
    let r_max = samples.iter().map(|s| s.x_a.hypot(s.y_a)).fold(0.0, f64::max);
    assert!(r_max < 10.0, "path wandered to {r_max}");
    let m = analyze(&samples[0], &summary.turning_points, summary.t_end);
    assert!(!m.retrograde_turn);
    let th_max: Vec<f64> = m.theta_max.iter().map(|p| p.1).collect();
    let spread = th_max.iter().cloned().fold(f64::MIN, f64::max)
        - th_max.iter().cloned().fold(f64::MAX, f64::min);
    assert!(
        th_max.len() > 300 && spread < 1e-6,
        "theta_max varies by {spread} over {} cycles",
        th_max.len()
    );
}
