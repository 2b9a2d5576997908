//! Shared test helpers: the test data in `tests/data` (the independent reference solution,
//! the sample recording and its truth, the independent simulator's recordings), the binary run
//! with arguments, a file as the window system drops it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

#[path = "../../crates/ringlab-core/tests/common/mod.rs"]
mod data;
pub mod drawing;
#[allow(unused_imports)]
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

/// The frames of a GIF as shown: each drawn over the one before (transparent pixels keep it).
pub fn gif_frames(path: &Path) -> Vec<image::RgbaImage> {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d =
        opts.read_info(std::fs::File::open(path).expect("the GIF is there")).expect("a GIF");
    let (w, h) = (d.width() as u32, d.height() as u32);
    let mut canvas = image::RgbaImage::new(w, h);
    let mut frames = Vec::new();
    while let Some(f) = d.read_next_frame().expect("a frame") {
        for y in 0..f.height as u32 {
            for x in 0..f.width as u32 {
                let i = 4 * (y * f.width as u32 + x) as usize;
                if f.buffer[i + 3] != 0 {
                    let px = [f.buffer[i], f.buffer[i + 1], f.buffer[i + 2], 255];
                    canvas.put_pixel(x + f.left as u32, y + f.top as u32, image::Rgba(px));
                }
            }
        }
        frames.push(canvas.clone());
    }
    frames
}
