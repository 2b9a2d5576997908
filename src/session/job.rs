//! One piece of work off the UI thread (reading a recording, a fit, a file dialog): a thread
//! that reports its progress and can be asked to stop, polled by the UI without waiting.
//!
//! In the app's fixed mode (tests, headless pictures) a job runs at once on the calling
//! thread instead, so that what it does is there in the same frame and nothing depends on
//! timing.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::sync::{Arc, Mutex};

/// Where a job is, as the UI shows it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Progress {
    /// 0 to 1.
    pub fraction: f32,
    pub text: String,
}

/// What the work sees: where to report progress, and whether it was asked to stop.
#[derive(Clone, Debug, Default)]
pub struct JobContext {
    progress: Arc<Mutex<Progress>>,
    cancel: Arc<AtomicBool>,
}

impl JobContext {
    pub fn report(&self, p: Progress) {
        if let Ok(mut slot) = self.progress.lock() {
            *slot = p;
        }
    }

    /// Reports without moving the bar back (work whose stages repeat: the fit's segments and
    /// least squares per merge, the diagnosis's candidates).
    pub fn report_forward(&self, mut p: Progress) {
        if let Ok(mut slot) = self.progress.lock() {
            p.fraction = p.fraction.clamp(0.0, 1.0).max(slot.fraction);
            *slot = p;
        }
    }

    pub fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    /// The flag itself, for work that takes one (the fit).
    pub fn cancel_flag(&self) -> &AtomicBool {
        &self.cancel
    }
}

/// Runs `work` on a pool of all cores but one when `own_pool`, so that the window and the
/// integrator keep one (else on the caller's pool: tests, pictures).
pub fn on_spare_cores<T: Send>(own_pool: bool, work: impl FnOnce() -> T + Send) -> T {
    let threads =
        std::thread::available_parallelism().map_or(1, |n| n.get()).saturating_sub(1).max(1);
    match own_pool.then(|| rayon::ThreadPoolBuilder::new().num_threads(threads).build().ok()) {
        Some(Some(pool)) => pool.install(work),
        _ => work(),
    }
}

/// The work ended without a result: it panicked (a bug; the app goes on).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the background task stopped unexpectedly")]
pub struct JobLost;

enum State<T> {
    Running(Receiver<T>),
    Done(Option<T>),
    Taken,
}

/// A job whose result is a `T`.
pub struct Job<T> {
    state: State<T>,
    ctx: JobContext,
}

impl<T: Send + 'static> Job<T> {
    /// Starts `work` on a thread of its own (`background`), or runs it here and now. Where no
    /// thread can be had it runs here too.
    pub fn start(
        name: &str,
        background: bool,
        work: impl FnOnce(&JobContext) -> T + Send + 'static,
    ) -> Job<T> {
        let ctx = JobContext::default();
        if background {
            let (tx, rx) = mpsc::channel();
            let c = ctx.clone();
            let work = Arc::new(Mutex::new(Some(work)));
            let w = Arc::clone(&work);
            let spawned = std::thread::Builder::new().name(name.into()).spawn(move || {
                if let Some(f) = w.lock().ok().and_then(|mut s| s.take()) {
                    // The receiver may be gone (the job was dropped): nothing to tell then.
                    let _ = tx.send(f(&c));
                }
            });
            if spawned.is_ok() {
                return Job { state: State::Running(rx), ctx };
            }
            let f = work.lock().ok().and_then(|mut s| s.take());
            let result = f.map(|f| f(&ctx));
            return Job { state: State::Done(result), ctx };
        }
        let result = work(&ctx);
        Job { state: State::Done(Some(result)), ctx }
    }

    /// A job whose result another task delivers through the sender (a browser's promise: a
    /// page's file picker), polled like any other.
    pub fn waiting() -> (Job<T>, mpsc::Sender<T>) {
        let (tx, rx) = mpsc::channel();
        (Job { state: State::Running(rx), ctx: JobContext::default() }, tx)
    }

    /// What the work sees, for work that reports from elsewhere (a web page's worker).
    pub fn context(&self) -> JobContext {
        self.ctx.clone()
    }

    /// A job already done, with this result.
    pub fn done(result: T) -> Job<T> {
        Job { state: State::Done(Some(result)), ctx: JobContext::default() }
    }

    /// The result once it is there (taken: later calls give None), without waiting.
    pub fn poll(&mut self) -> Option<Result<T, JobLost>> {
        if let State::Running(rx) = &self.state {
            self.state = match rx.try_recv() {
                Ok(v) => State::Done(Some(v)),
                Err(TryRecvError::Empty) => return None,
                Err(TryRecvError::Disconnected) => State::Done(None),
            };
        }
        match std::mem::replace(&mut self.state, State::Taken) {
            State::Done(v) => Some(v.ok_or(JobLost)),
            other => {
                self.state = other;
                None
            }
        }
    }

    /// Waits until the work is done, leaving the result for [`Job::poll`].
    pub fn finish(&mut self) {
        if let State::Running(rx) = &self.state {
            self.state = State::Done(rx.recv().ok());
        }
    }

    /// Waits for the result (tests, and a caller that must have it now).
    pub fn wait(&mut self) -> Option<Result<T, JobLost>> {
        self.finish();
        self.poll()
    }

    pub fn is_running(&self) -> bool {
        matches!(self.state, State::Running(_))
    }

    pub fn progress(&self) -> Progress {
        self.ctx.progress.lock().map(|p| p.clone()).unwrap_or_default()
    }

    /// Asks the work to stop (it decides when: the fit at its next evaluation).
    pub fn cancel(&self) {
        self.ctx.cancel.store(true, Ordering::Relaxed);
    }

    pub fn is_cancelling(&self) -> bool {
        self.ctx.cancelled()
    }
}

impl<T> Drop for Job<T> {
    /// A job nobody waits for any more stops at its next check instead of running on.
    fn drop(&mut self) {
        self.ctx.cancel.store(true, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_background_job_reports_and_delivers_once() {
        let (go_tx, go_rx) = mpsc::channel::<()>();
        let mut job = Job::start("test", true, move |ctx| {
            ctx.report(Progress { fraction: 0.5, text: "half".into() });
            go_rx.recv().ok();
            42
        });
        assert!(job.is_running());
        assert!(job.poll().is_none(), "still waiting for the go");
        go_tx.send(()).ok();
        assert_eq!(job.wait(), Some(Ok(42)));
        assert_eq!(job.progress().text, "half");
        assert_eq!(job.poll(), None, "the result is taken once");
        assert!(!job.is_running());
    }

    #[test]
    fn cancel_reaches_the_work() {
        let mut job = Job::start("test", true, |ctx| {
            while !ctx.cancelled() {
                std::thread::yield_now();
            }
            "stopped"
        });
        job.cancel();
        assert!(job.is_cancelling());
        assert_eq!(job.wait(), Some(Ok("stopped")));
    }

    #[test]
    fn a_panic_in_the_work_is_a_lost_job_not_a_crash() {
        let mut job: Job<u8> = Job::start("test", true, |_| panic!("bug"));
        assert_eq!(job.wait(), Some(Err(JobLost)));
    }

    #[test]
    fn a_foreground_job_is_done_at_once() {
        let mut job = Job::start("test", false, |_| 7);
        assert!(!job.is_running());
        assert_eq!(job.poll(), Some(Ok(7)));
    }
}
