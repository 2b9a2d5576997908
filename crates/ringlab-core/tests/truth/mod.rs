//! The sample recording's truth (`tests/data/sample-ring.truth.json`), regenerated with
//! the physics core: the model at every frame.
#![allow(dead_code)]

use ringlab_core::physics::{Body, Initial, Model, RunOptions, Sample, Shape, Units, simulate};
use serde_json::Value;

pub struct Truth {
    pub json: Value,
    pub model: Model,
    pub initial: Initial,
    pub units: Units,
    /// The model at frame `i` (the run's end state from its end on).
    pub frames: Vec<Sample>,
    pub t_end: f64,
}

fn num(v: &Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("truth: {key} missing"))
}

pub fn load() -> Truth {
    let path = super::common::test_data("sample-ring.truth.json");
    let json: Value = serde_json::from_str(&std::fs::read_to_string(path).expect("truth readable"))
        .expect("truth is JSON");
    let g = 1.025 * 4.5 * 4.5 / 20.2;
    let units = Units::dimensionless(20.16, g);
    assert!((units.time_s - num(&json, "T0_s")).abs() < 1e-12);
    let body =
        Body::new(Shape::Ring, num(&json, "R"), num(&json, "h"), num(&json, "w")).expect("body");
    let c = json["C"].as_array().expect("C");
    let c = [0, 1, 2].map(|i| c[i].as_f64().expect("C_i"));
    let model = Model::new(body, g, c, units.nu_air()).expect("model");
    let initial = Initial {
        phi: num(&json, "phi0"),
        theta: num(&json, "theta0"),
        psi: num(&json, "psi0"),
        theta_dot: num(&json, "thetadot0"),
        phi_dot: num(&json, "phidot0"),
        psi_dot: num(&json, "psidot0"),
        x_c: 0.0,
        y_c: 0.0,
    };
    let dt = 1.0 / 300.0 / units.time_s;
    let (summary, mut frames) = simulate(
        model.clone(),
        &initial,
        RunOptions { sample_dt: Some(dt), ..RunOptions::default() },
    )
    .expect("runs");
    assert!((summary.t_end - num(&json, "t_end_model")).abs() < 1e-4, "t_end {}", summary.t_end);
    let n = num(&json, "frames") as usize;
    frames.truncate((summary.t_end / dt).floor() as usize);
    frames.resize(n, summary.final_sample);
    Truth { json, model, initial, units, frames, t_end: summary.t_end }
}
