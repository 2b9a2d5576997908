//! What is drawn over a film's frame (Tracker's overlay): the tracked marks and, once fitted,
//! the model's marks and its path of A. The window's film panel shows it; `export::overlay`
//! writes it as an MP4.

use crate::film::Frame;
use crate::recording::{FrameMarks, Recording};
use image::{Rgba, RgbaImage};

/// The marks' colours, 1 to 4 (as the shared films paint them: red, green, blue, yellow).
pub const MARK_COLOURS: [[u8; 3]; 4] =
    [[230, 40, 40], [40, 200, 60], [50, 90, 240], [240, 210, 30]];
const MODEL: [u8; 3] = [255, 255, 255];
const PATH_TRACKED: [u8; 3] = [255, 140, 0];
const PATH_MODEL: [u8; 3] = [0, 220, 255];

/// What is drawn over one film: the tracked marks, and the model's where there is one.
pub struct Overlay<'a> {
    pub tracked: &'a Recording,
    /// The model's marks by stored frame of `tracked` (`None` where it has none).
    pub model: Option<&'a [Option<[[f64; 2]; 4]>]>,
}

fn blend(img: &mut RgbaImage, x: i64, y: i64, c: [u8; 3], alpha: f64) {
    if x < 0 || y < 0 || x >= img.width() as i64 || y >= img.height() as i64 {
        return;
    }
    let p = img.get_pixel_mut(x as u32, y as u32);
    for k in 0..3 {
        p[k] = (p[k] as f64 * (1.0 - alpha) + c[k] as f64 * alpha).round() as u8;
    }
}

/// A circle of radius `r` and line width about a pixel, anti-aliased.
fn circle(img: &mut RgbaImage, cx: f64, cy: f64, r: f64, c: [u8; 3]) {
    let reach = (r + 2.0).ceil() as i64;
    for y in cy as i64 - reach..=cy as i64 + reach {
        for x in cx as i64 - reach..=cx as i64 + reach {
            let d = ((x as f64 - cx).hypot(y as f64 - cy) - r).abs();
            if d < 1.0 {
                blend(img, x, y, c, 1.0 - d);
            }
        }
    }
}

/// A cross of half-size `r`.
fn cross(img: &mut RgbaImage, cx: f64, cy: f64, r: f64, c: [u8; 3]) {
    let (x, y) = (cx.round() as i64, cy.round() as i64);
    for d in -(r as i64)..=r as i64 {
        blend(img, x + d, y + d, c, 1.0);
        blend(img, x + d, y - d, c, 1.0);
    }
}

/// A polyline through points, one pixel wide.
fn polyline(img: &mut RgbaImage, points: &[[f64; 2]], c: [u8; 3]) {
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        let n = ((b[0] - a[0]).abs().max((b[1] - a[1]).abs()).ceil() as usize).max(1);
        for i in 0..=n {
            let t = i as f64 / n as f64;
            let (x, y) = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]));
            blend(img, x.round() as i64, y.round() as i64, c, 0.8);
        }
    }
}

fn centre(marks: &FrameMarks) -> Option<[f64; 2]> {
    crate::film::follow::centre_of(marks)
}

impl Overlay<'_> {
    /// Draws stored frame `i`'s overlay on `img`: the path of A up to it (tracked: orange;
    /// model: cyan), the tracked marks (circles in their colours), the model's (white crosses).
    pub fn draw(&self, img: &mut RgbaImage, i: usize) {
        let upto = (i + 1).min(self.tracked.frames.len());
        let tracked_path: Vec<[f64; 2]> =
            self.tracked.frames[..upto].iter().filter_map(centre).collect();
        polyline(img, &tracked_path, PATH_TRACKED);
        if let Some(model) = self.model {
            let path: Vec<[f64; 2]> = model[..upto.min(model.len())]
                .iter()
                .flatten()
                .map(|m| {
                    [
                        m.iter().map(|p| p[0]).sum::<f64>() / 4.0,
                        m.iter().map(|p| p[1]).sum::<f64>() / 4.0,
                    ]
                })
                .collect();
            polyline(img, &path, PATH_MODEL);
        }
        if let Some(marks) = self.tracked.frames.get(i) {
            for (k, m) in marks.iter().enumerate() {
                if let Some(p) = m {
                    circle(img, p[0], p[1], 5.0, MARK_COLOURS[k]);
                }
            }
        }
        if let Some(Some(m)) = self.model.and_then(|m| m.get(i)) {
            for p in m {
                cross(img, p[0], p[1], 4.0, MODEL);
            }
        }
    }
}

/// A frame as an image.
pub fn frame_image(frame: &Frame) -> RgbaImage {
    RgbaImage::from_raw(frame.width as u32, frame.height as u32, frame.to_rgba())
        .unwrap_or_else(|| RgbaImage::from_pixel(1, 1, Rgba([0, 0, 0, 255])))
}
