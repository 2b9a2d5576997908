//! A film's frames decoded on demand, one at a time in a [`Job`], the last one kept. The film
//! stays open between frames: a later frame is reached by decoding on from the last one (the
//! way playback goes), an earlier one by opening the film again and passing over the frames
//! before it.

use super::job::Job;
use crate::film::{FilmSource, Frame};
use std::path::PathBuf;

/// The film open at frame `next`.
struct Reader {
    source: FilmSource,
    next: u64,
}

/// The film open where the last frame was read, and frame `n` or why it could not be read.
type Decoded = (Option<Reader>, Result<Frame, String>);

/// Reads frame `n` (counted from the film's first), from `reader` where it has not yet passed it.
fn decode(path: &std::path::Path, reader: Option<Reader>, n: u64) -> Decoded {
    let reader = match reader.filter(|r| r.next <= n) {
        Some(r) => Ok(r),
        None => FilmSource::open(path).map(|source| Reader { source, next: 0 }),
    };
    let mut r = match reader {
        Ok(r) => r,
        Err(e) => return (None, Err(e.to_string())),
    };
    let mut frame = Frame::default();
    let read = r.source.skip(n - r.next).and_then(|skipped| {
        r.next += skipped;
        r.source.next_frame(&mut frame)
    });
    match read {
        Ok(true) => {
            r.next += 1;
            (Some(r), Ok(frame))
        }
        Ok(false) => (None, Err(format!("the film has no frame {n}"))),
        Err(e) => (None, Err(e.to_string())),
    }
}

/// The frames of one film, decoded as they are asked for.
pub struct FilmFrames {
    path: PathBuf,
    background: bool,
    reader: Option<Reader>,
    /// The frame being decoded and its job.
    decoding: Option<(u64, Job<Decoded>)>,
    /// The frame asked for while another was being decoded.
    wanted: Option<u64>,
    shown: Option<(u64, Frame)>,
    /// Why the last frame asked for could not be read.
    pub error: Option<String>,
}

impl FilmFrames {
    pub fn new(path: PathBuf, background: bool) -> FilmFrames {
        FilmFrames {
            path,
            background,
            reader: None,
            decoding: None,
            wanted: None,
            shown: None,
            error: None,
        }
    }

    /// Asks for frame `n` of the film (at once in the foreground; else when the frame being
    /// decoded is done).
    pub fn want(&mut self, n: u64) {
        if self.shown.as_ref().is_some_and(|(k, _)| *k == n) {
            self.wanted = None;
            return;
        }
        match &self.decoding {
            Some((k, _)) if *k == n => self.wanted = None,
            Some(_) => self.wanted = Some(n),
            None => self.start(n),
        }
        self.poll();
    }

    fn start(&mut self, n: u64) {
        let (path, reader) = (self.path.clone(), self.reader.take());
        let job = Job::start("film-frame", self.background, move |_| decode(&path, reader, n));
        self.decoding = Some((n, job));
    }

    /// Takes in a decoded frame, without waiting; starts the one asked for since.
    pub fn poll(&mut self) {
        let Some((n, done)) = self.decoding.as_mut().and_then(|(n, j)| Some((*n, j.poll()?)))
        else {
            return;
        };
        self.decoding = None;
        match done {
            Ok((reader, Ok(frame))) => {
                self.reader = reader;
                self.shown = Some((n, frame));
                self.error = None;
            }
            Ok((reader, Err(e))) => {
                self.reader = reader;
                self.error = Some(e);
            }
            Err(lost) => self.error = Some(lost.to_string()),
        }
        if let Some(w) = self.wanted.take() {
            self.want(w);
        }
    }

    /// Waits for the frames asked for (tests; pictures).
    pub fn finish(&mut self) {
        while let Some((_, j)) = self.decoding.as_mut() {
            j.finish();
            self.poll();
        }
    }

    pub fn busy(&self) -> bool {
        self.decoding.is_some()
    }

    /// The last frame decoded, and its number in the film.
    pub fn shown(&self) -> Option<(u64, &Frame)> {
        self.shown.as_ref().map(|(n, f)| (*n, f))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A folder of three frames of 4x2 pixels, each one grey level brighter than the last.
    fn folder() -> PathBuf {
        let dir = std::env::temp_dir().join(format!("ringlab-film-frames-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for i in 0..3u8 {
            let img = image::RgbImage::from_pixel(4, 2, image::Rgb([40 * (i + 1); 3]));
            img.save(dir.join(format!("f{i:03}.png"))).unwrap();
        }
        dir
    }

    #[test]
    fn frames_forward_and_back_and_past_the_end() {
        let dir = folder();
        let mut f = FilmFrames::new(dir.clone(), false);
        let grey = |f: &FilmFrames| f.shown().map(|(n, fr)| (n, fr.to_rgba()[0]));
        f.want(1);
        assert_eq!(grey(&f), Some((1, 80)));
        f.want(2);
        assert_eq!(grey(&f), Some((2, 120)));
        f.want(0);
        assert_eq!(grey(&f), Some((0, 40)), "back: the film opened again");
        f.want(7);
        assert_eq!(grey(&f), Some((0, 40)), "the last good frame stays");
        assert!(f.error.as_deref().is_some_and(|e| e.contains("no frame 7")), "{:?}", f.error);
        assert!(!f.busy());

        // On a thread: asked for while another is decoded, the last one asked for comes.
        let mut f = FilmFrames::new(dir.clone(), true);
        f.want(0);
        f.want(1);
        f.want(2);
        f.finish();
        assert_eq!(grey(&f), Some((2, 120)));
        std::fs::remove_dir_all(&dir).ok();
    }
}
