//! Core errors as Python exceptions: a bad file is `ringlab.RecordingError` (a `ValueError`),
//! a bad parameter a plain `ValueError`, a fit that cannot be made `ringlab.FitError`. The
//! messages are the CLI's, with its `--flag` names turned into the keyword arguments'.

use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use ringlab_core::analysis::diagnose::DiagnoseError;
use ringlab_core::analysis::fit::FitError as CoreFitError;
use ringlab_core::recording::import::{ImportError, ImportErrorKind};

create_exception!(
    ringlab,
    RecordingError,
    PyValueError,
    "A recording that cannot be read or made: which file (and line), and what is wrong."
);
create_exception!(
    ringlab,
    FitError,
    PyRuntimeError,
    "A fit or diagnosis that cannot be made from this recording (too short, no turning point, a model that cannot be run over it)."
);

/// The CLI's flags in a message as this package's keyword arguments (`give --px-per-mm` ->
/// `give px_per_mm=`, `--from` -> `format=`).
pub fn python_names(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(at) = rest.find("--") {
        out.push_str(&rest[..at]);
        let after = &rest[at + 2..];
        let len =
            after.find(|c: char| !(c.is_ascii_lowercase() || c == '-')).unwrap_or(after.len());
        let flag = &after[..len];
        if flag.is_empty() || !flag.starts_with(|c: char| c.is_ascii_lowercase()) {
            out.push_str("--");
            rest = after;
            continue;
        }
        let name = if flag == "from" { "format".to_string() } else { flag.replace('-', "_") };
        out.push_str(&name);
        rest = &after[len..];
        // "--fps = -1" reads "fps = -1"; "give --fps" reads "give fps=", "--marks 1,3" "marks=1,3".
        if !rest.starts_with(" =") {
            out.push('=');
            if rest.starts_with(' ') && rest[1..].starts_with(|c: char| c.is_ascii_alphanumeric()) {
                rest = &rest[1..];
            }
        }
    }
    out.push_str(rest);
    out
}

/// What the body keyword says, where the CLI's message names its flags.
const BODY_HINT: &str = "give body='NAME' (a preset, see ringlab.presets()) or body={'shape': 'ring', 'outer_radius_mm': ..., 'width_mm': ..., 'thickness_mm': ...}";

/// An import's error: a problem of the options is a `ValueError`, of the file a
/// `RecordingError`; both carry the file (and line) as the CLI says them.
pub fn import_error(e: &ImportError) -> PyErr {
    let text = match &e.kind {
        ImportErrorKind::MissingBody => {
            let at = e.path.display();
            format!("{at}: the body is not in the file: {BODY_HINT}")
        }
        _ => python_names(&e.to_string()),
    };
    let bad_option = matches!(
        e.kind,
        ImportErrorKind::BadOption(_)
            | ImportErrorKind::BadMarks(_)
            | ImportErrorKind::UnknownMark { .. }
            | ImportErrorKind::UnitConflict { .. }
    );
    if bad_option { PyValueError::new_err(text) } else { RecordingError::new_err(text) }
}

/// A fit's error, `what` naming the recording ("fitting sample.csv").
pub fn fit_error(what: &str, e: &CoreFitError) -> PyErr {
    match e {
        CoreFitError::Options(_) => PyValueError::new_err(format!("{what}: {e}")),
        _ => FitError::new_err(format!("{what}: {e}")),
    }
}

/// A diagnosis's error (its cancel is handled by the caller: a pending KeyboardInterrupt).
pub fn diagnose_error(what: &str, e: &DiagnoseError) -> PyErr {
    match e {
        DiagnoseError::Options(_) => PyValueError::new_err(format!("{what}: {e}")),
        DiagnoseError::Fit(f) => fit_error(what, f),
        _ => FitError::new_err(format!("{what}: {e}")),
    }
}
