//! Presets and units: every preset is valid, and the one conversion function is consistent.

use ringlab_core::config::{load_preset, preset_names};
use ringlab_core::physics::{Units, simulate};

#[test]
fn every_preset_builds() {
    for name in preset_names() {
        let case = load_preset(name).unwrap_or_else(|e| panic!("{name}: {e}")).build();
        assert!(case.is_ok(), "{name}: {:?}", case.err());
    }
}

#[test]
fn a_run_in_mm_is_the_model_run_rescaled() {
    let model_case = load_preset("paper-ring").unwrap().build().unwrap();
    let mm_case = model_case.in_units(Units::MM_S).unwrap();
    assert!((mm_case.model.g - 9810.0).abs() < 1e-9);
    assert!((mm_case.model.body.r - 1.025 * 20.16).abs() < 1e-9);
    let (a, pa) =
        simulate(model_case.model.clone(), &model_case.initial, model_case.opts.clone()).unwrap();
    let (b, pb) = simulate(mm_case.model.clone(), &mm_case.initial, mm_case.opts.clone()).unwrap();
    let t0 = model_case.units.time_s;
    assert!(
        (b.t_end - a.t_end * t0).abs() < 1e-6 * b.t_end,
        "{} s vs {} model units",
        b.t_end,
        a.t_end
    );
    for (sa, sb) in pa.iter().zip(&pb).step_by(50).take_while(|(s, _)| s.t < 50.0) {
        assert!((sb.t - sa.t * t0).abs() < 1e-9);
        assert!((sb.theta() - sa.theta()).abs() < 1e-6, "theta at t = {}", sa.t);
        assert!((sb.x_a - sa.x_a * 20.16).abs() < 1e-4, "x_a at t = {}", sa.t);
        // Reynolds numbers are physical: the same in both.
        assert!((sb.reynolds - sa.reynolds).abs() < 1e-6 * sa.reynolds.max(1.0));
    }
    // Back again.
    let back = mm_case.in_units(model_case.units).unwrap();
    assert!((back.initial.phi_dot - 4.5).abs() < 1e-12);
    assert!((back.model.g - model_case.model.g).abs() < 1e-12);
}

#[test]
fn the_paper_ring_reynolds_number_is_as_in_the_paper() {
    // The paper: Re <= 800 in its experiment.
    let case = load_preset("paper-ring").unwrap().build().unwrap();
    let (_, s) = simulate(case.model.clone(), &case.initial, case.opts.clone()).unwrap();
    let re_max = s.iter().map(|s| s.reynolds).fold(0.0, f64::max);
    assert!(re_max > 100.0 && re_max < 2000.0, "Re max {re_max}");
}
