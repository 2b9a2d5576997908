//! The sliding contact (issue 5, `slip`): Coulomb friction at the contact with real
//! rolling/sliding transitions.

use ringlab_core::physics::slip::{SLIDE_LEN, SlidingModel, painleve_mu_limit};
use ringlab_core::physics::{
    Body, Effects, EndReason, Initial, Model, RunOptions, RunSummary, Sample, Shape, Simulation,
    SlipStart, paper, simulate,
};

fn with_mu(model: Model, mu: f64) -> Model {
    let e = Effects { slip_mu: Some(mu), ..model.effects };
    model.with_effects(e).expect("valid mu")
}

fn run(model: Model, initial: &Initial, dt: f64) -> (RunSummary, Vec<Sample>) {
    simulate(model, initial, RunOptions { sample_dt: Some(dt), ..Default::default() })
        .expect("runs")
}

/// A gentle launch of the paper's ring: it never lifts off, and rolling needs at most 0.61
/// times F_N in friction over the whole run.
fn gentle() -> Initial {
    Initial { theta: 0.8, phi_dot: 3.0, psi_dot: -1.0, ..paper::initial() }
}

#[test]
fn with_friction_to_spare_it_never_slides_and_is_the_rolling_run() {
    let (roll, pr) = run(paper::ring_model(paper::C_RING), &gentle(), 0.05);
    let worst = pr.iter().map(|s| s.friction_ratio()).fold(0.0, f64::max);
    assert!(worst < 0.65 && roll.lift_off.is_empty(), "not a gentle case: {worst}");
    let (slip, ps) = run(with_mu(paper::ring_model(paper::C_RING), 0.9), &gentle(), 0.05);
    assert!(slip.sliding.is_empty(), "slid: {:?}", slip.sliding);
    assert_eq!(slip.t_end, roll.t_end);
    assert_eq!(ps.len(), pr.len());
    assert!(ps.iter().zip(&pr).all(|(a, b)| a.y == b.y && !a.sliding && a.slip_speed == 0.0));
}

#[test]
fn with_less_friction_it_slides_in_intervals_and_sticks_again() {
    let mu = 0.3;
    let (s, p) = run(with_mu(paper::ring_model(paper::C_RING), mu), &gentle(), 0.002);
    assert!(s.end_reason.is_natural(), "{:?}", s.end_reason);
    assert!(s.sliding.len() >= 2, "{:?}", s.sliding);
    let stuck = s.sliding.iter().filter(|i| i.end < s.t_end).count();
    assert!(stuck >= 2, "it does not stick again: {:?}", s.sliding);
    let inside = |t: f64| s.sliding.iter().any(|i| t > i.start && t < i.end);
    for x in &p {
        assert_eq!(
            x.sliding,
            inside(x.t) || x.sliding && s.sliding.iter().any(|i| x.t == i.start),
            "t = {}",
            x.t
        );
        if !x.sliding {
            assert_eq!(x.slip_speed, 0.0);
            // While rolling the friction is within the cone (the switch happens at its edge).
            assert!(x.friction_ratio() <= mu + 1e-6, "rolling outside the cone at t = {}", x.t);
        } else {
            // Kinetic friction: exactly mu F_N (the contact presses throughout this case).
            assert!((x.friction_ratio() - mu).abs() < 1e-9, "t = {}", x.t);
        }
    }
    // The run departs from the rolling one.
    let (roll, _) = run(paper::ring_model(paper::C_RING), &gentle(), 0.05);
    let drift = (s.final_sample.x_a - roll.final_sample.x_a)
        .hypot(s.final_sample.y_a - roll.final_sample.y_a);
    assert!(drift > 0.05, "drift {drift}");
}

#[test]
fn the_slip_speed_starts_and_ends_at_zero_and_is_continuous() {
    let m = with_mu(paper::ring_model(paper::C_RING), 0.3);
    let creep = SlidingModel::new(m.clone(), 0.3, [1.0, 0.0]).creep_speed();
    let (s, p) = run(m, &gentle(), 0.0005);
    let peak = p.iter().map(|x| x.slip_speed).fold(0.0, f64::max);
    assert!(peak > 1e-3, "hardly slides: {peak}");
    // A stick removes no more than creep-level slip (the plastic impulse of slip.rs).
    assert!(
        s.stick_residual <= creep && s.stick_residual < 0.05 * peak,
        "slip left at a stick: {} (creep {creep}, peak {peak})",
        s.stick_residual
    );
    // Continuous: no jump between samples beyond what the slip's rate allows.
    for w in p.windows(2) {
        assert!(
            (w[1].slip_speed - w[0].slip_speed).abs() < 0.01 * peak.max(1e-3) + 1e-4,
            "jump at t = {}",
            w[1].t
        );
    }
    // It rises from zero at each onset and falls to zero at each stick.
    for i in &s.sliding {
        let near = |t: f64| {
            p.iter()
                .filter(|x| x.sliding && (x.t - t).abs() < 2e-3)
                .map(|x| x.slip_speed)
                .fold(0.0, f64::max)
        };
        assert!(near(i.start) < 0.05 * peak, "onset at {}: {}", i.start, near(i.start));
        if i.end < s.t_end {
            assert!(near(i.end) < 0.05 * peak, "stick at {}: {}", i.end, near(i.end));
        }
    }
}

#[test]
fn sliding_never_raises_the_energy_and_lift_off_is_still_reported() {
    // The paper's own start: rolling would need 4.2 F_N in friction, and F_N falls below zero
    // three times before t = 1.8. With any mu the ring slides there.
    for mu in [0.25, 0.4, 1.0] {
        let (s, p) = run(with_mu(paper::ring_model(paper::C_RING), mu), &paper::initial(), 0.01);
        assert!(s.end_reason.is_natural(), "mu {mu}: {:?}", s.end_reason);
        assert!(!s.sliding.is_empty() && s.sliding[0].start == 0.0, "mu {mu}: {:?}", s.sliding);
        assert!(!s.lift_off.is_empty(), "mu {mu}: lift-off not reported");
        let lift_while_sliding =
            s.lift_off.iter().any(|l| s.sliding.iter().any(|i| l.start < i.end && l.end > i.start));
        assert!(lift_while_sliding, "mu {mu}");
        for w in p.windows(2) {
            assert!(
                w[1].energy <= w[0].energy + 1e-12 * w[0].energy.abs(),
                "mu {mu}: energy rose from {} to {} at t = {}",
                w[0].energy,
                w[1].energy,
                w[1].t
            );
        }
        assert!(s.slip.is_empty(), "the would-slip check belongs to pure rolling");
    }
}

#[test]
fn slippage_makes_the_paper_ring_drift() {
    // The paper's second suspect: slippage changes the direction of travel. With its own
    // table's mu = 0.4 the ring slides through the violent start and ends far from the
    // rolling model's end point.
    let (roll, _) = run(paper::ring_model(paper::C_RING), &paper::initial(), 0.05);
    let (s, _) = run(with_mu(paper::ring_model(paper::C_RING), 0.4), &paper::initial(), 0.05);
    let drift = (s.final_sample.x_a - roll.final_sample.x_a)
        .hypot(s.final_sample.y_a - roll.final_sample.y_a);
    assert!(drift > 2.0, "drift {drift} mean radii");
    assert!(s.sliding.iter().all(|i| i.end < 12.0), "slides late: {:?}", s.sliding);
}

#[test]
fn reversed_spin_gives_the_mirrored_sliding_run() {
    // Reflection in the vertical plane through C that holds the ring's axis (as for rolling,
    // paper_phenomena.rs): the sliding intervals are the same and the paths are mirror images.
    let a0 = paper::initial();
    let b0 = Initial { phi_dot: -a0.phi_dot, psi_dot: -a0.psi_dot, ..a0 };
    let (ux, uy) = (-a0.phi.sin(), a0.phi.cos());
    let mirror = |x: f64, y: f64| {
        let d = x * ux + y * uy;
        (2.0 * d * ux - x, 2.0 * d * uy - y)
    };
    for (initial_a, initial_b, mu, tol_t, tol_path) in [
        (
            gentle(),
            Initial { phi_dot: -gentle().phi_dot, psi_dot: -gentle().psi_dot, ..gentle() },
            0.3,
            1e-8,
            1e-6,
        ),
        (a0, b0, 0.4, 1e-8, 1e-5),
        (a0, b0, 0.25, 1e-6, 1e-5),
    ] {
        let m = with_mu(paper::ring_model(paper::C_RING), mu);
        let (sa, pa) = run(m.clone(), &initial_a, 0.05);
        let (sb, pb) = run(m, &initial_b, 0.05);
        assert_eq!(sa.sliding.len(), sb.sliding.len(), "mu {mu}");
        for (i, j) in sa.sliding.iter().zip(&sb.sliding) {
            assert!(
                (i.start - j.start).abs() < tol_t && (i.end - j.end).abs() < tol_t,
                "mu {mu}: {i:?} vs {j:?}"
            );
        }
        let mut worst: f64 = 0.0;
        for (a, b) in pa.iter().zip(&pb) {
            assert!(
                (a.theta() - b.theta()).abs() < tol_path,
                "mu {mu}: theta differs at t = {}",
                a.t
            );
            assert!(
                (a.slip_speed - b.slip_speed).abs() < tol_path,
                "mu {mu}: slip speed differs at t = {}",
                a.t
            );
            let (mx, my) = mirror(a.x_a, a.y_a);
            worst = worst.max((mx - b.x_a).hypot(my - b.y_a));
        }
        assert!(worst < tol_path, "mu {mu}: mirrored path off by {worst}");
    }
}

/// The same push begun from a rolling state (the disk at rest) with a slide in progress
/// (`Effects::slip_start_velocity`, along the heading): the start a fit gives a recording that
/// begins mid-slide. It is the textbook slide above, along the heading's direction.
#[test]
fn a_run_begun_with_a_slide_in_progress_is_the_disk_pushed_without_spin() {
    let (r, h, g, mu, v0, phi) = (1.0, 1e-6, 1.0, 0.3, 1.0, 0.6);
    let body = Body::new(Shape::Disk, r, h, r).unwrap();
    let model = Model::new(body, g, [0.0; 3], 1.0)
        .unwrap()
        .with_effects(Effects {
            slip_mu: Some(mu),
            slip_start_velocity: [v0, 0.0],
            ..Default::default()
        })
        .expect("valid");
    let mut y0 = [0.0; 8];
    (y0[0], y0[1]) = (phi, (0.5 * h / r).atan());
    let opts = RunOptions { t_end: 1.5, sample_dt: Some(0.01), ..Default::default() };
    let sim = Simulation::from_state(model.clone(), 0.0, y0, opts.clone()).expect("starts");
    assert!(sim.sliding_state().is_some(), "a slide in progress begins sliding");
    let mut p = Vec::new();
    let s = sim.run(&mut |x| p.push(*x));
    let t_star = v0 / (3.0 * mu * g);
    assert_eq!(s.sliding.len(), 1, "{:?}", s.sliding);
    assert_eq!(s.sliding[0].start, 0.0);
    assert!((s.sliding[0].end - t_star).abs() < 1e-6, "sticks at {}", s.sliding[0].end);
    for x in &p {
        let v = if x.t < t_star { v0 - mu * g * x.t } else { 2.0 * v0 / 3.0 };
        assert!((x.speed_c - v).abs() < 1e-6, "v at t = {}: {} vs {v}", x.t, x.speed_c);
        // Along the heading (cos phi, sin phi): no distance across it.
        let across = -x.y[6] * phi.sin() + x.y[7] * phi.cos();
        assert!(across.abs() < 1e-6, "off the heading by {across} at t = {}", x.t);
    }
    assert!(p.last().unwrap().y[6] > 0.5, "it went along +heading");
    // Without the slide in progress the disk at rest stays at rest, rolling.
    let still = Model {
        effects: Effects { slip_start_velocity: [0.0, 0.0], ..model.effects },
        ..model.clone()
    };
    let sim = Simulation::from_state(still, 0.0, y0, opts.clone()).expect("starts");
    assert!(sim.sliding_state().is_none());
    let s = sim.run(&mut |_| {});
    assert!(s.sliding.is_empty(), "{:?}", s.sliding);
    // A start held rolling ignores it (held means the contact rolls at the first frame).
    let held =
        Model { effects: Effects { slip_start: SlipStart::HeldRolling, ..model.effects }, ..model };
    let sim = Simulation::from_state(held, 0.0, y0, opts).expect("starts");
    assert!(sim.sliding_state().is_none());
}

#[test]
fn a_disk_launched_sliding_without_spin_rolls_off_at_two_thirds_of_its_speed() {
    // Textbook: a thin disk pushed along without spin slides with friction mu g against the
    // slip, which spins it up (I w' = mu g R); rolling starts when v = w R, at
    // t* = v0 / (3 mu g), with v = 2 v0 / 3; a third of the energy is lost.
    // The disk stands on its edge at the balance tilt tan(theta) = (h/2) / R, h = 1e-6 R,
    // so the motion stays in its plane.
    let (r, h, g, mu, v0) = (1.0, 1e-6, 1.0, 0.3, 1.0);
    let body = Body::new(Shape::Disk, r, h, r).unwrap();
    let model = with_mu(Model::new(body, g, [0.0; 3], 1.0).unwrap(), mu);
    let theta0 = (0.5 * h / r).atan();
    let mut y0 = [0.0; SLIDE_LEN];
    y0[1] = theta0;
    y0[8] = v0; // along e1 = (cos phi, sin phi) = x
    // The contact sits at the rim's edge, h/2 off the disk's plane, so friction also turns the
    // disk (a yaw torque mu g h/2), whose gyroscopic effect tips it towards the other rim by
    // 5e-7 rad (the balance tilt) in 1.9 time units; the run stops at 1.5.
    let opts = RunOptions { t_end: 1.5, sample_dt: Some(0.01), ..Default::default() };
    let sim = Simulation::from_sliding_state(model.clone(), 0.0, y0, opts).expect("starts");
    let mut p = Vec::new();
    let s = sim.run(&mut |x| p.push(*x));
    assert_eq!(s.end_reason, EndReason::TEnd);
    let t_star = v0 / (3.0 * mu * g);
    assert_eq!(s.sliding.len(), 1, "{:?}", s.sliding);
    assert!(
        (s.sliding[0].end - t_star).abs() < 1e-6,
        "sticks at {} not {t_star}",
        s.sliding[0].end
    );
    for x in &p {
        let (v, w2) = if x.t < t_star {
            (v0 - mu * g * x.t, 2.0 * mu * g * x.t / r)
        } else {
            (2.0 * v0 / 3.0, 2.0 * v0 / (3.0 * r))
        };
        assert!((x.speed_c - v).abs() < 1e-6, "v at t = {}: {} vs {v}", x.t, x.speed_c);
        assert!((x.y[4] - w2).abs() < 1e-6, "w2 at t = {}", x.t);
        assert!((x.f_n - g).abs() < 1e-6, "F_N at t = {}", x.t);
        assert!(x.y[7].abs() < 1e-6, "left its line at t = {}", x.t);
    }
    let e0 = p[0].energy;
    let lost = e0 - p.last().unwrap().energy;
    assert!((lost - v0 * v0 / 6.0).abs() < 1e-6, "lost {lost}");
}

#[test]
fn friction_beyond_the_painleve_limit_is_refused() {
    let m = paper::ring_model(paper::C_RING);
    let limit = painleve_mu_limit(&m);
    assert!(limit > 1.0, "{limit}");
    let e = Effects { slip_mu: Some(1.01 * limit), ..Default::default() };
    let err = m.clone().with_effects(e).unwrap_err();
    assert_eq!(err.name, "slip mu");
    let mut sneaky = m;
    sneaky.effects.slip_mu = Some(2.0 * limit);
    assert!(Simulation::new(sneaky, &paper::initial(), RunOptions::default()).is_err());
}

#[test]
fn all_effects_together_still_lose_energy_and_end_naturally() {
    // Sliding with the friction torques, air drag on C and Reynolds-dependent drag: the
    // sliding equations carry them all (slip.rs), and none may add energy.
    let base = paper::ring_model(paper::C_RING);
    let s0 = Sample::new(&base, 0.0, &paper::initial().to_state());
    let mut e = Effects::default();
    for (k, x) in [
        (ringlab_core::physics::EffectKind::ReynoldsDrag, 0.5),
        (ringlab_core::physics::EffectKind::RollingFriction, 0.01),
        (ringlab_core::physics::EffectKind::PivotFriction, 0.01),
        (ringlab_core::physics::EffectKind::TranslationalDrag, 0.1),
        (ringlab_core::physics::EffectKind::Slip, 0.3),
    ] {
        ringlab_core::physics::effects::apply(k, x, base.body.r, s0.reynolds, &mut e).unwrap();
    }
    let (s, p) = run(base.with_effects(e).unwrap(), &paper::initial(), 0.01);
    assert!(s.end_reason.is_natural(), "{:?}", s.end_reason);
    assert!(!s.sliding.is_empty());
    for w in p.windows(2) {
        assert!(
            w[1].energy <= w[0].energy + 1e-12 * w[0].energy.abs(),
            "energy rose at t = {}",
            w[1].t
        );
    }
}

#[test]
fn a_sliding_run_in_mm_is_the_model_run_rescaled() {
    // The creep speed, the friction smoothing and the Painleve limit are all relative to the
    // body's own scales, so the sliding contact does not depend on the unit system.
    let mut case = ringlab_core::config::load_preset("paper-ring").unwrap().build().unwrap();
    case.model = with_mu(case.model.clone(), 0.4);
    case.opts.sample_dt = None;
    let mm = case.in_units(ringlab_core::physics::Units::MM_S).unwrap();
    let (a, _) = simulate(case.model.clone(), &case.initial, case.opts.clone()).unwrap();
    let (b, _) = simulate(mm.model.clone(), &mm.initial, mm.opts.clone()).unwrap();
    let t0 = case.units.time_s;
    assert_eq!(a.sliding.len(), b.sliding.len());
    for (i, j) in a.sliding.iter().zip(&b.sliding) {
        assert!(
            (j.start - i.start * t0).abs() < 1e-6 * t0 && (j.end - i.end * t0).abs() < 1e-5 * t0,
            "{i:?} vs {j:?}"
        );
    }
    assert!((b.t_end - a.t_end * t0).abs() < 1e-5 * b.t_end);
}

#[test]
fn the_sliding_run_converges_with_the_tolerance() {
    // The equations solved must not depend on the steps taken (the friction direction at
    // creep-level slip uses a reference fixed by events, slip.rs): then tighter tolerances
    // only refine the same run, through dozens of stick-slip switches.
    let m = with_mu(paper::ring_model(paper::C_RING), 0.3);
    let at = |rtol: f64| {
        let tol = ringlab_core::physics::integrator::Tolerances { rtol, atol: 1e-2 * rtol };
        let opts = RunOptions { tol, sample_dt: Some(25.0), ..Default::default() };
        simulate(m.clone(), &paper::initial(), opts).expect("runs")
    };
    let ((a, pa), (b, pb)) = (at(1e-8), at(1e-11));
    assert!(a.sliding.len() > 50, "{}", a.sliding.len());
    assert_eq!(a.sliding.len(), b.sliding.len());
    let worst = a
        .sliding
        .iter()
        .zip(&b.sliding)
        .map(|(i, j)| (i.start - j.start).abs().max((i.end - j.end).abs()))
        .fold(0.0, f64::max);
    assert!(worst < 1e-5, "switch times move by {worst}");
    for (x, y) in pa.iter().zip(&pb) {
        assert!((x.x_a - y.x_a).hypot(x.y_a - y.y_a) < 1e-4, "A differs at t = {}", x.t);
    }
    assert!((a.t_end - b.t_end).abs() < 1e-3);
}

/// A start beyond the friction cone (the paper's launch needs 1.7 F_N in friction, mu 0.4
/// gives 0.4): the cone start slides at once; a start held rolling is the rolling run until
/// rolling first needs no more than `mu F_N`, slides from the next crossing, and reports the
/// held stretch as `slip`.
#[test]
fn a_start_held_rolling_rolls_until_the_cone_is_regained_and_then_slides() {
    let mu = 0.4;
    let initial = Initial { theta: 0.52, phi_dot: 3.8, psi_dot: 0.0, ..paper::initial() };
    let cone = with_mu(paper::ring_model(paper::C_RING), mu);
    let (s_cone, _) = run(cone.clone(), &initial, 0.01);
    assert_eq!(s_cone.sliding.first().map(|i| i.start), Some(0.0), "{:?}", s_cone.sliding);

    let held = Model {
        effects: Effects { slip_start: SlipStart::HeldRolling, ..cone.effects },
        ..cone.clone()
    };
    let (s_held, p_held) = run(held, &initial, 0.01);
    let (_, p_roll) = run(paper::ring_model(paper::C_RING), &initial, 0.01);
    let first = s_held.sliding.first().expect("it slides at some point").start;
    // Rolling needs no more than mu F_N first near t = 2.59, and more again from t = 2.82.
    let released = s_held.slip.first().expect("the held stretch is reported").end;
    assert!((2.55..2.65).contains(&released), "released at {released}");
    assert!((2.80..2.85).contains(&first), "first slide at {first}");
    // Before the first slide the held run is the rolling run, though rolling is beyond the cone.
    let mut beyond = 0;
    for (a, b) in p_held.iter().zip(&p_roll).take_while(|(a, _)| a.t < first) {
        assert_eq!(a.y, b.y, "t = {}", a.t);
        beyond += usize::from(b.friction_ratio() > mu);
    }
    assert!(beyond > 100, "the held stretch is not beyond the cone: {beyond} samples");
    // After it the runs part.
    let d = (s_held.final_sample.x_a - s_cone.final_sample.x_a)
        .hypot(s_held.final_sample.y_a - s_cone.final_sample.y_a);
    assert!(d > 0.1, "the held and the cone start end {d} apart");
}

#[test]
fn position_samples_are_the_full_samples_where_they_are() {
    // A fit's runs sample positions only (`Simulation::positions_only`): the same run, the same
    // state, top centre and contact to the bit, rolling and sliding (mu 0.4 from the paper's
    // start slides at the launch and where the ring lifts off).
    let model = with_mu(paper::ring_model(paper::C_RING), 0.4);
    let opts = RunOptions { sample_dt: Some(0.05), ..Default::default() };
    let samples = |positions_only: bool| {
        let mut sim =
            Simulation::new(model.clone(), &paper::initial(), opts.clone()).expect("runs");
        if positions_only {
            sim.positions_only();
        }
        let mut out = Vec::new();
        let summary = sim.run(&mut |s: &Sample| out.push(*s));
        (summary, out)
    };
    let ((full_run, full), (light_run, light)) = (samples(false), samples(true));
    assert_eq!(full_run.stats.steps, light_run.stats.steps);
    assert_eq!(full.len(), light.len());
    assert!(full.iter().filter(|s| s.sliding).count() > 10, "it must slide");
    for (a, b) in full.iter().zip(&light) {
        assert_eq!((a.t, a.y, a.x_a, a.y_a, a.z_c), (b.t, b.y, b.x_a, b.y_a, b.z_c));
        assert_eq!(a.sliding, b.sliding, "t = {}", a.t);
    }
    // What a position sample does not carry is not made up.
    assert!(light[light.len() / 2].f_n.is_nan() && light[light.len() / 2].energy.is_nan());
}
