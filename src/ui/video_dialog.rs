//! File > Export video…: a window with the command line's choices (view, from, to, frames per
//! second, speed, size, GIF or MP4), then the file dialog; while the video is made, its
//! progress and Cancel.

use crate::export::session::{ExportSession, VideoRequest};
use crate::export::{VideoFormat, VideoSpec, View};
use crate::sim::{SPEED_MAX, SPEED_MIN};
use eframe::egui::{self, Color32, DragValue, RichText};

/// The window's choices (kept while the app runs).
#[derive(Clone, Debug, PartialEq)]
pub struct VideoDialog {
    pub open: bool,
    pub view: View,
    pub spec: VideoSpec,
    pub size: [u32; 2],
    pub format: VideoFormat,
}

impl Default for VideoDialog {
    fn default() -> Self {
        VideoDialog {
            open: false,
            view: View::ThreeD,
            spec: VideoSpec { from: 0.0, to: 40.0, fps: 25.0, speed: 0.25 },
            size: [640, 360],
            format: VideoFormat::Gif,
        }
    }
}

impl VideoDialog {
    /// Opens it for a run seen up to `now` (ending at `end`, when known) played at `speed`.
    pub fn show(&mut self, now: f64, end: Option<f64>, speed: f64) {
        self.open = true;
        self.spec.speed = speed;
        self.spec.from = 0.0;
        self.spec.to = if now > 0.0 { now } else { end.unwrap_or(self.spec.to) };
    }

    pub fn request(&self) -> VideoRequest {
        VideoRequest { view: self.view, spec: self.spec, size: self.size, format: self.format }
    }
}

/// What the window asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum VideoDialogAction {
    None,
    /// Choose the file, then make the video.
    Export(VideoRequest),
    Cancel,
}

/// The window (nothing when closed). `time` is the time unit's label, `time_s` its seconds.
pub fn video_dialog_ui(
    ctx: &egui::Context,
    d: &mut VideoDialog,
    exports: &ExportSession,
    time: &str,
    time_s: f64,
) -> VideoDialogAction {
    let mut action = VideoDialogAction::None;
    let mut open = d.open;
    let window =
        egui::Window::new("Export video").open(&mut open).resizable(false).collapsible(false);
    // In the middle, off the top bar and the message strip (where the outcome is said).
    let window = window.pivot(egui::Align2::CENTER_CENTER).default_pos(ctx.content_rect().center());
    window.show(ctx, |ui| {
        egui::Grid::new("video-choices").num_columns(2).spacing([12.0, 6.0]).show(ui, |ui| {
            ui.label("show");
            ui.horizontal(|ui| {
                for v in View::ALL {
                    ui.radio_value(&mut d.view, v, v.name());
                }
            });
            ui.end_row();
            let l = ui.label("from");
            ui.add(
                DragValue::new(&mut d.spec.from)
                    .range(0.0..=f64::MAX)
                    .speed(0.5)
                    .suffix(format!(" {time}")),
            )
            .labelled_by(l.id);
            ui.end_row();
            let l = ui.label("to");
            ui.add(
                DragValue::new(&mut d.spec.to)
                    .range(0.0..=f64::MAX)
                    .speed(0.5)
                    .suffix(format!(" {time}")),
            )
            .labelled_by(l.id);
            ui.end_row();
            let l = ui.label("frames per second");
            ui.add(DragValue::new(&mut d.spec.fps).range(1.0..=120.0).speed(1.0)).labelled_by(l.id);
            ui.end_row();
            let l = ui.label("speed");
            ui.add(
                DragValue::new(&mut d.spec.speed)
                    .range(SPEED_MIN..=SPEED_MAX)
                    .speed(0.01)
                    .suffix("x real time"),
            )
            .labelled_by(l.id);
            ui.end_row();
            let l = ui.label("size (pixels)");
            ui.horizontal(|ui| {
                ui.add(DragValue::new(&mut d.size[0]).range(16..=4096).prefix("w "))
                    .labelled_by(l.id);
                ui.add(DragValue::new(&mut d.size[1]).range(16..=4096).prefix("h "))
                    .labelled_by(l.id);
            });
            ui.end_row();
            ui.label("file");
            ui.horizontal(|ui| {
                ui.radio_value(&mut d.format, VideoFormat::Gif, "GIF");
                ui.radio_value(&mut d.format, VideoFormat::Mp4, "MP4 (needs ffmpeg)");
            });
            ui.end_row();
        });
        let problem = d.spec.check(d.format).err().or_else(|| d.spec.frame_times(time_s).err());
        let frames = d.spec.frame_times(time_s).map(|t| t.len()).unwrap_or(0);
        ui.label(
            RichText::new(format!(
                "{frames} frames, {:.1} s of video",
                frames as f64 / d.spec.fps.max(1.0)
            ))
            .small(),
        );
        if let Some(p) = &problem {
            ui.colored_label(Color32::from_rgb(190, 20, 20), p.replace("--", ""));
        }
        match exports.video_progress() {
            Some(p) => {
                ui.add(egui::ProgressBar::new(p.fraction).text(p.text).animate(true));
                let cancelling = exports.video_cancelling();
                if ui
                    .add_enabled(
                        !cancelling,
                        egui::Button::new(if cancelling { "Cancelling…" } else { "Cancel" }),
                    )
                    .clicked()
                {
                    action = VideoDialogAction::Cancel;
                }
            }
            None => {
                let ok = problem.is_none() && !exports.dialog_open();
                if ui
                    .add_enabled(ok, egui::Button::new("Export…"))
                    .on_hover_text(
                        "choose the file, then the video is made off the window's thread",
                    )
                    .clicked()
                {
                    action = VideoDialogAction::Export(d.request());
                }
            }
        }
    });
    d.open = open;
    action
}
