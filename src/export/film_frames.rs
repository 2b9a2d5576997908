//! A planned film drawn and written: each frame through the scene renderer at `supersample`
//! times the size, averaged down in linear light (what a sensor's pixel collects), then handed
//! to the MP4 encoder or a folder of PNG frames.

use super::ExportError;
use super::film::{FILM_METAL, FilmPlan};
use super::mp4::Mp4Writer;
use super::sink::FrameSink;
use crate::recording::marks::mark_radius;
use crate::render::{
    BodyDraw, BodyGeometry, BodyPose, CameraView, Gpu, MarkDiscs, RenderError, SceneFrame,
    SceneRenderer,
};
use glam::Vec2;
use image::RgbaImage;
use std::path::{Path, PathBuf};

/// What was written.
#[derive(Clone, Debug, PartialEq)]
pub struct FilmReport {
    pub path: PathBuf,
    pub frames: usize,
    pub bytes: u64,
    /// Wall-clock time it took.
    pub seconds: f64,
}

/// The scene of frame `n` (in the case's units, as the renderer draws them), at any multiple
/// of the film's size.
pub fn film_scene(plan: &FilmPlan, n: usize) -> Option<SceneFrame> {
    let s = plan.samples.get(n)?;
    let b = &plan.body;
    let pose = BodyPose::new(s, b);
    let unit = plan.length_mm;
    let geometry = BodyGeometry { r: b.r as f32, h: b.h as f32, w: b.w.min(b.r) as f32 };
    let discs = MarkDiscs {
        circle: mark_radius(b) as f32,
        radius: (0.5 * plan.spec.mark_diameter_mm / unit) as f32,
        colours: plan.spec.marks.paint(),
    };
    let [w, h] = plan.spec.size.map(f64::from);
    let height = h / plan.px_per_unit();
    let centre = Vec2::new((plan.centre_mm[0] / unit) as f32, (plan.centre_mm[1] / unit) as f32);
    // Far enough above the ring and the picture that the table does not fade inside it.
    let distance = (10.0 * (b.r + b.h)).max(0.5 * height * (w / h).hypot(1.0));
    Some(SceneFrame {
        camera: CameraView::top_down(centre, height as f32, distance as f32),
        bodies: vec![BodyDraw {
            geometry,
            world_from_ring: pose.world_from_ring,
            color: FILM_METAL,
            contact: pose.contact,
            yields: false,
            discs: Some(discs),
        }],
        traces: Vec::new(),
        scale: b.r as f32,
        grid_spacing: 0.0,
        focus: centre,
    })
}

/// Frame `n` of the film at its size.
pub fn film_frame(
    gpu: &Gpu,
    renderer: &mut SceneRenderer,
    plan: &FilmPlan,
    n: usize,
) -> Result<RgbaImage, RenderError> {
    let frame = film_scene(plan, n).ok_or_else(|| RenderError::Readback("no such frame".into()))?;
    let ss = plan.spec.supersample.max(1);
    let [w, h] = plan.spec.size;
    let big = gpu.render_scene(renderer, &frame, [w * ss, h * ss])?;
    Ok(average_down(&big, ss))
}

/// `img` shrunk by `k` in each direction, each pixel the mean of its `k x k` block in linear
/// light: a block's centre is the pixel's centre, so positions carry over exactly.
pub fn average_down(img: &RgbaImage, k: u32) -> RgbaImage {
    if k <= 1 {
        return img.clone();
    }
    let linear: Vec<f32> = (0..=255u8).map(|v| decode(v as f32 / 255.0)).collect();
    let (w, h) = (img.width() / k, img.height() / k);
    let n = (k * k) as f32;
    RgbaImage::from_fn(w, h, |x, y| {
        let mut sum = [0.0f32; 3];
        for j in 0..k {
            for i in 0..k {
                let p = img.get_pixel(x * k + i, y * k + j);
                for c in 0..3 {
                    sum[c] += linear[p[c] as usize];
                }
            }
        }
        let px = sum.map(|s| (encode(s / n) * 255.0).round().clamp(0.0, 255.0) as u8);
        image::Rgba([px[0], px[1], px[2], 255])
    })
}

fn decode(x: f32) -> f32 {
    if x <= 0.04045 { x / 12.92 } else { ((x + 0.055) / 1.055).powf(2.4) }
}

fn encode(x: f32) -> f32 {
    if x <= 0.0031308 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 }
}

/// Where the frames go: an MP4 (by its extension) or a folder of numbered PNG files.
fn open(path: &Path, plan: &FilmPlan) -> Result<Box<dyn FrameSink>, ExportError> {
    let is_mp4 = path.extension().and_then(|e| e.to_str()).map(|e| e.eq_ignore_ascii_case("mp4"));
    match is_mp4 {
        Some(true) => Ok(Box::new(Mp4Writer::spawn(path, plan.spec.size, plan.spec.fps)?)),
        _ if path.extension().is_none() => {
            Ok(Box::new(super::png_folder::PngFolder::create(path)?))
        }
        _ => Err(ExportError::Invalid(format!(
            "{}: a film is an .mp4 file or a folder (a name without an extension) of PNG frames",
            path.display()
        ))),
    }
}

/// Draws every frame of `plan` and writes them to `path`. `progress(done, total)` is called
/// after every frame; when it returns false the film is abandoned (its file removed) and the
/// answer is [`ExportError::Cancelled`].
pub fn write_film(
    gpu: &Gpu,
    plan: &FilmPlan,
    path: &Path,
    progress: &mut dyn FnMut(usize, usize) -> bool,
) -> Result<FilmReport, ExportError> {
    let clock = web_time::Instant::now();
    let mut renderer = SceneRenderer::new(&gpu.device, None);
    let mut sink = open(path, plan)?;
    let total = plan.samples.len();
    for n in 0..total {
        let pushed = film_frame(gpu, &mut renderer, plan, n)
            .map_err(ExportError::from)
            .and_then(|img| sink.push(&img));
        if let Err(e) = pushed {
            sink.abandon();
            return Err(e);
        }
        if !progress(n + 1, total) {
            sink.abandon();
            return Err(ExportError::Cancelled);
        }
    }
    sink.finish()?;
    let bytes = super::png_folder::size_of_path(path);
    Ok(FilmReport {
        path: path.to_path_buf(),
        frames: total,
        bytes,
        seconds: clock.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn averaging_down_keeps_flat_colours_and_block_centres() {
        let mut img = RgbaImage::from_pixel(6, 6, image::Rgba([200, 100, 50, 255]));
        assert_eq!(average_down(&img, 3).get_pixel(1, 1), &image::Rgba([200, 100, 50, 255]));
        // One bright block of 3x3 becomes one pixel, the others stay dark.
        img = RgbaImage::from_pixel(6, 6, image::Rgba([0, 0, 0, 255]));
        for (x, y) in [(3, 0), (4, 0), (5, 0), (3, 1), (4, 1), (5, 1), (3, 2), (4, 2), (5, 2)] {
            img.put_pixel(x, y, image::Rgba([255, 255, 255, 255]));
        }
        let small = average_down(&img, 3);
        assert_eq!(small.dimensions(), (2, 2));
        assert_eq!(small.get_pixel(1, 0)[0], 255);
        assert_eq!(small.get_pixel(0, 0)[0], 0);
        // Half covered: half the light, encoded.
        img.put_pixel(3, 0, image::Rgba([0, 0, 0, 255]));
        let v = average_down(&img, 3).get_pixel(1, 0)[0];
        assert_eq!(v, (encode(8.0 / 9.0) * 255.0).round() as u8);
    }
}
