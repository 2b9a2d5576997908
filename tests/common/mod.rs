//! Shared test helpers: the test data in `tests/data` (the independent reference solution,
//! the sample recording and its truth, the independent simulator's recordings), the binary run
//! with arguments, a file as the window system drops it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

#[path = "../../crates/ringlab-core/tests/common/mod.rs"]
mod data;
pub use data::test_data;
use std::process::{Command, Output};

/// The `ringlab` binary run with `args`.
pub fn ringlab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ringlab")).args(args).output().expect("runs the binary")
}

/// `ringlab args` fails, without a panic, with an error that mentions every needle.
pub fn assert_fails_with(args: &[&str], needles: &[&str]) {
    let out = ringlab(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} succeeded");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    for needle in needles {
        assert!(err.contains(needle), "{args:?}: error does not mention '{needle}':\n{err}");
    }
}

/// A file as the window system hands it to egui when it is dropped.
#[derive(Debug)]
pub struct Dropped(pub PathBuf);

impl eframe::egui::DroppedFile for Dropped {
    fn path(&self) -> &Path {
        &self.0
    }

    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

/// A DeepLabCut CSV of a recording's marks (bodyparts m1..m4, likelihood 0.99; blank cells
/// where a mark is missing).
pub fn deeplabcut_text(rec: &ringlab::recording::Recording) -> String {
    let mut s = String::from("scorer,DLC,DLC,DLC,DLC,DLC,DLC,DLC,DLC,DLC,DLC,DLC,DLC\nbodyparts");
    for k in 1..=4 {
        s.push_str(&format!(",m{k},m{k},m{k}"));
    }
    s.push_str("\ncoords");
    s.push_str(&",x,y,likelihood".repeat(4));
    s.push('\n');
    for (i, f) in rec.frames.iter().enumerate() {
        s.push_str(&i.to_string());
        for p in f {
            match p {
                Some([x, y]) => s.push_str(&format!(",{x:.3},{y:.3},0.99")),
                None => s.push_str(",,,"),
            }
        }
        s.push('\n');
    }
    s
}
