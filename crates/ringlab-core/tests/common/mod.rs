//! Test data for the core's tests and the app's (the app's `tests/common` includes this file):
//! `tests/data` at the repository's root (copies of the project's shared data, so that a clone
//! anywhere tests on its own).
#![allow(dead_code)]

use std::path::PathBuf;

/// `tests/data/NAME` at the repository's root (this file is compiled into the core's tests, two
/// folders below the root, and into the app's, at the root).
pub fn test_data(name: &str) -> PathBuf {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let root = if manifest.join("tests/data").is_dir() { manifest } else { manifest.join("../..") };
    let p = root.join("tests/data").join(name);
    assert!(p.is_file(), "{} not found", p.display());
    p
}

/// The reference solution of the paper's case: column names and rows.
pub struct Reference {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl Reference {
    pub fn load() -> Reference {
        let text = std::fs::read_to_string(test_data("paper-ring-reference.csv"))
            .expect("readable reference");
        let mut lines = text.lines().filter(|l| !l.starts_with('#'));
        let columns: Vec<String> =
            lines.next().expect("header").split(',').map(|s| s.trim().to_string()).collect();
        let rows = lines
            .filter(|l| !l.trim().is_empty())
            .map(|l| l.split(',').map(|v| v.trim().parse::<f64>().expect("number")).collect())
            .collect();
        Reference { columns, rows }
    }

    pub fn col(&self, name: &str) -> Vec<f64> {
        let i = self
            .columns
            .iter()
            .position(|c| c == name)
            .unwrap_or_else(|| panic!("no column {name}"));
        self.rows.iter().map(|r| r[i]).collect()
    }

    /// The end time stated in the file's second comment line.
    pub fn end_time(&self) -> f64 {
        let text =
            std::fs::read_to_string(test_data("paper-ring-reference.csv")).expect("readable");
        let line = text.lines().find(|l| l.contains("run ends")).expect("end line");
        line.rsplit("t=").next().expect("t=").trim().parse().expect("end time")
    }
}
