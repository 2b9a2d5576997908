//! Shared test helpers: the test data in `tests/data` (the independent reference solution,
//! the sample recording and its truth, the independent simulator's recordings), the binary run
//! with arguments, a file as the window system drops it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
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

/// `tests/data/NAME` in the repository (copies of the project's shared data, so that a clone
/// anywhere tests on its own).
pub fn test_data(name: &str) -> PathBuf {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name);
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
        let text = std::fs::read_to_string(test_data("paper-ring-reference.csv")).expect("readable reference");
        let mut lines = text.lines().filter(|l| !l.starts_with('#'));
        let columns: Vec<String> = lines.next().expect("header").split(',').map(|s| s.trim().to_string()).collect();
        let rows = lines
            .filter(|l| !l.trim().is_empty())
            .map(|l| l.split(',').map(|v| v.trim().parse::<f64>().expect("number")).collect())
            .collect();
        Reference { columns, rows }
    }

    pub fn col(&self, name: &str) -> Vec<f64> {
        let i = self.columns.iter().position(|c| c == name).unwrap_or_else(|| panic!("no column {name}"));
        self.rows.iter().map(|r| r[i]).collect()
    }

    /// The end time stated in the file's second comment line.
    pub fn end_time(&self) -> f64 {
        let text = std::fs::read_to_string(test_data("paper-ring-reference.csv")).expect("readable");
        let line = text.lines().find(|l| l.contains("run ends")).expect("end line");
        line.rsplit("t=").next().expect("t=").trim().parse().expect("end time")
    }
}

/// The frames of a GIF as shown: each drawn over the one before (transparent pixels keep it).
pub fn gif_frames(path: &Path) -> Vec<image::RgbaImage> {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d = opts.read_info(std::fs::File::open(path).expect("the GIF is there")).expect("a GIF");
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
