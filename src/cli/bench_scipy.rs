//! `ringlab bench --scipy PYTHON`: scipy's DOP853 on the same run, timed through the given
//! Python by `bench/scipy_vs_ringlab.py`, beside ringlab's own figures in one run
//! (`docs/speed.md`).

use anyhow::{Context, Result, bail};
use ringlab::config::Case;
use ringlab::physics::paper;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

/// What the script prints with `--scipy-only --json`.
#[derive(Serialize, Deserialize, Debug, Clone)]
pub struct ScipyFigures {
    /// Wall time of the fastest solve.
    pub seconds: f64,
    /// That solve's CPU time.
    pub cpu_seconds: f64,
    pub evaluations: u64,
    pub t_end: f64,
    pub repeats: usize,
    /// Python's, numpy's and scipy's versions.
    pub versions: BTreeMap<String, String>,
}

/// The script writes the paper's ring into its right-hand side: any other case would time
/// another problem than ringlab's.
pub fn check_paper_ring(case: &Case) -> Result<()> {
    let (m, p) = (&case.model, paper::ring_model(paper::C_RING));
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1.0);
    let (b, q) = (&m.body, &p.body);
    let same_model = b.shape == q.shape
        && close(b.r, q.r)
        && close(b.h, q.h)
        && close(b.w, q.w)
        && close(m.g, p.g)
        && (0..3).all(|i| close(m.c_drag[i], p.c_drag[i]))
        && m.effects.is_none();
    let (i, j) = (&case.initial, paper::initial());
    let same_start = [
        (i.phi, j.phi),
        (i.theta, j.theta),
        (i.psi, j.psi),
        (i.theta_dot, j.theta_dot),
        (i.phi_dot, j.phi_dot),
        (i.psi_dot, j.psi_dot),
        (i.x_c, j.x_c),
        (i.y_c, j.y_c),
    ]
    .iter()
    .all(|&(a, b)| close(a, b));
    if !(same_model && same_start) {
        bail!(
            "--scipy times the paper's ring only (the reference script has its equations and \
             start written in): case '{}' with the given flags is another",
            case.name
        );
    }
    Ok(())
}

/// Runs the reference script through `python` and reads its figures.
pub fn run(python: &Path, script: &Path, repeats: usize) -> Result<ScipyFigures> {
    if !script.is_file() {
        bail!("the scipy reference {} is not there (--scipy-script)", script.display());
    }
    let out = Command::new(python)
        .arg(script)
        .args(["--scipy-only", "--json", "--repeats", &repeats.max(1).to_string()])
        .output()
        .with_context(|| {
            format!(
                "could not start {} (--scipy names a Python that has numpy and scipy, e.g. \
                 bench/.venv/bin/python after `python3 -m venv bench/.venv && \
                 bench/.venv/bin/pip install scipy`)",
                python.display()
            )
        })?;
    if !out.status.success() {
        bail!(
            "{} {} failed ({}): {}",
            python.display(),
            script.display(),
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
    serde_json::from_slice(&out.stdout).with_context(|| {
        format!(
            "{} printed no figures: {}",
            script.display(),
            String::from_utf8_lossy(&out.stdout).trim()
        )
    })
}
