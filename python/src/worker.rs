//! Long work (a fit, a diagnosis) on a thread of its own while the caller's thread waits
//! without the GIL: every 50 ms it takes the GIL for a moment to check for Ctrl-C (the
//! signal sets the core's cancel flag, and `KeyboardInterrupt` is raised once the core has
//! stopped) and to hand the latest progress to a Python callback on the caller's thread (so
//! no worker thread ever calls into Python).

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

/// How often the waiting thread looks for Ctrl-C and progress.
const POLL: Duration = Duration::from_millis(50);

/// Progress as the work reports it: a fraction of the whole in [0, 1] and a line to show.
pub type Report<'a> = &'a (dyn Fn(f64, String) + Sync);

/// Sets "done" when the worker ends, by returning or by a panic (its drop runs either way).
struct Done<'a>(&'a (Mutex<bool>, Condvar));

impl Drop for Done<'_> {
    fn drop(&mut self) {
        let (flag, cv) = self.0;
        if let Ok(mut d) = flag.lock() {
            *d = true;
        }
        cv.notify_all();
    }
}

/// Runs `work(report, cancel)` on `threads` threads (`None`: rayon's global pool, all cores,
/// as the CLI), calling `progress(fraction, message)` with the latest report. Ctrl-C or an
/// exception raised by `progress` sets `cancel` and is raised once `work` returns; a panic
/// in the core becomes a `RuntimeError`, never a crash of the interpreter.
pub fn run<T: Send>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    threads: Option<usize>,
    work: impl FnOnce(Report<'_>, &AtomicBool) -> T + Send,
) -> PyResult<T> {
    let pool = match threads {
        None => None,
        Some(0) => {
            return Err(PyValueError::new_err(
                "threads = 0: must be at least 1 (or None: all cores)",
            ));
        }
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| PyRuntimeError::new_err(format!("cannot start {n} threads: {e}")))?,
        ),
    };
    let cancel = AtomicBool::new(false);
    let latest: Mutex<Option<(f64, String)>> = Mutex::new(None);
    let done = (Mutex::new(false), Condvar::new());
    let report = |fraction: f64, message: String| {
        if let Ok(mut l) = latest.lock() {
            *l = Some((fraction, message));
        }
    };
    let mut raised: Option<PyErr> = None;
    let joined = std::thread::scope(|s| {
        let (cancel, report, done, pool) = (&cancel, &report, &done, &pool);
        let worker = s.spawn(move || {
            let _done = Done(done);
            match pool {
                Some(p) => p.install(|| work(report, cancel)),
                None => work(report, cancel),
            }
        });
        loop {
            let finished = py.detach(|| {
                let (flag, cv) = done;
                match flag.lock() {
                    Ok(g) => {
                        cv.wait_timeout_while(g, POLL, |d| !*d).map(|(g, _)| *g).unwrap_or(true)
                    }
                    Err(_) => true,
                }
            });
            if raised.is_none()
                && let Err(e) = py.check_signals()
            {
                cancel.store(true, Ordering::Relaxed);
                raised = Some(e);
            }
            let last = latest.lock().ok().and_then(|mut l| l.take());
            if raised.is_none()
                && let (Some(cb), Some((fraction, message))) = (progress, last)
                && let Err(e) = cb.call1((fraction, message))
            {
                cancel.store(true, Ordering::Relaxed);
                raised = Some(e);
            }
            if finished {
                break;
            }
        }
        worker.join()
    });
    if let Some(e) = raised {
        return Err(e);
    }
    joined.map_err(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "no message".into());
        PyRuntimeError::new_err(format!(
            "ringlab: internal error (a panic in the core: {what}); please report it"
        ))
    })
}
