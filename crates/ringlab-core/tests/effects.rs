//! The effects beyond the paper's model (issue 5) on the paper's ring: each reduces to the
//! baseline at strength zero, never raises the energy, has its defining property, and changes
//! the run in the physically expected way. (The sliding contact has its own file, slip.rs.)

use ringlab_core::physics::effects::apply;
use ringlab_core::physics::motion::analyze;
use ringlab_core::physics::{
    EffectKind, Effects, Initial, Model, RunOptions, RunSummary, Sample, Units, paper, simulate,
};

fn paper_model(kind: EffectKind, strength: f64) -> Model {
    let base = paper::ring_model(paper::C_RING);
    let s0 = Sample::new(&base, 0.0, &paper::initial().to_state());
    let mut e = Effects::default();
    apply(kind, strength, base.body.r, s0.reynolds, &mut e).expect("valid strength");
    base.with_effects(e).expect("valid effects")
}

fn run_model(model: Model, initial: &Initial, dt: f64, t_end: f64) -> (RunSummary, Vec<Sample>) {
    let opts = RunOptions { sample_dt: Some(dt), t_end, ..Default::default() };
    simulate(model, initial, opts).expect("runs")
}

fn run(kind: EffectKind, strength: f64, dt: f64) -> (RunSummary, Vec<Sample>) {
    run_model(paper_model(kind, strength), &paper::initial(), dt, 1000.0)
}

const ROLLING_EFFECTS: [EffectKind; 4] = [
    EffectKind::ReynoldsDrag,
    EffectKind::RollingFriction,
    EffectKind::PivotFriction,
    EffectKind::TranslationalDrag,
];

#[test]
fn every_effect_at_strength_zero_is_the_baseline_bit_for_bit() {
    let (base, pb) = run(EffectKind::None, 0.0, 0.05);
    for kind in ROLLING_EFFECTS {
        let (s, p) = run(kind, 0.0, 0.05);
        assert_eq!(s.t_end, base.t_end, "{kind}");
        assert_eq!(s.stats, base.stats, "{kind}");
        assert!(p.iter().zip(&pb).all(|(a, b)| a.y == b.y && a.energy == b.energy), "{kind}");
    }
}

#[test]
fn the_cold_path_at_vanishing_strength_is_the_fast_path() {
    // Tiny contact terms take the other branch of the right-hand side (closed-form F_N, air
    // drag on C); it must give the same dynamics to rounding, and the same run to the
    // integrator's accuracy (its steps differ, so the runs differ at the level of rtol,
    // amplified along the run as in any comparison of two integrations).
    let e = Effects {
        rolling_friction: 1e-15,
        pivot_friction: 1e-15,
        translational_drag: 1e-15,
        ..Default::default()
    };
    let slow = paper::ring_model(paper::C_RING).with_effects(e).unwrap();
    let fast = paper::ring_model(paper::C_RING);
    for k in 0..100 {
        let x = k as f64;
        let theta = 0.05 + 1.45 * (0.37 * x).sin().abs();
        let w =
            nalgebra::Vector3::new((1.3 * x).sin(), 3.0 * (0.7 * x).cos(), 2.0 * (0.23 * x).sin());
        let (a, b) = (fast.dynamics(theta, &w), slow.dynamics(theta, &w));
        assert!((a.omega_dot - b.omega_dot).norm() <= 1e-13 * (1.0 + a.omega_dot.norm()));
        assert!((a.force - b.force).norm() <= 1e-13 * (1.0 + a.force.norm()));
    }
    let (a, pa) = run_model(paper::ring_model(paper::C_RING), &paper::initial(), 0.1, 40.0);
    let (b, pb) = run_model(slow, &paper::initial(), 0.1, 40.0);
    assert_eq!(a.turning_points.len(), b.turning_points.len());
    let worst = pa
        .iter()
        .zip(&pb)
        .map(|(x, y)| (0..8).map(|i| (x.y[i] - y.y[i]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max);
    assert!(worst < 1e-6, "cold path departs by {worst:e}");
}

#[test]
fn no_effect_ever_raises_the_energy() {
    for kind in ROLLING_EFFECTS {
        let (_, hi) = kind.realistic_range();
        for strength in [hi, 3.0 * hi] {
            let (_, samples) = run(kind, strength, 0.01);
            for w in samples.windows(2) {
                assert!(
                    w[1].energy <= w[0].energy + 1e-12 * w[0].energy.abs(),
                    "{kind} {strength}: energy rose from {} to {} at t = {}",
                    w[0].energy,
                    w[1].energy,
                    w[1].t
                );
            }
        }
    }
}

#[test]
fn reynolds_drag_scales_the_coefficients_as_re_to_the_minus_n() {
    let n = 0.5;
    let m = paper_model(EffectKind::ReynoldsDrag, n);
    let re_ref = m.effects.reynolds_drag.expect("on").re_ref;
    let start = Sample::new(&m, 0.0, &paper::initial().to_state());
    assert!((re_ref - start.reynolds).abs() < 1e-9 * re_ref, "the reference is the start");
    // At any state the drag is the paper's with every C_i multiplied by (Re_ref / Re)^n.
    for (theta, w) in [(0.7, [0.3, 2.0, 1.5]), (1.2, [-0.2, 0.4, 0.3]), (1.45, [0.05, 0.1, 0.05])] {
        let w = nalgebra::Vector3::new(w[0], w[1], w[2]);
        let d = m.dynamics(theta, &w);
        let re = m.reynolds(d.v_c.norm());
        let k = (re_ref / re).powf(n);
        let mut scaled = paper::ring_model(paper::C_RING);
        scaled.c_drag = paper::C_RING.map(|c| c * k);
        let expected = scaled.dynamics(theta, &w);
        assert!((d.omega_dot - expected.omega_dot).norm() < 1e-14, "Re {re}");
        assert!((k > 1.0) == (re < re_ref), "more drag exactly when slower than at the start");
    }
    // Bounded at low Re.
    let r = m.effects.reynolds_drag.unwrap();
    assert_eq!(r.factor(0.0), r.max_factor);
    assert_eq!(r.factor(1e-6 * re_ref), r.max_factor);
    assert!((r.factor(re_ref / 4.0) - 2.0).abs() < 1e-12);
}

#[test]
fn reynolds_drag_on_the_rim_speed_follows_omega_r_and_a_share_blends_the_squares() {
    let n = 0.5;
    let centre = paper_model(EffectKind::ReynoldsDrag, n);
    let re_ref = centre.effects.reynolds_drag.expect("on").re_ref;
    let with_share = |share: f64| {
        let mut e = centre.effects;
        e.reynolds_drag =
            e.reynolds_drag.map(|r| ringlab_core::physics::ReynoldsDrag { rim_share: share, ..r });
        centre.clone().with_effects(e).expect("a share in [0, 1]")
    };
    let (rim, half) = (with_share(1.0), with_share(0.5));
    for (theta, w) in [(0.7, [0.3, 2.0, 1.5]), (1.2, [-0.2, 0.4, 0.3]), (1.45, [0.05, 0.1, 3.0])] {
        let w = nalgebra::Vector3::new(w[0], w[1], w[2]);
        let v_c = centre.dynamics(theta, &w).v_c;
        let (u_c, u_rim) = (v_c.norm(), w.norm() * centre.body.r);
        for (m, u) in
            [(&centre, u_c), (&rim, u_rim), (&half, (0.5 * u_c * u_c + 0.5 * u_rim * u_rim).sqrt())]
        {
            let k = (re_ref / m.reynolds(u)).powf(n).min(10.0);
            let got = m.drag_coefficients(&v_c, &w);
            for i in 0..3 {
                assert!((got[i] - paper::C_RING[i] * k).abs() < 1e-12 * got[i], "U {u}");
            }
        }
    }
    // Spinning about the line from contact to centre moves the rim and not the centre: the
    // paper's law sees no flow there, the rim's does.
    let spin = nalgebra::Vector3::new(0.0, 0.0, 5.0);
    let still = nalgebra::Vector3::zeros();
    assert_eq!(centre.drag_coefficients(&still, &spin)[0], 10.0 * paper::C_RING[0]);
    assert!(rim.drag_coefficients(&still, &spin)[0] < 10.0 * paper::C_RING[0]);
    // A share outside [0, 1] is refused by name.
    let mut e = centre.effects;
    e.reynolds_drag =
        e.reynolds_drag.map(|r| ringlab_core::physics::ReynoldsDrag { rim_share: 1.5, ..r });
    let err = centre.clone().with_effects(e).expect_err("out of range");
    assert!(err.to_string().contains("rim_share"), "{err}");
}

#[test]
fn reynolds_drag_is_the_same_run_in_physical_units() {
    // Re is physical, so the effect must not depend on the unit system.
    let case = ringlab_core::config::load_preset("paper-ring").unwrap().build().unwrap();
    let mut model_case = case.clone();
    model_case.model = paper_model(EffectKind::ReynoldsDrag, 0.5);
    let mm_case = model_case.in_units(Units::MM_S).unwrap();
    let (a, _) =
        simulate(model_case.model.clone(), &model_case.initial, model_case.opts.clone()).unwrap();
    let (b, _) = simulate(mm_case.model.clone(), &mm_case.initial, mm_case.opts.clone()).unwrap();
    let t0 = model_case.units.time_s;
    assert!(
        (b.t_end - a.t_end * t0).abs() < 1e-6 * b.t_end,
        "{} s vs {} model units",
        b.t_end,
        a.t_end
    );
}

#[test]
fn reynolds_drag_shortens_the_terminal_spiral() {
    // The paper's explanation of the long-lived simulated spiral: C_i grow as Re falls.
    let (base, pb) = run(EffectKind::None, 0.0, 0.05);
    let (s, p) = run(EffectKind::ReynoldsDrag, 0.5, 0.05);
    let mb = analyze(&pb[0], &base.turning_points, base.t_end);
    let m = analyze(&p[0], &s.turning_points, s.t_end);
    assert!(m.retrograde_turn, "the ring still turns back");
    assert!(s.t_end < 0.7 * base.t_end, "ends at {} (baseline {})", s.t_end, base.t_end);
    assert!(m.retrograde_total_deg < 0.6 * mb.retrograde_total_deg);
    // The start is the same (factor 1 at Re_ref).
    assert!((p[1].x_a - pb[1].x_a).abs() < 1e-4);
}

#[test]
fn rolling_and_pivot_friction_shorten_the_run_in_order_of_strength() {
    let (base, _) = run(EffectKind::None, 0.0, 0.5);
    for kind in [EffectKind::RollingFriction, EffectKind::PivotFriction] {
        let (lo, hi) = kind.realistic_range();
        let ends: Vec<f64> =
            [lo, (lo * hi).sqrt(), hi].iter().map(|&k| run(kind, k, 0.5).0.t_end).collect();
        assert!(ends[0] < 0.98 * base.t_end, "{kind}: {ends:?} vs {}", base.t_end);
        assert!(ends[0] > ends[1] && ends[1] > ends[2], "{kind}: {ends:?}");
        assert!(ends[2] < 0.65 * base.t_end, "{kind}: {ends:?}");
    }
}

#[test]
fn translational_drag_slows_the_centre_of_mass() {
    // Quadratic drag on C: the centre of mass covers less ground; the path drifts.
    let path = |p: &[Sample], t_max: f64| -> f64 {
        p.windows(2)
            .filter(|w| w[1].t <= t_max)
            .map(|w| (w[1].x_c() - w[0].x_c()).hypot(w[1].y_c() - w[0].y_c()))
            .sum()
    };
    let (base, pb) = run(EffectKind::None, 0.0, 0.01);
    let (lo, hi) = EffectKind::TranslationalDrag.realistic_range();
    let (s_lo, p_lo) = run(EffectKind::TranslationalDrag, lo, 0.01);
    let (s_hi, p_hi) = run(EffectKind::TranslationalDrag, hi, 0.01);
    let (l0, l1, l2) = (path(&pb, 50.0), path(&p_lo, 50.0), path(&p_hi, 50.0));
    assert!(l0 > l1 && l1 > l2 && l2 < 0.8 * l0, "paths {l0} {l1} {l2}");
    let drift = |s: &RunSummary| {
        (s.final_sample.x_a - base.final_sample.x_a)
            .hypot(s.final_sample.y_a - base.final_sample.y_a)
    };
    assert!(drift(&s_lo) > 0.3, "end point moved only {}", drift(&s_lo));
    assert!(drift(&s_hi) > 2.0, "end point moved only {}", drift(&s_hi));
}

#[test]
fn every_realistic_strength_changes_the_run_visibly() {
    // What the diagnosis relies on: at the low end of each range the path of A departs from
    // the baseline by at least 0.2 mean radii at some time of the run (4 mm, 13 px in the
    // paper's video at 135.6 px per 40.3 mm; the recordings' noise is 0.5 px).
    let (_, pb) = run(EffectKind::None, 0.0, 0.05);
    for kind in ROLLING_EFFECTS {
        let (lo, _) = kind.realistic_range();
        let (_, p) = run(kind, lo, 0.05);
        let worst = p
            .iter()
            .zip(&pb)
            .map(|(a, b)| (a.x_a - b.x_a).hypot(a.y_a - b.y_a))
            .fold(0.0, f64::max);
        assert!(worst > 0.2, "{kind} at {lo}: A departs by at most {worst} mean radii");
    }
}
