//! A run's samples as CSV: the same run and the same columns as `ringlab simulate --out`.

use super::ExportError;
use crate::config::Case;
use crate::physics::Simulation;
use crate::report::write_samples_csv;
use std::path::Path;

/// Runs `case` from its start (as `simulate` does: every output state, not the window's
/// thinned copy) and writes its samples to `path`. Returns the number of rows.
pub fn write_run_csv(case: &Case, path: &Path) -> Result<usize, ExportError> {
    let sim = Simulation::new(case.model.clone(), &case.initial, case.opts.clone())
        .map_err(|e| ExportError::Invalid(format!("the case '{}' does not run: {e}", case.name)))?;
    let mut samples = Vec::new();
    sim.run(&mut |s| samples.push(*s));
    let mut bytes = Vec::new();
    write_samples_csv(&mut bytes, &samples).map_err(ExportError::io(path))?;
    super::deliver::deliver(path, &bytes)?;
    Ok(samples.len())
}
