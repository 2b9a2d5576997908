//! The film a recording was tracked from, in a panel beside the 3D view: the frame at the time
//! scrubber's time with the tracked marks and the path of A drawn over it, and once fitted or
//! diagnosed the model's marks and path ([`crate::session::overlay::Overlay`]). The session
//! decodes the frames (off the UI thread in the live window); the picture is made here when
//! the frame, the model or the size on the screen changes, and kept as an egui texture.

use super::RinglabApp;
use crate::film::Frame;
use crate::recording::Recording;
use crate::session::ModelMarks;
use crate::session::overlay::{Overlay, frame_image};
use eframe::egui::{self, RichText};
use image::RgbaImage;
use image::imageops::{FilterType, resize};
use std::sync::Arc;

/// What a picture of the film shows: it is made again when any of this changes.
struct Shown {
    /// The recording (held: another film's is another allocation) and its stored frame.
    recording: Arc<Recording>,
    frame: usize,
    /// The model's marks drawn (a new fit's are new ones).
    model: Option<Arc<ModelMarks>>,
    /// The part of the film shown and the picture's size in pixels.
    crop: Crop,
    size: [u32; 2],
}

impl PartialEq for Shown {
    fn eq(&self, o: &Shown) -> bool {
        let same_model = match (&self.model, &o.model) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        };
        Arc::ptr_eq(&self.recording, &o.recording)
            && same_model
            && (self.frame, self.crop, self.size) == (o.frame, o.crop, o.size)
    }
}

/// A rectangle of the film in its pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Crop {
    x: u32,
    y: u32,
    width: u32,
    height: u32,
}

/// The film's picture as a texture, and what it shows.
#[derive(Default)]
pub struct FilmView {
    texture: Option<(Shown, egui::TextureHandle)>,
    /// The whole frame, not only where the ring goes.
    pub whole: bool,
    /// The Tracking section's fields.
    tracking: super::film_tracking::TrackingForm,
}

impl FilmView {
    /// The recording's stored frame the picture shows now, if there is one.
    pub fn frame_shown(&self) -> Option<usize> {
        self.texture.as_ref().map(|(s, _)| s.frame)
    }
}

/// The part of a `w` x `h` film shown: where the marks go over the whole recording with a
/// margin, widened to the film's proportions (the whole frame where no mark was found).
fn crop_of(rec: &Recording, w: u32, h: u32) -> Crop {
    let whole = Crop { x: 0, y: 0, width: w, height: h };
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in rec.frames.iter().flatten().flatten() {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if !(lo[0] <= hi[0] && lo[1] <= hi[1]) || w == 0 || h == 0 {
        return whole;
    }
    let pad = 0.05 * (hi[0] - lo[0]).max(hi[1] - lo[1]) + 24.0;
    let (mut cw, mut ch) = (hi[0] - lo[0] + 2.0 * pad, hi[1] - lo[1] + 2.0 * pad);
    let aspect = w as f64 / h as f64;
    if cw / ch < aspect {
        cw = ch * aspect;
    } else {
        ch = cw / aspect;
    }
    let (cw, ch) = (cw.min(w as f64).round(), ch.min(h as f64).round());
    let x = ((lo[0] + hi[0] - cw) / 2.0).clamp(0.0, w as f64 - cw).round();
    let y = ((lo[1] + hi[1] - ch) / 2.0).clamp(0.0, h as f64 - ch).round();
    Crop { x: x as u32, y: y as u32, width: (cw as u32).max(1), height: (ch as u32).max(1) }
}

/// Frame `i` of `rec`, the part `crop`, as a picture of `size` pixels with the overlay drawn
/// at that size (so that its marks and lines stay as thick as drawn at any scale).
fn film_picture(
    frame: &Frame,
    rec: &Recording,
    model: Option<&[Option<[[f64; 2]; 4]>]>,
    i: usize,
    (crop, size): (Crop, [u32; 2]),
) -> RgbaImage {
    let full = frame_image(frame);
    if [crop.width, crop.height] == size && crop.x == 0 && crop.y == 0 {
        let mut img = full;
        Overlay { tracked: rec, model }.draw(&mut img, i);
        return img;
    }
    let part = image::imageops::crop_imm(&full, crop.x, crop.y, crop.width, crop.height);
    let mut img = resize(&*part, size[0], size[1], FilterType::Triangle);
    let k = size[0] as f64 / crop.width as f64;
    let to = |p: [f64; 2]| [(p[0] - crop.x as f64) * k, (p[1] - crop.y as f64) * k];
    let mut moved = rec.clone();
    for f in &mut moved.frames {
        *f = f.map(|m| m.map(to));
    }
    let moved_model: Option<Vec<Option<[[f64; 2]; 4]>>> =
        model.map(|m| m.iter().map(|x| x.map(|p| p.map(to))).collect());
    Overlay { tracked: &moved, model: moved_model.as_deref() }.draw(&mut img, i);
    img
}

/// The size in pixels of a picture of `crop` that fits `room` (pixels), at most 4 times its
/// own.
fn fit_size(crop: Crop, room: egui::Vec2) -> [u32; 2] {
    let (w, h) = (crop.width.max(1) as f32, crop.height.max(1) as f32);
    let k = (room.x / w).min(room.y / h).clamp(0.05, 4.0);
    [((w * k).round() as u32).max(1), ((h * k).round() as u32).max(1)]
}

impl RinglabApp {
    /// The recording's stored frame the film panel shows now (None: no film, or no frame yet).
    pub fn film_frame_shown(&self) -> Option<usize> {
        self.film_view.frame_shown()
    }

    /// The film panel's width in points, given the space left beside the side panels: half
    /// of it at most, less where the film's height sets it.
    pub(super) fn film_panel_width(&self, room: egui::Vec2) -> f32 {
        let Some(f) = self.recording.film() else { return 0.0 };
        let (w, h) = (f.report.width_px.max(1) as f32, f.report.height_px.max(1) as f32);
        let by_height = (room.y - 40.0).max(80.0) * w / h;
        (0.5 * room.x).min(by_height).max(120.0)
    }

    /// The film at the clock's time with the overlay (the panel's contents).
    pub(super) fn film_panel_ui(&mut self, ui: &mut egui::Ui) {
        self.recording.want_film_frame(self.player.seconds());
        let Some(film) = self.recording.film() else { return };
        let name = film
            .path
            .file_name()
            .map_or_else(|| film.path.display().to_string(), |n| n.to_string_lossy().into_owned());
        let first = film.options.from_frame;
        let model = self.recording.model_marks();
        let whole = &mut self.film_view.whole;
        ui.horizontal_wrapped(|ui| {
            ui.label(RichText::new(format!("film: {name}")).strong());
            if let Some((i, _)) = self.recording.film_frame() {
                ui.label(RichText::new(format!("frame {}", first + i as u64)).small());
            }
            ui.checkbox(whole, RichText::new("whole frame").small())
                .on_hover_text("the whole frame, not only where the ring goes");
        });
        let busy = self.recording.loading_progress().is_some();
        let again =
            super::film_tracking::film_tracking_ui(ui, &mut self.film_view.tracking, film, busy);
        let legend = if model.is_some() {
            "circles: the tracked marks, orange: their path of A; white crosses: the model's marks, cyan: its path"
        } else {
            "circles: the tracked marks, orange: their path of A (fit or diagnose to draw the model too)"
        };
        ui.label(RichText::new(legend).small());
        if let Some(e) = self.recording.film_error() {
            ui.colored_label(ui.visuals().error_fg_color, RichText::new(e).small());
        }
        if let Some(options) = again {
            self.recording.track_film_again(options);
            return;
        }
        let Some((i, frame)) = self.recording.film_frame() else {
            ui.horizontal(|ui| {
                ui.spinner();
                ui.label("decoding the film…");
            });
            return;
        };
        let Some(l) = self.recording.loaded() else { return };
        let (w, h) = (frame.width as u32, frame.height as u32);
        let crop = if self.film_view.whole {
            Crop { x: 0, y: 0, width: w, height: h }
        } else {
            crop_of(&l.recording, w, h)
        };
        let ppp = ui.ctx().pixels_per_point();
        let size = fit_size(crop, ui.available_size() * ppp);
        let shown = Shown {
            recording: Arc::clone(&l.recording),
            frame: i,
            model: model.cloned(),
            crop,
            size,
        };
        if self.film_view.texture.as_ref().is_none_or(|(s, _)| *s != shown) {
            let marks = model.map(|m| m.as_slice());
            let img = film_picture(frame, &l.recording, marks, i, (crop, size));
            let color = egui::ColorImage::from_rgba_unmultiplied(
                [img.width() as usize, img.height() as usize],
                img.as_raw(),
            );
            let options = egui::TextureOptions::LINEAR;
            match &mut self.film_view.texture {
                Some((s, t)) => {
                    t.set(color, options);
                    *s = shown;
                }
                None => {
                    let t = ui.ctx().load_texture("ringlab-film", color, options);
                    self.film_view.texture = Some((shown, t));
                }
            }
        }
        if let Some((_, t)) = &self.film_view.texture {
            let points = egui::vec2(size[0] as f32, size[1] as f32) / ppp;
            let r = ui.add(egui::Image::new((t.id(), points)));
            let label = format!("film frame {}", first + i as u64);
            r.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Image, true, &label));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_picture_fits_its_room() {
        let film = Crop { x: 0, y: 0, width: 1280, height: 1024 };
        assert_eq!(fit_size(film, egui::vec2(640.0, 2000.0)), [640, 512]);
        assert_eq!(fit_size(film, egui::vec2(2000.0, 512.0)), [640, 512]);
        let part = Crop { x: 10, y: 20, width: 100, height: 80 };
        assert_eq!(fit_size(part, egui::vec2(4000.0, 4000.0)), [400, 320], "4 times at most");
    }

    #[test]
    fn the_part_shown_is_where_the_marks_go_in_the_films_proportions() {
        let header = crate::recording::Header {
            fps: 300.0,
            px_per_mm: 3.0,
            shape: crate::physics::Shape::Ring,
            outer_radius_mm: 20.0,
            width_mm: 18.0,
            thickness_mm: Some(1.0),
            image_width_px: None,
            image_height_px: None,
            camera_distance_mm: None,
            camera_tilt_deg: None,
            extra: Vec::new(),
        };
        let rec = |frames| Recording { header: header.clone(), first_frame: 0, frames };
        let two = [Some([600.0, 500.0]), Some([700.0, 520.0]), None, None];
        let c = crop_of(&rec(vec![two]), 1280, 1024);
        assert!((c.width as f64 / c.height as f64 - 1.25).abs() < 0.02, "{c:?}");
        assert!(c.x <= 600 && c.x + c.width >= 700 && c.y <= 500 && c.y + c.height >= 520);
        assert!(c.width < 400, "{c:?}");
        let none = crop_of(&rec(vec![[None; 4]]), 1280, 1024);
        assert_eq!(none, Crop { x: 0, y: 0, width: 1280, height: 1024 });
        let edge = crop_of(&rec(vec![[Some([1.0, 1.0]), None, None, None]]), 1280, 1024);
        assert_eq!((edge.x, edge.y), (0, 0), "kept inside the frame");
    }
}
