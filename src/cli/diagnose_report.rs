//! `ringlab diagnose --report DIR`: figures and a short report.md.

use anyhow::{Result, bail};
use ringlab::analysis::diagnose::Diagnosis;
use ringlab::recording::Recording;
use std::path::Path;

pub fn write(_dir: &Path, _file: &Path, _rec: &Recording, _d: &Diagnosis) -> Result<()> {
    bail!("not written yet")
}
