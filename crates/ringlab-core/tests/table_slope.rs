//! The table's slope (`physics/effects/table_slope.rs`): a table tilted 0.2 degrees is named
//! with its angle and direction and fitted to the noise; a table that is not flat in another way
//! (a dish: its slope grows with the distance from a centre and points to it) is not taken for a
//! slope that leaves the misfit above the noise.

use ringlab_core::analysis::diagnose::concealed::concealed_case;
use ringlab_core::analysis::diagnose::{DiagnoseOptions, Diagnosis, Finding, diagnose};
use ringlab_core::physics::effects::table_slope::TableSlope;
use ringlab_core::physics::effects::{self, EffectKind};
use ringlab_core::physics::{Initial, RunOptions, Sample, Simulation};
use ringlab_core::recording::synth::{film, synthesize};
use std::sync::atomic::AtomicBool;

fn diagnosed(rec: &ringlab_core::recording::Recording) -> Diagnosis {
    diagnose(rec, &DiagnoseOptions::default(), &|_| {}, &AtomicBool::new(false))
        .expect("a diagnosis")
}

#[test]
fn a_level_table_is_the_paper_model_and_a_slope_changes_the_run() {
    let (case, _, _) = concealed_case(EffectKind::None, 1).expect("a case");
    let mut e = case.model.effects;
    effects::apply(EffectKind::TableSlope, 0.0, 1.0, 100.0, &mut e).unwrap();
    assert!(e.is_none());
    let end = |model: ringlab_core::physics::Model| {
        let sim = Simulation::new(model, &case.initial, case.opts.clone()).expect("runs");
        sim.run(&mut |_| {}).final_sample
    };
    let level = end(case.model.clone());
    let mut tilted = case.model.clone();
    tilted.effects.table_slope = Some(TableSlope { angle: 0.2f64.to_radians(), direction: 1.0 });
    let slope = end(tilted);
    let moved = (slope.y[6] - level.y[6]).hypot(slope.y[7] - level.y[7]);
    assert!(moved > 0.1, "the centre's end moved by {moved} mean radii");
}

#[test]
fn a_table_tilted_two_tenths_of_a_degree_is_named_with_its_angle_and_direction() {
    let (case, mut opts, _) = concealed_case(EffectKind::None, 1).expect("a case");
    let (angle, direction) = (0.2, 60.0);
    opts.effect = Some((EffectKind::TableSlope, angle));
    opts.effect_extras = vec![direction];
    let rec = synthesize(&case, &opts).expect("a recording").recording;
    let d = diagnosed(&rec);
    assert_eq!(d.finding.named(), [EffectKind::TableSlope], "{}", d.explanation);
    let (fitted, _) = d.after.strength.expect("a strength");
    assert!((fitted - angle).abs() < 0.05, "angle {fitted}: {}", d.explanation);
    let toward = d
        .after
        .extras
        .iter()
        .find(|x| x.kind == EffectKind::TableSlope)
        .map(|x| x.value.0)
        .expect("its direction");
    let off = (toward - direction + 180.0).rem_euclid(360.0) - 180.0;
    assert!(off.abs() < 20.0, "direction {toward}: {}", d.explanation);
    assert!(d.after.rms_px < 1.3 * d.noise_px, "{} px: {}", d.after.rms_px, d.explanation);
    assert!(
        d.explanation.contains("the table is not level")
            || d.explanation.contains("The table is not level")
    );
    assert!(d.explanation.contains("falls 0.2"), "{}", d.explanation);
}

/// The paper's ring on a dish: the table falls toward a centre by `deg_per_radius` degrees
/// for every mean radius of distance from it, filmed as `synth` films (the motion made one
/// frame at a time, each frame with the slope where the ring is).
fn dished_recording(deg_per_radius: f64) -> ringlab_core::recording::Recording {
    let (case, opts, _) = concealed_case(EffectKind::None, 2).expect("a case");
    let dt = 1.0
        / opts.fps
        / ringlab_core::physics::Conversion::between(
            case.units,
            ringlab_core::physics::Units::MM_S,
        )
        .time;
    let centre = [case.initial.x_c + 1.5, case.initial.y_c - 1.0];
    let mut model = case.model.clone();
    let mut y = case.initial.to_state();
    let mut samples = vec![Sample::new(&model, 0.0, &y)];
    for n in 1..6000 {
        let (dx, dy) = (centre[0] - y[6], centre[1] - y[7]);
        let r = dx.hypot(dy);
        model.effects.table_slope = (r > 0.0).then(|| TableSlope {
            angle: (deg_per_radius * r).to_radians(),
            direction: dy.atan2(dx),
        });
        let run = RunOptions { t_end: dt, sample_dt: None, ..case.opts.clone() };
        let mut sim =
            Simulation::new(model.clone(), &Initial::from_state(&y), run).expect("a frame's run");
        let end = sim.advance(dt, &mut |_| {});
        y = *sim.state();
        samples.push(Sample::new(&model, n as f64 * dt, &y));
        if end.is_some_and(|e| e.is_natural()) {
            break;
        }
    }
    let last = *samples.last().expect("frames");
    samples.extend(std::iter::repeat_n(last, opts.rest_frames));
    film(&case, &model, &samples, &opts).expect("filmed")
}

#[test]
fn a_dished_table_is_not_taken_for_a_slope() {
    let rec = dished_recording(0.1);
    let d = diagnosed(&rec);
    assert!(d.before.rms_px > 3.0 * d.noise_px, "the dish must show: {}", d.explanation);
    match &d.finding {
        Finding::Unexplained { .. } => {}
        f => panic!("a dish must be unexplained, said {f:?}: {}", d.explanation),
    }
}
