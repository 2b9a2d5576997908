//! A recording made outside ringlab, diagnosed and checked against its folder's `truth.json`
//! (`tests/data/FOLDER/`): what was said (effects in any order, `none` or `unexplained`), the
//! noise within 20% of the truth's (correlated in time only where the truth says so), and a named model's cut of the misfit beyond the noise.
#![allow(dead_code)]

use crate::common;
use ringlab_core::analysis::diagnose::{DiagnoseOptions, Diagnosis, Finding, diagnose};
use ringlab_core::recording::read_recording;
use std::sync::atomic::AtomicBool;

pub struct Truth {
    pub left_out: Vec<String>,
    pub noise_px: f64,
    /// The noise's correlation from frame to frame (0: white).
    pub noise_corr: f64,
}

pub fn truth(folder: &str, name: &str) -> Truth {
    let text = std::fs::read_to_string(common::test_data(&format!("{folder}/truth.json")))
        .expect("truth.json");
    let all: serde_json::Value = serde_json::from_str(&text).expect("truth.json is JSON");
    let t = &all[name];
    let left_out = t["left_out"]
        .as_array()
        .expect("left_out")
        .iter()
        .map(|v| v.as_str().expect("a name").to_string())
        .collect();
    Truth {
        left_out,
        noise_px: t["noise_px"].as_f64().expect("noise_px"),
        noise_corr: t["noise_corr"].as_f64().unwrap_or(0.0),
    }
}

pub fn run(folder: &str, name: &str) -> (Diagnosis, Truth) {
    let rec = read_recording(&common::test_data(&format!("{folder}/{name}.csv")))
        .expect("a readable recording");
    let d = diagnose(&rec, &DiagnoseOptions::default(), &|_| {}, &AtomicBool::new(false))
        .expect("a diagnosis");
    (d, truth(folder, name))
}

/// Diagnoses `folder/name.csv` and checks it against the truth: the names said, the noise, and
/// a named model cutting the excess over the noise at least 4x or to below 0.15 noise.
pub fn check(folder: &str, name: &str) -> Diagnosis {
    let (d, truth) = run(folder, name);
    let said: Vec<String> = match &d.finding {
        Finding::Nothing => vec!["none".into()],
        Finding::Unexplained { .. } => vec!["unexplained".into()],
        Finding::Named(k) => k.iter().map(|k| k.name().to_string()).collect(),
    };
    let (mut want, mut got) = (truth.left_out.clone(), said.clone());
    want.sort();
    got.sort();
    assert_eq!(got, want, "{name}: {}", d.explanation);
    assert!(
        (d.noise_px / truth.noise_px - 1.0).abs() < 0.2,
        "{name}: noise {} against {}",
        d.noise_px,
        truth.noise_px
    );
    // White noise is never taken for a tracker's correlated noise.
    assert_eq!(
        d.noise_correlation.is_some(),
        truth.noise_corr > 0.0,
        "{name}: {:?}",
        d.noise_correlation
    );
    if !d.finding.named().is_empty() {
        let (before, after) = (d.excess_px(d.before.rms_px), d.excess_px(d.after.rms_px));
        assert!(
            after <= before / 4.0 || after < 0.15 * d.noise_px,
            "{name}: excess {before} -> {after} px"
        );
    }
    d
}
