//! MP4 through an `ffmpeg` found on PATH: raw RGBA frames piped to its standard input, H.264
//! (yuv420p, what every player takes) out. ffmpeg's complaints are read on a thread of their
//! own so that a full pipe never stops it.

use super::ExportError;
use super::sink::FrameSink;
use image::RgbaImage;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::thread::JoinHandle;

/// The `ffmpeg` on PATH, if there is one.
pub fn find_ffmpeg() -> Option<PathBuf> {
    let name = if cfg!(windows) { "ffmpeg.exe" } else { "ffmpeg" };
    std::env::split_paths(&std::env::var_os("PATH")?).map(|d| d.join(name)).find(|p| p.is_file())
}

pub struct Mp4Writer {
    child: Child,
    stdin: Option<ChildStdin>,
    stderr: Option<JoinHandle<String>>,
    path: PathBuf,
    size: [u32; 2],
}

impl Mp4Writer {
    pub fn spawn(path: &Path, size: [u32; 2], fps: f64) -> Result<Mp4Writer, ExportError> {
        let ffmpeg = find_ffmpeg().ok_or(ExportError::NoFfmpeg)?;
        // Create the file here first: a folder that is not there is then our error, not ffmpeg's.
        std::fs::File::create(path).map_err(ExportError::io(path))?;
        let mut child = Command::new(&ffmpeg)
            .args(["-hide_banner", "-loglevel", "error", "-nostdin", "-y"])
            .args(["-f", "rawvideo", "-pix_fmt", "rgba", "-s", &format!("{}x{}", size[0], size[1])])
            .args(["-framerate", &format!("{fps}"), "-i", "pipe:0", "-an"])
            // yuv420p needs an even width and height: pad by a pixel where they are odd.
            .args([
                "-vf",
                "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                "-c:v",
                "libx264",
                "-pix_fmt",
                "yuv420p",
                "-crf",
                "20",
            ])
            .args(["-movflags", "+faststart", "-f", "mp4"])
            .arg(path)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| ExportError::Ffmpeg {
                path: path.to_path_buf(),
                message: format!("cannot start {}: {e}", ffmpeg.display()),
            })?;
        let stdin = child.stdin.take();
        let stderr = child.stderr.take().map(|mut s| {
            std::thread::spawn(move || {
                let mut text = String::new();
                s.read_to_string(&mut text).ok();
                text
            })
        });
        Ok(Mp4Writer { child, stdin, stderr, path: path.to_path_buf(), size })
    }

    /// Waits for ffmpeg; its complaint when it failed.
    fn wait(&mut self) -> Result<(), ExportError> {
        self.stdin = None;
        let status = self
            .child
            .wait()
            .map_err(|e| ExportError::Ffmpeg { path: self.path.clone(), message: e.to_string() })?;
        let said = self.stderr.take().and_then(|h| h.join().ok()).unwrap_or_default();
        if status.success() {
            return Ok(());
        }
        let said = said.trim();
        let message = if said.is_empty() {
            format!("it ended with {status}")
        } else {
            format!("{status}: {said}")
        };
        Err(ExportError::Ffmpeg { path: self.path.clone(), message })
    }
}

impl FrameSink for Mp4Writer {
    fn push(&mut self, frame: &RgbaImage) -> Result<(), ExportError> {
        if frame.dimensions() != (self.size[0], self.size[1]) {
            return Err(ExportError::Invalid(format!(
                "a frame of {:?} pixels in a video of {:?}",
                frame.dimensions(),
                self.size
            )));
        }
        let written = self.stdin.as_mut().map(|s| s.write_all(frame.as_raw()));
        match written {
            Some(Ok(())) => Ok(()),
            // ffmpeg stopped taking frames: what it said is the error.
            _ => Err(self.wait().err().unwrap_or_else(|| ExportError::Ffmpeg {
                path: self.path.clone(),
                message: "it stopped taking frames".into(),
            })),
        }
    }

    fn finish(mut self: Box<Self>) -> Result<(), ExportError> {
        self.wait()
    }

    fn abandon(mut self: Box<Self>) {
        self.stdin = None;
        self.child.kill().ok();
        self.child.wait().ok();
        std::fs::remove_file(&self.path).ok();
    }
}

impl Drop for Mp4Writer {
    /// Never leave an ffmpeg behind.
    fn drop(&mut self) {
        if matches!(self.child.try_wait(), Ok(None)) {
            self.child.kill().ok();
            self.child.wait().ok();
        }
    }
}
