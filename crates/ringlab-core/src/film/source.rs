//! Where frames come from: a video file decoded by an `ffmpeg` found on PATH (raw 4:2:0 frames
//! through a pipe, one frame in memory at a time), or a folder of numbered PNG, JPEG or TIFF
//! frames read by the `image` crate.

use super::frame::Frame;
use super::{FilmError, FilmErrorKind};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdout, Command, Stdio};
use std::thread::JoinHandle;

/// What the container (or the folder) says of the film.
#[derive(Clone, Debug, PartialEq)]
pub struct FilmInfo {
    pub width: usize,
    pub height: usize,
    /// Frames per second, where the container says it.
    pub fps: Option<f64>,
    /// Number of frames, where the container says it (a film whose rate varies: the frames
    /// at its nominal rate from the first to the last, `missing` of them never taken).
    pub frames: Option<u64>,
    /// Frames a film whose rate varies lacks at its nominal rate (given as blank frames).
    pub missing: u64,
}

/// The extensions read as video files; anything else that is not a folder is a recording.
pub const VIDEO_EXTENSIONS: [&str; 8] = ["mp4", "mov", "avi", "mkv", "webm", "m4v", "mpg", "mpeg"];
const IMAGE_EXTENSIONS: [&str; 5] = ["png", "jpg", "jpeg", "tif", "tiff"];

/// Whether a path names a film (a video file by its extension, or a folder) rather than a
/// recording or a tracker's table.
pub fn is_film(path: &Path) -> bool {
    path.is_dir()
        || path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| VIDEO_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
}

/// A program found on PATH.
pub fn find_program(name: &str) -> Option<PathBuf> {
    let name = if cfg!(windows) { format!("{name}.exe") } else { name.to_string() };
    std::env::split_paths(&std::env::var_os("PATH")?).map(|d| d.join(&name)).find(|p| p.is_file())
}

pub enum FilmSource {
    Video(Video),
    Folder(Folder),
}

impl FilmSource {
    pub fn open(path: &Path) -> Result<FilmSource, FilmError> {
        if path.is_dir() {
            Folder::open(path).map(FilmSource::Folder)
        } else if !path.exists() {
            Err(FilmError::new(path, FilmErrorKind::Io("no such file".into())))
        } else {
            Video::open(path).map(FilmSource::Video)
        }
    }

    pub fn info(&self) -> &FilmInfo {
        match self {
            FilmSource::Video(v) => &v.info,
            FilmSource::Folder(f) => &f.info,
        }
    }

    /// The next frame into `frame` (its buffers reused); `false` at the end.
    pub fn next_frame(&mut self, frame: &mut Frame) -> Result<bool, FilmError> {
        match self {
            FilmSource::Video(v) => v.next_frame(frame),
            FilmSource::Folder(f) => f.next_frame(frame),
        }
    }

    /// Passes over `n` frames without keeping them.
    pub fn skip(&mut self, n: u64) -> Result<u64, FilmError> {
        let mut scratch = Frame::default();
        for i in 0..n {
            if let FilmSource::Folder(f) = self {
                if f.next >= f.files.len() {
                    return Ok(i);
                }
                f.next += 1;
                continue;
            }
            if !self.next_frame(&mut scratch)? {
                return Ok(i);
            }
        }
        Ok(n)
    }
}

/// A video decoded by ffmpeg.
pub struct Video {
    path: PathBuf,
    pub info: FilmInfo,
    child: Child,
    stdout: ChildStdout,
    stderr: Option<JoinHandle<String>>,
    decoded: u64,
    buffer: Vec<u8>,
    ended: bool,
    /// A film whose rate varies: each decoded frame's number at the nominal rate.
    slots: Option<Vec<u64>>,
    /// The number of the next frame given (decoded or, where none was taken, blank).
    next_slot: u64,
}

fn parse_rate(s: &str) -> Option<f64> {
    let (n, d) = s.split_once('/').unwrap_or((s, "1"));
    let (n, d) = (n.trim().parse::<f64>().ok()?, d.trim().parse::<f64>().ok()?);
    let r = n / d;
    (r.is_finite() && r > 0.0).then_some(r)
}

/// The video stream's size, rate and length, from ffprobe, and its nominal rate (the rate
/// its timestamps are counted in, which a film that drops frames keeps above its average).
pub fn probe(path: &Path) -> Result<(FilmInfo, Option<f64>), FilmError> {
    let ffprobe = find_program("ffprobe").ok_or(FilmError::new(path, FilmErrorKind::NoFfmpeg))?;
    let out = Command::new(ffprobe)
        .args(["-v", "error", "-select_streams", "v:0", "-show_entries"])
        .args(["stream=width,height,avg_frame_rate,r_frame_rate,nb_frames:stream_tags=rotate"])
        .args(["-show_entries", "stream_side_data=rotation", "-of"])
        .args(["default=noprint_wrappers=1"])
        .arg(path)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| FilmError::new(path, FilmErrorKind::Io(format!("cannot run ffprobe: {e}"))))?;
    let text = String::from_utf8_lossy(&out.stdout);
    let said = String::from_utf8_lossy(&out.stderr).trim().to_string();
    let get = |k: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(k).and_then(|r| r.strip_prefix('=')))
            .map(str::trim)
    };
    let (Some(w), Some(h)) = (
        get("width").and_then(|v| v.parse::<usize>().ok()),
        get("height").and_then(|v| v.parse::<usize>().ok()),
    ) else {
        let why =
            if said.is_empty() { "no video stream in it".to_string() } else { first_line(&said) };
        return Err(FilmError::new(path, FilmErrorKind::NotAVideo(why)));
    };
    if w < 2 || h < 2 {
        return Err(FilmError::new(path, FilmErrorKind::NotAVideo(format!("frames of {w}x{h}"))));
    }
    let (average, nominal) =
        (get("avg_frame_rate").and_then(parse_rate), get("r_frame_rate").and_then(parse_rate));
    let fps = average.or(nominal);
    let frames = get("nb_frames").and_then(|v| v.parse::<u64>().ok()).filter(|&n| n > 0);
    // A phone held upright stores its frames on their side with a rotation to show them by,
    // which ffmpeg applies when it decodes: the frames come as shown, a quarter turn swapping
    // their width and height.
    let rotation = get("rotation").or(get("TAG:rotate")).and_then(|v| v.parse::<f64>().ok());
    let (w, h) = match rotation {
        Some(r) if (r.abs().round() as i64) % 180 == 90 => (h, w),
        _ => (w, h),
    };
    Ok((FilmInfo { width: w & !1, height: h & !1, fps, frames, missing: 0 }, nominal))
}

/// The slots of a film whose rate varies (`timestamps`), with its info set to the film's own
/// rate; `None` for a steady film, or where the timestamps do not say.
fn variable_rate(path: &Path, info: &mut FilmInfo, nominal: Option<f64>) -> Option<Vec<u64>> {
    let (average, nominal) = (info.fps?, nominal?);
    if !super::timestamps::rate_varies(nominal, average) {
        return None;
    }
    let (rate, slots) = super::timestamps::frame_slots(&find_program("ffprobe")?, path)?;
    let last = *slots.last()?;
    info.fps = Some(rate);
    info.frames = Some(last + 1);
    info.missing = last + 1 - slots.len() as u64;
    Some(slots)
}

fn first_line(s: &str) -> String {
    s.lines().next().unwrap_or("").chars().take(200).collect()
}

impl Video {
    fn open(path: &Path) -> Result<Video, FilmError> {
        let (mut info, nominal) = probe(path)?;
        let slots = variable_rate(path, &mut info, nominal);
        let ffmpeg = find_program("ffmpeg").ok_or(FilmError::new(path, FilmErrorKind::NoFfmpeg))?;
        let mut child = Command::new(ffmpeg)
            .args(["-v", "error", "-nostdin", "-i"])
            .arg(path)
            .args(["-map", "0:v:0", "-an", "-sn", "-vsync", "passthrough"])
            // 4:2:0 needs even sides: an odd last row or column is dropped.
            .args(["-vf", "crop=trunc(iw/2)*2:trunc(ih/2)*2:0:0"])
            .args(["-f", "rawvideo", "-pix_fmt", "yuv420p", "pipe:1"])
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| {
                FilmError::new(path, FilmErrorKind::Io(format!("cannot run ffmpeg: {e}")))
            })?;
        let stdout = child.stdout.take().expect("piped");
        let stderr = child.stderr.take().map(|mut s| {
            std::thread::spawn(move || {
                let mut text = String::new();
                s.read_to_string(&mut text).ok();
                text
            })
        });
        let size = info.width * info.height * 3 / 2;
        Ok(Video {
            path: path.to_path_buf(),
            info,
            child,
            stdout,
            stderr,
            decoded: 0,
            buffer: vec![0; size],
            ended: false,
            slots,
            next_slot: 0,
        })
    }

    fn next_frame(&mut self, frame: &mut Frame) -> Result<bool, FilmError> {
        if self.ended {
            return Ok(false);
        }
        // A frame never taken (a film whose rate varies): blank, where nothing is found.
        if let Some(slot) = self.slots.as_ref().and_then(|s| s.get(self.decoded as usize))
            && *slot > self.next_slot
        {
            let (w, h) = (self.info.width, self.info.height);
            (frame.width, frame.height) = (w, h);
            frame.luma.clear();
            frame.luma.resize(w * h, 0);
            frame.cb.clear();
            frame.cb.resize(w * h / 4, 128);
            frame.cr.clear();
            frame.cr.resize(w * h / 4, 128);
            self.next_slot += 1;
            return Ok(true);
        }
        self.next_slot += 1;
        let mut filled = 0;
        while filled < self.buffer.len() {
            match self.stdout.read(&mut self.buffer[filled..]) {
                Ok(0) => break,
                Ok(n) => filled += n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(FilmError::new(&self.path, FilmErrorKind::Io(e.to_string()))),
            }
        }
        if filled < self.buffer.len() {
            self.ended = true;
            self.finish()?;
            return Ok(false);
        }
        let (w, h) = (self.info.width, self.info.height);
        frame.width = w;
        frame.height = h;
        let (l, c) = (w * h, w * h / 4);
        frame.luma.clear();
        frame.luma.extend_from_slice(&self.buffer[..l]);
        frame.cb.clear();
        frame.cb.extend_from_slice(&self.buffer[l..l + c]);
        frame.cr.clear();
        frame.cr.extend_from_slice(&self.buffer[l + c..l + 2 * c]);
        self.decoded += 1;
        Ok(true)
    }

    /// At the end of the stream: ffmpeg's verdict, and whether every announced frame came.
    fn finish(&mut self) -> Result<(), FilmError> {
        let status = self
            .child
            .wait()
            .map_err(|e| FilmError::new(&self.path, FilmErrorKind::Io(e.to_string())))?;
        let said = self.stderr.take().and_then(|h| h.join().ok()).unwrap_or_default();
        let said = said.trim();
        if !status.success() {
            let why = if said.is_empty() {
                format!("ffmpeg ended with {status}")
            } else {
                first_line(said)
            };
            return Err(FilmError::new(&self.path, FilmErrorKind::NotAVideo(why)));
        }
        // A film cut off mid-stream decodes what it holds and says so on stderr, or comes
        // short of the count its header announces.
        let announced = self.info.frames.map(|n| n - self.info.missing);
        let short = announced.is_some_and(|n| self.decoded + 1 < n);
        let complained = ["partial file", "Invalid data", "error while decoding", "corrupt"]
            .iter()
            .any(|k| said.contains(k));
        if short || complained {
            return Err(FilmError::new(
                &self.path,
                FilmErrorKind::CutOff {
                    decoded: self.decoded,
                    expected: self.info.frames,
                    said: first_line(said),
                },
            ));
        }
        Ok(())
    }
}

impl Drop for Video {
    fn drop(&mut self) {
        if !self.ended {
            self.child.kill().ok();
            self.child.wait().ok();
        }
    }
}

/// A folder of numbered frames, in the order of the numbers in their names.
pub struct Folder {
    pub info: FilmInfo,
    files: Vec<PathBuf>,
    next: usize,
}

/// The name's digits as a number (the last run of digits), for ordering frame files.
fn frame_number(path: &Path) -> Option<u64> {
    let stem = path.file_stem()?.to_str()?;
    let digits: String = stem
        .chars()
        .rev()
        .skip_while(|c| !c.is_ascii_digit())
        .take_while(|c| c.is_ascii_digit())
        .collect();
    digits.chars().rev().collect::<String>().parse().ok()
}

impl Folder {
    fn open(path: &Path) -> Result<Folder, FilmError> {
        let io = |e: std::io::Error| FilmError::new(path, FilmErrorKind::Io(e.to_string()));
        let mut files: Vec<PathBuf> = std::fs::read_dir(path)
            .map_err(io)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                p.is_file()
                    && p.extension().and_then(|e| e.to_str()).is_some_and(|e| {
                        IMAGE_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str())
                    })
            })
            .collect();
        if files.is_empty() {
            return Err(FilmError::new(path, FilmErrorKind::NoFrames));
        }
        files.sort_by(|a, b| (frame_number(a), a).cmp(&(frame_number(b), b)));
        let first = read_image(&files[0])?;
        let info = FilmInfo {
            width: first.width,
            height: first.height,
            fps: None,
            frames: Some(files.len() as u64),
            missing: 0,
        };
        Ok(Folder { info, files, next: 0 })
    }

    fn next_frame(&mut self, frame: &mut Frame) -> Result<bool, FilmError> {
        let Some(file) = self.files.get(self.next) else { return Ok(false) };
        let f = read_image(file)?;
        if (f.width, f.height) != (self.info.width, self.info.height) {
            return Err(FilmError::new(
                file,
                FilmErrorKind::BadFrame(format!(
                    "{}x{} where the first frame is {}x{}",
                    f.width, f.height, self.info.width, self.info.height
                )),
            ));
        }
        *frame = f;
        self.next += 1;
        Ok(true)
    }
}

fn read_image(path: &Path) -> Result<Frame, FilmError> {
    let img = image::ImageReader::open(path)
        .and_then(|r| r.with_guessed_format())
        .map_err(|e| FilmError::new(path, FilmErrorKind::Io(e.to_string())))?
        .decode()
        .map_err(|e| FilmError::new(path, FilmErrorKind::BadFrame(e.to_string())))?
        .to_rgb8();
    let (w, h) = (img.width() as usize, img.height() as usize);
    if w < 2 || h < 2 {
        return Err(FilmError::new(path, FilmErrorKind::BadFrame(format!("an image of {w}x{h}"))));
    }
    Ok(Frame::from_rgb(w, h, img.as_raw()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_files_sort_by_their_numbers() {
        let mut v: Vec<PathBuf> =
            ["f10.png", "f9.png", "f100.png", "f1.png"].iter().map(PathBuf::from).collect();
        v.sort_by(|a, b| (frame_number(a), a).cmp(&(frame_number(b), b)));
        let names: Vec<_> = v.iter().map(|p| p.to_str().unwrap()).collect();
        assert_eq!(names, ["f1.png", "f9.png", "f10.png", "f100.png"]);
        assert_eq!(parse_rate("300/1"), Some(300.0));
        assert_eq!(parse_rate("0/0"), None);
    }
}
