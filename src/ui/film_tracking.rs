//! The film panel's "Tracking": what `ringlab track`'s flags say for a film (the marks'
//! style, the frames, the region, the scale), filled in from how the open film was tracked,
//! and "Track again" with them. The form is text, as the import dialog's is, so that a number
//! half typed is never taken; a bad one is named beside the button.

use crate::film::{MarkStyle, Roi, TrackOptions};
use crate::session::FilmOrigin;
use eframe::egui::{self, RichText};
use std::path::PathBuf;

/// The form's fields, as typed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TrackingForm {
    /// The film the fields were filled in from (filled again when another opens).
    film: Option<(PathBuf, u64)>,
    style: Option<MarkStyle>,
    from: String,
    to: String,
    roi: String,
    scale: String,
    error: Option<String>,
}

fn whole_number(label: &str, text: &str) -> Result<Option<u64>, String> {
    let t = text.trim();
    if t.is_empty() {
        return Ok(None);
    }
    t.parse::<u64>()
        .map(Some)
        .map_err(|_| format!("{label} '{t}': not a frame number (0, 1, 2, ...)"))
}

impl TrackingForm {
    /// The fields as `options` set them.
    fn fill(&mut self, film: &FilmOrigin) {
        let o = &film.options;
        self.film = Some((film.path.clone(), o.from_frame));
        self.style = Some(o.style);
        self.from = if o.from_frame == 0 { String::new() } else { o.from_frame.to_string() };
        self.to = o.to_frame.map(|v| v.to_string()).unwrap_or_default();
        self.roi =
            o.roi.map(|r| format!("{},{},{},{}", r.x, r.y, r.width, r.height)).unwrap_or_default();
        self.scale = o.px_per_mm.map(|v| v.to_string()).unwrap_or_default();
        self.error = None;
    }

    /// The options the fields give over `base` (the body and the frame rate stay), or what is
    /// wrong with them.
    pub fn options(&self, base: &TrackOptions) -> Result<TrackOptions, String> {
        let from = whole_number("first frame", &self.from)?.unwrap_or(0);
        let to = whole_number("last frame", &self.to)?;
        if let Some(to) = to
            && to <= from
        {
            return Err(format!("last frame {to}: must come after the first ({from})"));
        }
        let roi =
            match self.roi.trim() {
                "" => None,
                r => Some(Roi::parse(r).ok_or_else(|| {
                    format!("region '{r}': not X,Y,W,H (pixels, W and H positive)")
                })?),
            };
        let px_per_mm = match self.scale.trim() {
            "" => None,
            s => match s.parse::<f64>() {
                Ok(v) if v.is_finite() && v > 0.0 => Some(v),
                _ => return Err(format!("scale '{s}': not a positive number of px per mm")),
            },
        };
        Ok(TrackOptions {
            style: self.style.unwrap_or(MarkStyle::Auto),
            roi,
            from_frame: from,
            to_frame: to,
            px_per_mm,
            ..base.clone()
        })
    }
}

fn field_ui(ui: &mut egui::Ui, label: &str, text: &mut String, hint: &str, width: f32) {
    ui.label(RichText::new(label).small());
    ui.add(egui::TextEdit::singleline(text).hint_text(hint).desired_width(width));
}

/// The Tracking section under the film's name; the options to track the film again with, on
/// the button.
pub fn film_tracking_ui(
    ui: &mut egui::Ui,
    form: &mut TrackingForm,
    film: &FilmOrigin,
    busy: bool,
) -> Option<TrackOptions> {
    if form.film.as_ref() != Some(&(film.path.clone(), film.options.from_frame)) {
        form.fill(film);
    }
    let mut again = None;
    egui::CollapsingHeader::new(RichText::new("Tracking").small()).id_salt("film-tracking").show(
        ui,
        |ui| {
            ui.horizontal_wrapped(|ui| {
                ui.label(RichText::new("marks").small());
                let style = form.style.get_or_insert(MarkStyle::Auto);
                egui::ComboBox::from_id_salt("film-marks").selected_text(style.name()).show_ui(
                    ui,
                    |ui| {
                        for s in [
                            MarkStyle::Auto,
                            MarkStyle::Colours,
                            MarkStyle::Dark,
                            MarkStyle::Bright,
                        ] {
                            ui.selectable_value(style, s, s.name());
                        }
                    },
                );
                field_ui(ui, "frames", &mut form.from, "0", 48.0);
                field_ui(ui, "to", &mut form.to, "the end", 56.0);
            });
            ui.horizontal_wrapped(|ui| {
                field_ui(ui, "region", &mut form.roi, "X,Y,W,H (the whole frame)", 150.0);
                field_ui(ui, "px/mm", &mut form.scale, "from the ring", 90.0);
            });
            ui.horizontal_wrapped(|ui| {
                let button = ui.add_enabled(!busy, egui::Button::new("Track again"));
                if button.clicked() {
                    match form.options(&film.options) {
                        Ok(o) => {
                            form.error = None;
                            again = Some(o);
                        }
                        Err(e) => form.error = Some(e),
                    }
                }
                let told = format!(
                    "tracked: {} marks, {}",
                    film.report.style.name(),
                    if film.options.px_per_mm.is_some() {
                        "the scale given"
                    } else {
                        "the scale from the ring"
                    }
                );
                ui.label(RichText::new(told).small());
            });
            if let Some(e) = &form.error {
                ui.colored_label(ui.visuals().error_fg_color, RichText::new(e).small());
            }
        },
    );
    again
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recording::import::BodyMm;

    fn base() -> TrackOptions {
        TrackOptions {
            fps: Some(240.0),
            ..TrackOptions::for_body(BodyMm {
                shape: crate::physics::Shape::Ring,
                outer_radius_mm: 20.0,
                width_mm: 18.0,
                thickness_mm: Some(1.0),
            })
        }
    }

    #[test]
    fn the_fields_give_the_options_and_keep_the_body_and_rate() {
        let form = TrackingForm {
            style: Some(MarkStyle::Dark),
            from: "12".into(),
            to: " 300 ".into(),
            roi: "10, 20, 300, 200".into(),
            scale: "3.5".into(),
            ..TrackingForm::default()
        };
        let o = form.options(&base()).expect("good fields");
        assert_eq!(o.style, MarkStyle::Dark);
        assert_eq!((o.from_frame, o.to_frame), (12, Some(300)));
        assert_eq!(o.roi, Some(Roi { x: 10.0, y: 20.0, width: 300.0, height: 200.0 }));
        assert_eq!(o.px_per_mm, Some(3.5));
        assert_eq!((o.fps, o.body), (base().fps, base().body));
        let empty = TrackingForm::default().options(&base()).expect("all empty is the default");
        assert_eq!(empty, TrackOptions { style: MarkStyle::Auto, ..base() });
    }

    #[test]
    fn a_bad_field_is_named() {
        let bad = |f: TrackingForm| f.options(&base()).expect_err("refused");
        let e = bad(TrackingForm { from: "x".into(), ..TrackingForm::default() });
        assert!(e.contains("first frame 'x'"), "{e}");
        let e = bad(TrackingForm { from: "50".into(), to: "50".into(), ..TrackingForm::default() });
        assert!(e.contains("must come after"), "{e}");
        let e = bad(TrackingForm { roi: "1,2,3".into(), ..TrackingForm::default() });
        assert!(e.contains("region '1,2,3'"), "{e}");
        let e = bad(TrackingForm { scale: "-2".into(), ..TrackingForm::default() });
        assert!(e.contains("scale '-2'"), "{e}");
    }
}
