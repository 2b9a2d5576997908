//! A run as a video: frames at even steps of the playback clock from one time to another,
//! drawn by a [`Frames`] (the window's drawing) and handed to an encoder (GIF or MP4, by the
//! file's name).
//!
//! The clock is the window's: `speed` is a multiple of real time (0.25: a quarter of real
//! time, the window's default), so a second of video shows `speed` seconds of the motion,
//! `speed / time unit` units of a case in the paper's units.

use super::frames::Frames;
pub use super::sink::FrameSink;
use super::{ExportError, gif::GifWriter, mp4::Mp4Writer};
use crate::render::Gpu;
use std::path::{Path, PathBuf};

/// The most frames one video may have (an hour at 25 frames/s).
pub const MAX_FRAMES: usize = 90_000;
/// GIF delays count hundredths of a second and viewers stretch the shortest ones: above 50
/// frames/s a GIF would play slower than asked.
pub const GIF_MAX_FPS: f64 = 50.0;

/// Which encoder, by the file's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VideoFormat {
    Gif,
    Mp4,
}

impl VideoFormat {
    pub fn of(path: &Path) -> Option<VideoFormat> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "gif" => Some(VideoFormat::Gif),
            "mp4" => Some(VideoFormat::Mp4),
            _ => None,
        }
    }

    pub fn extension(self) -> &'static str {
        match self {
            VideoFormat::Gif => "gif",
            VideoFormat::Mp4 => "mp4",
        }
    }
}

/// From when to when, how many frames a second and how fast.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VideoSpec {
    /// Times of the first run, in its time unit.
    pub from: f64,
    pub to: f64,
    /// Frames per second of video.
    pub fps: f64,
    /// Seconds of motion per second of video (a multiple of real time).
    pub speed: f64,
}

impl VideoSpec {
    /// What is wrong with the numbers, named as the command line names them.
    pub fn check(&self, format: VideoFormat) -> Result<(), String> {
        super::check_span(self.from, self.to)?;
        if !(self.fps.is_finite() && self.fps >= 1.0 && self.fps <= 120.0) {
            return Err(format!(
                "--fps = {}: must be between 1 and 120 frames per second",
                self.fps
            ));
        }
        if format == VideoFormat::Gif && self.fps > GIF_MAX_FPS {
            return Err(format!(
                "--fps = {}: a GIF plays at most {GIF_MAX_FPS} frames per second (its delays are hundredths of a second)",
                self.fps
            ));
        }
        if !(self.speed.is_finite() && self.speed > 0.0 && self.speed <= 1000.0) {
            return Err(format!(
                "--speed = {}: must be a multiple of real time above 0 (at most 1000)",
                self.speed
            ));
        }
        Ok(())
    }

    /// The frames' times (the first run's unit `time_unit_s` seconds): `from`, then one step of
    /// `speed / fps` seconds of motion after another, up to `to`.
    pub fn frame_times(&self, time_unit_s: f64) -> Result<Vec<f64>, String> {
        let step = self.speed / self.fps / time_unit_s;
        let n = ((self.to - self.from) / step + 1e-9).floor() + 1.0;
        if !(n.is_finite() && n <= MAX_FRAMES as f64) {
            return Err(format!(
                "{} to {} at {} frames/s and speed {} is {n} frames, more than {MAX_FRAMES}: a shorter span or a higher --speed",
                self.from, self.to, self.fps, self.speed
            ));
        }
        Ok((0..n as usize).map(|k| self.from + k as f64 * step).collect())
    }
}

/// Opens the encoder for `path` (GIF or MP4 by its extension), frames of `size` at `fps`.
pub fn open_sink(path: &Path, size: [u32; 2], fps: f64) -> Result<Box<dyn FrameSink>, ExportError> {
    match VideoFormat::of(path) {
        Some(VideoFormat::Gif) => Ok(Box::new(GifWriter::create(path, size, fps)?)),
        Some(VideoFormat::Mp4) => Ok(Box::new(Mp4Writer::spawn(path, size, fps)?)),
        None => Err(ExportError::Invalid(format!(
            "{}: a video is a .gif or an .mp4 file",
            path.display()
        ))),
    }
}

/// What was written.
#[derive(Clone, Debug, PartialEq)]
pub struct VideoReport {
    pub path: PathBuf,
    pub frames: usize,
    pub bytes: u64,
    pub size: [u32; 2],
    /// Wall-clock time it took.
    pub seconds: f64,
}

/// Draws the frames of `spec` from `source` at `size` and writes them to `path`.
/// `progress(done, total)` is called after every frame; when it returns false the video is
/// abandoned (its file removed) and the answer is [`ExportError::Cancelled`].
pub fn write_video(
    gpu: &Gpu,
    source: &mut dyn Frames,
    spec: &VideoSpec,
    size: [u32; 2],
    path: &Path,
    progress: &mut dyn FnMut(usize, usize) -> bool,
) -> Result<VideoReport, ExportError> {
    let format = VideoFormat::of(path).ok_or_else(|| {
        ExportError::Invalid(format!("{}: a video is a .gif or an .mp4 file", path.display()))
    })?;
    spec.check(format).map_err(ExportError::Invalid)?;
    let times = spec.frame_times(source.time_unit_s()).map_err(ExportError::Invalid)?;
    let clock = web_time::Instant::now();
    let mut sink = open_sink(path, size, spec.fps)?;
    for (k, &t) in times.iter().enumerate() {
        let pushed =
            source.frame(gpu, t, size).map_err(ExportError::from).and_then(|img| sink.push(&img));
        if let Err(e) = pushed {
            sink.abandon();
            return Err(e);
        }
        if !progress(k + 1, times.len()) {
            sink.abandon();
            return Err(ExportError::Cancelled);
        }
    }
    sink.finish()?;
    let bytes = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
    Ok(VideoReport {
        path: path.to_path_buf(),
        frames: times.len(),
        bytes,
        size,
        seconds: clock.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_step_by_speed_over_fps_seconds_of_motion() {
        let spec = VideoSpec { from: 10.0, to: 50.0, fps: 25.0, speed: 0.25 };
        // The paper's ring: a time unit of 0.04595 s.
        let t = spec.frame_times(0.04595).unwrap();
        let step: f64 = 0.25 / 25.0 / 0.04595;
        assert_eq!(t.len(), (40.0 / step).floor() as usize + 1);
        assert_eq!(t[0], 10.0);
        assert!((t[1] - t[0] - step).abs() < 1e-12);
        assert!(*t.last().unwrap() <= 50.0);
        // Seconds as the time unit: 2 s at real speed and 10 frames/s is 21 frames.
        let spec = VideoSpec { from: 0.0, to: 2.0, fps: 10.0, speed: 1.0 };
        assert_eq!(spec.frame_times(1.0).unwrap().len(), 21);
    }

    #[test]
    fn bad_numbers_are_named() {
        let ok = VideoSpec { from: 0.0, to: 1.0, fps: 25.0, speed: 1.0 };
        assert!(ok.check(VideoFormat::Gif).is_ok());
        let cases = [
            (VideoSpec { from: -1.0, ..ok }, "--from"),
            (VideoSpec { to: 0.0, ..ok }, "--to"),
            (VideoSpec { fps: 0.0, ..ok }, "--fps"),
            (VideoSpec { fps: 60.0, ..ok }, "GIF"),
            (VideoSpec { speed: f64::NAN, ..ok }, "--speed"),
        ];
        for (spec, needle) in cases {
            let e = spec.check(VideoFormat::Gif).unwrap_err();
            assert!(e.contains(needle), "{e}");
        }
        assert!(VideoSpec { fps: 60.0, ..ok }.check(VideoFormat::Mp4).is_ok());
        let long = VideoSpec { from: 0.0, to: 1e9, fps: 25.0, speed: 1.0 };
        assert!(long.frame_times(1.0).unwrap_err().contains("frames"));
    }

    #[test]
    fn the_format_is_the_extension() {
        assert_eq!(VideoFormat::of(Path::new("a/b.GIF")), Some(VideoFormat::Gif));
        assert_eq!(VideoFormat::of(Path::new("b.mp4")), Some(VideoFormat::Mp4));
        assert_eq!(VideoFormat::of(Path::new("b.avi")), None);
        assert_eq!(VideoFormat::of(Path::new("gif")), None);
    }
}
