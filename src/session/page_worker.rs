//! A fit or a diagnosis in a web page's worker (`worker.js` beside the page): the page has one
//! thread, and work of seconds there would freeze the window. The recording goes over as
//! format v1 text (written exactly: the worker reads back the same numbers), the result comes
//! back as RON (which keeps the infinite sigmas of unconstrained parameters and the effects
//! without parameters; JSON and TOML keep neither), progress in between. Cancel ends the
//! worker. Where no worker can be started the work runs in place.

use crate::recording::Recording;
use crate::recording::write::write_recording_exact;
use serde::Serialize;
use serde::de::DeserializeOwned;

/// The work a worker does: the message's key, and the job's name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Work {
    Fit,
    Diagnose,
}

impl Work {
    pub fn key(self) -> &'static str {
        match self {
            Work::Fit => "fit",
            Work::Diagnose => "diagnose",
        }
    }
}

/// The recording as the worker reads it.
pub fn recording_text(rec: &Recording) -> Result<String, String> {
    let mut out = Vec::new();
    write_recording_exact(&mut out, rec).map_err(|e| e.to_string())?;
    String::from_utf8(out).map_err(|e| e.to_string())
}

/// A result as the worker sends it back.
pub fn result_text<T: Serialize>(r: &T) -> Result<String, String> {
    ron::to_string(r).map_err(|e| e.to_string())
}

/// The result read back on the page's side.
pub fn result_from_text<T: DeserializeOwned>(text: &str) -> Result<T, String> {
    ron::from_str(text).map_err(|e| e.to_string())
}

#[cfg(target_arch = "wasm32")]
pub use page::{PageWorker, in_worker};

#[cfg(target_arch = "wasm32")]
mod page {
    use super::*;
    use crate::session::job::{Job, JobContext, Progress};
    use wasm_bindgen::JsCast;
    use wasm_bindgen::prelude::Closure;

    /// The worker of one job: ended when dropped (Cancel, a new recording, the page closed).
    pub struct PageWorker {
        worker: web_sys::Worker,
        _on_message: Closure<dyn FnMut(web_sys::MessageEvent)>,
        _on_error: Closure<dyn FnMut(web_sys::Event)>,
    }

    impl Drop for PageWorker {
        fn drop(&mut self) {
            self.worker.terminate();
        }
    }

    /// Starts `work` on `rec` in a worker; its answer (the result's text, or the worker's
    /// error) becomes the job's result through `deliver`. None where the page cannot start a
    /// worker (then the caller works in place).
    pub fn in_worker<T: Send + 'static>(
        work: Work,
        rec: &Recording,
        deliver: impl Fn(Result<String, String>) -> T + 'static,
    ) -> Option<(Job<T>, PageWorker)> {
        let text = recording_text(rec).ok()?;
        let options = web_sys::WorkerOptions::new();
        options.set_type(web_sys::WorkerType::Module);
        let worker = web_sys::Worker::new_with_options("./worker.js", &options).ok()?;
        let (job, tx) = Job::waiting();
        let ctx: JobContext = job.context();
        let deliver = std::rc::Rc::new(deliver);
        // A worker whose script cannot be loaded or that fails outside the work says so here
        // (else the job would wait for ever).
        let (fail_tx, fail) = (tx.clone(), std::rc::Rc::clone(&deliver));
        let on_error = Closure::<dyn FnMut(web_sys::Event)>::new(move |_: web_sys::Event| {
            let why = "the page's worker (worker.js) failed to start or stopped".to_string();
            let _ = fail_tx.send((*fail)(Err(why)));
        });
        worker.set_onerror(Some(on_error.as_ref().unchecked_ref()));
        let on_message =
            Closure::<dyn FnMut(web_sys::MessageEvent)>::new(move |e: web_sys::MessageEvent| {
                let get = |key: &str| js_sys::Reflect::get(&e.data(), &key.into()).ok();
                let text = |key: &str| get(key).and_then(|v| v.as_string());
                if let Some(t) = text("progress") {
                    let fraction = get("fraction").and_then(|v| v.as_f64()).unwrap_or(0.0);
                    ctx.report_forward(Progress { fraction: fraction as f32, text: t });
                } else if let Some(t) = text("result") {
                    let _ = tx.send((*deliver)(Ok(t)));
                } else {
                    let why = text("error").unwrap_or_else(|| "the page's worker stopped".into());
                    let _ = tx.send((*deliver)(Err(why)));
                }
            });
        worker.set_onmessage(Some(on_message.as_ref().unchecked_ref()));
        let message = js_sys::Object::new();
        js_sys::Reflect::set(&message, &work.key().into(), &text.into()).ok()?;
        worker.post_message(&message).ok()?;
        Some((job, PageWorker { worker, _on_message: on_message, _on_error: on_error }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::fit::{FitOptions, FitResult, fit};
    use crate::recording::read::parse_recording;
    use std::sync::atomic::AtomicBool;

    #[test]
    fn a_fit_crosses_to_the_worker_and_back_unchanged() {
        let bytes = include_bytes!("../../tests/data/sample-ring.csv");
        let path = std::path::Path::new("sample-ring.csv");
        let rec = parse_recording(bytes, path).expect("the sample reads");
        // What the page sends is what the worker reads.
        let sent = parse_recording(recording_text(&rec).expect("written").as_bytes(), path);
        assert_eq!(sent.as_ref(), Ok(&rec));
        let r = fit(&rec, &FitOptions::default(), &|_| {}, &AtomicBool::new(false)).expect("fits");
        let mut unconstrained = r.clone();
        unconstrained.c_sigma[2] = f64::INFINITY;
        for r in [r, unconstrained] {
            let text = result_text(&r).expect("written");
            let back: FitResult = result_from_text(&text).expect("read back");
            assert_eq!(format!("{back:?}"), format!("{r:?}"));
        }
    }
}
