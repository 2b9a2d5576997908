//! A film as a folder of numbered PNG frames (`frame_000000.png`, ...): lossless, and what the
//! tracker reads as a film given its frame rate.

use super::ExportError;
use super::sink::FrameSink;
use image::RgbaImage;
use std::path::{Path, PathBuf};

pub struct PngFolder {
    dir: PathBuf,
    written: usize,
    /// Whether the folder was made here (abandoning removes it then).
    made: bool,
}

impl PngFolder {
    /// Opens `dir` for frames: made when missing; an existing one must be empty, so that no
    /// older frame is read as part of the film.
    pub fn create(dir: &Path) -> Result<PngFolder, ExportError> {
        let made = !dir.exists();
        if made {
            std::fs::create_dir(dir).map_err(ExportError::io(dir))?;
        } else {
            let mut entries = std::fs::read_dir(dir).map_err(ExportError::io(dir))?;
            if entries.next().is_some() {
                return Err(ExportError::Invalid(format!(
                    "{}: the folder is not empty (a film's frames go into a new or empty folder)",
                    dir.display()
                )));
            }
        }
        Ok(PngFolder { dir: dir.to_path_buf(), written: 0, made })
    }

    fn frame_path(&self, n: usize) -> PathBuf {
        self.dir.join(format!("frame_{n:06}.png"))
    }
}

impl FrameSink for PngFolder {
    fn push(&mut self, frame: &RgbaImage) -> Result<(), ExportError> {
        let path = self.frame_path(self.written);
        // Opaque frames: RGB is a third smaller than RGBA.
        image::DynamicImage::ImageRgba8(frame.clone())
            .to_rgb8()
            .save_with_format(&path, image::ImageFormat::Png)
            .map_err(|e| ExportError::Encode { path, message: e.to_string() })?;
        self.written += 1;
        Ok(())
    }

    fn finish(self: Box<Self>) -> Result<(), ExportError> {
        Ok(())
    }

    fn abandon(self: Box<Self>) {
        for n in 0..self.written {
            std::fs::remove_file(self.frame_path(n)).ok();
        }
        if self.made {
            std::fs::remove_dir(&self.dir).ok();
        }
    }
}

/// Bytes in a file, or in the files of a folder (0 where unreadable).
pub fn size_of_path(path: &Path) -> u64 {
    if path.is_dir() {
        let entries = std::fs::read_dir(path).into_iter().flatten().flatten();
        entries.filter_map(|e| e.metadata().ok()).map(|m| m.len()).sum()
    } else {
        std::fs::metadata(path).map(|m| m.len()).unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_numbered_and_abandoning_leaves_nothing() {
        let dir = std::env::temp_dir().join(format!("ringlab-png-folder-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let mut sink = Box::new(PngFolder::create(&dir).unwrap());
        let img = RgbaImage::from_pixel(4, 3, image::Rgba([10, 20, 30, 255]));
        sink.push(&img).unwrap();
        sink.push(&img).unwrap();
        assert!(dir.join("frame_000001.png").is_file());
        assert!(size_of_path(&dir) > 0);
        assert!(PngFolder::create(&dir).is_err(), "a folder with frames is refused");
        sink.abandon();
        assert!(!dir.exists());
    }
}
