//! The terminal's progress bar and the thread pool, set up once for every command.

use anyhow::Result;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// A bar on stderr that shows itself only once the work has run for a moment (short runs and
/// piped output stay clean; indicatif hides it when stderr is not a terminal).
pub struct LateBar {
    bar: ProgressBar,
    started: Instant,
    shown: AtomicBool,
}

/// `{msg}` before the bar, position of length after it.
pub const COUNT_TEMPLATE: &str = "{spinner} {msg:<22} [{bar:30}] {pos}/{len} {elapsed}";
/// A percentage (set a length of 1000).
pub const PERCENT_TEMPLATE: &str = "{spinner} [{bar:30}] {percent:>3}% {elapsed} {msg}";

impl LateBar {
    pub fn new(template: &str) -> LateBar {
        let bar = ProgressBar::hidden();
        bar.set_style(
            ProgressStyle::with_template(template)
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
        );
        LateBar { bar, started: Instant::now(), shown: AtomicBool::new(false) }
    }

    /// Moves the bar (never backwards) and sets its message.
    pub fn update(&self, position: u64, length: u64, message: String) {
        if self.started.elapsed() > Duration::from_millis(300)
            && !self.shown.swap(true, Ordering::Relaxed)
        {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
            self.bar.enable_steady_tick(Duration::from_millis(120));
        }
        self.bar.set_message(message);
        self.bar.set_length(length);
        if position > self.bar.position() {
            self.bar.set_position(position);
        }
    }

    /// A line printed above the bar.
    pub fn println(&self, line: &str) {
        self.bar.suspend(|| println!("{line}"));
    }

    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// Runs `work` on `threads` threads (`None`: rayon's global pool, all cores).
pub fn with_threads<T: Send>(threads: Option<usize>, work: impl FnOnce() -> T + Send) -> Result<T> {
    Ok(match threads {
        Some(n) => rayon::ThreadPoolBuilder::new().num_threads(n.max(1)).build()?.install(work),
        None => work(),
    })
}
