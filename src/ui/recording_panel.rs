//! The recording in the window: the side panel's Recording tab (what was loaded,
//! the fit with its progress and results), the message strip for errors, and the hint shown
//! while a file is dragged over the window. The state lives in [`RecordingSession`] (no egui);
//! these functions only draw it and say what the user asked for.

use super::job_controls::{JobClick, JobView, job_controls_ui};
use super::palette::DATA_COLOR;
use crate::recording::import::Source;
use crate::recording::marks::MarkOrder;
use crate::session::{Fitted, LoadedRecording, RecordingSession};
use eframe::egui::{self, Color32, RichText};

/// What the user asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RecordingAction {
    None,
    Open,
    /// The sample recording that comes with ringlab (a steel ring's four marks, 300 frames/s).
    OpenSample,
    /// File > Open video: a film to track.
    OpenVideo,
    /// Stop tracking a film (or reading a file).
    CancelOpen,
    Close,
    Fit,
    CancelFit,
    /// Back to the fitted model after the sliders moved.
    UseFit,
}

const ERROR_RED: Color32 = Color32::from_rgb(190, 20, 20);

/// A strip with the error (red) or note, each with a button that dismisses it. Nothing when
/// there is neither.
pub fn messages_ui(ui: &mut egui::Ui, session: &mut RecordingSession) {
    if let Some(e) = session.error.clone() {
        ui.horizontal_wrapped(|ui| {
            if ui.small_button("Dismiss").clicked() {
                session.error = None;
            }
            ui.colored_label(ERROR_RED, RichText::new(e).strong());
        });
    }
    if let Some(n) = session.note.clone() {
        ui.horizontal_wrapped(|ui| {
            if ui.small_button("Dismiss").clicked() {
                session.note = None;
            }
            ui.label(n);
        });
    }
}

/// Whether [`messages_ui`] has anything to show.
pub fn has_messages(session: &RecordingSession) -> bool {
    session.error.is_some() || session.note.is_some()
}

/// The Recording tab of the side panel.
/// `fit_in_use`: the simulator runs the fitted model now.
pub fn recording_panel_ui(
    ui: &mut egui::Ui,
    session: &RecordingSession,
    fit_in_use: bool,
) -> RecordingAction {
    let mut action = RecordingAction::None;
    if let Some(p) = session.loading() {
        let progress = session.loading_progress().filter(|p| !p.text.is_empty());
        ui.horizontal(|ui| {
            ui.spinner();
            let what = if crate::film::is_film(p) { "tracking" } else { "reading" };
            ui.label(format!("{what} {}", p.display()));
        });
        if let Some(p) = progress {
            ui.add(egui::ProgressBar::new(p.fraction).text(RichText::new(p.text).small()));
            if ui.button("Cancel").on_hover_text("stop tracking the film").clicked() {
                action = RecordingAction::CancelOpen;
            }
        }
    }
    let Some(l) = session.loaded() else {
        ui.label("No recording loaded.");
        ui.label(RichText::new("File > Open recording…, or drop a recording (format v1, or a DeepLabCut, Tracker or TrackMate file) onto the window; File > Open video… tracks a film's four marks.").small());
        if ui.add_enabled(!session.dialog_open(), egui::Button::new("Open recording…")).clicked()
        {
            action = RecordingAction::Open;
        }
        if ui
            .button("Open the sample recording")
            .on_hover_text(
                "a steel ring's four marks as a camera above films them at 300 frames/s (made from the \
                 model, with 0.5 px of noise), to replay, fit and diagnose",
            )
            .clicked()
        {
            action = RecordingAction::OpenSample;
        }
        return action;
    };
    ui.horizontal(|ui| {
        super::teach::swatch_ui(ui, DATA_COLOR);
        ui.label(RichText::new(l.name()).strong()).on_hover_text(l.path.display().to_string());
    });
    facts_ui(ui, l, session.offset_s());
    ui.add_space(4.0);
    ui.separator();
    ui.label(RichText::new("Fit the model").strong());
    ui.label(
        RichText::new("drag C1..C3 and the start state, by multiple shooting on the marks' pixels (a few seconds)").small(),
    );
    let fit = JobView {
        name: "Fit",
        hover: "runs off the window's thread; the simulator then runs the fitted model",
        progress: session.fit_progress(),
        cancelling: session.fit_cancelling(),
        done: session.fitted().is_some(),
    };
    match job_controls_ui(ui, fit) {
        JobClick::Start => action = RecordingAction::Fit,
        JobClick::Cancel => action = RecordingAction::CancelFit,
        JobClick::None => {}
    }
    if let Some(f) = session.fitted()
        && fit_ui(ui, f, fit_in_use)
    {
        action = RecordingAction::UseFit;
    }
    ui.add_space(6.0);
    if ui.button("Close recording").clicked() {
        action = RecordingAction::Close;
    }
    action
}

/// The wrapping width of a facts grid's values: what the side panel leaves beside the keys
/// (a long note would otherwise widen the panel over the view and the film).
pub(super) fn value_width(ui: &egui::Ui) -> f32 {
    (ui.available_width() - 100.0).max(120.0)
}

fn row(ui: &mut egui::Ui, key: &str, value: String) {
    ui.label(RichText::new(key).small());
    ui.label(RichText::new(value).small());
    ui.end_row();
}

/// A number as a file gives it, or to 6 decimals where it has more (a scale measured from
/// the ring of a film).
fn short_number(x: f64) -> String {
    let s = format!("{x:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    // Exact, or too small for 6 decimals: as it is.
    if s.parse::<f64>().is_ok_and(|v| v == x || v == 0.0) { x.to_string() } else { s.to_string() }
}

/// What the file says and what the recovery found.
fn facts_ui(ui: &mut egui::Ui, l: &LoadedRecording, offset_s: f64) {
    let h = &l.recording.header;
    let m = &l.motion;
    egui::Grid::new("recording-facts")
        .num_columns(2)
        .spacing([10.0, 2.0])
        .max_col_width(value_width(ui))
        .show(ui, |ui| {
            row(
                ui,
                "frames",
                format!("{} at {} fps ({:.2} s)", l.frames().len(), h.fps, l.duration_s()),
            );
            let read = &l.import;
            if read.source != Source::Ringlab {
                row(
                    ui,
                    "read as",
                    format!("{}; marks 1-4: {}", read.source.name(), read.marks.join(", ")),
                );
                if read.low_likelihood > 0 {
                    row(
                        ui,
                        "dropped",
                        format!("{} points below the likelihood threshold", read.low_likelihood),
                    );
                }
            }
            for n in &read.notes {
                row(ui, "note", n.clone());
            }
            let wall = h.thickness_mm.map(|w| format!(", wall {w} mm")).unwrap_or_default();
            row(
                ui,
                "body",
                format!(
                    "{}, outer radius {} mm, width {} mm{wall}",
                    h.shape.name(),
                    h.outer_radius_mm,
                    h.width_mm
                ),
            );
            row(ui, "scale", format!("{} px/mm", short_number(h.px_per_mm)));
            row(
                ui,
                "pixel noise",
                m.noise_px
                    .map_or("unknown".into(), |n| format!("{n:.2} px (from the marks' tracks)")),
            );
            if let Some(note) = m.pose_scatter_note() {
                row(ui, "pose scatter", note);
            }
            row(ui, "marks missing", format!("{} of {}", l.marks_missing(), 4 * l.frames().len()));
            let spin = if m.spin_sign > 0.0 { "counter-clockwise" } else { "clockwise" };
            let order = match m.mark_order {
                MarkOrder::Forward => "clockwise",
                MarkOrder::Reverse => "counter-clockwise",
            };
            row(ui, "spin (from above)", format!("{spin}; marks numbered {order}"));
            row(ui, "turning points", format!("{} of theta", m.turning_points.len()));
            if let Some(p) = m.first_inner_turn {
                row(
                    ui,
                    "first inner turn",
                    format!("frame {:.1} (theta {:.3} rad)", p.at, p.theta),
                );
            }
            if let Some(r) = m.rest_from {
                row(ui, "at rest from", format!("frame {r} ({:.2} s)", r as f64 / l.fps()));
            }
            row(ui, "model's t = 0", format!("{offset_s:.3} s into the recording"));
        });
}

/// The fit's numbers; true when "use the fitted model" was clicked.
fn fit_ui(ui: &mut egui::Ui, f: &Fitted, in_use: bool) -> bool {
    let r = &f.result;
    let pm = |x: f64, s: f64| {
        if s.is_finite() {
            format!("{x:.4} ± {s:.4}")
        } else {
            format!("{x:.4} (not constrained)")
        }
    };
    let per_s = 1.0 / r.units.time_s;
    egui::Grid::new("fit-results")
        .num_columns(2)
        .spacing([10.0, 2.0])
        .max_col_width(value_width(ui))
        .show(ui, |ui| {
            for i in 0..3 {
                row(ui, &format!("C{}", i + 1), pm(r.c[i], r.c_sigma[i]));
            }
            row(ui, "theta0", format!("{:.4} rad", r.start.theta));
            row(
                ui,
                "phi'0",
                format!("{:.4} rad/T ({:.2} rad/s)", r.start.phi_dot, r.start.phi_dot * per_s),
            );
            row(
                ui,
                "psi'0",
                format!("{:.4} rad/T ({:.2} rad/s)", r.start.psi_dot, r.start.psi_dot * per_s),
            );
            row(
                ui,
                "start",
                format!("frame {:.2} ({:.4} s)", r.start_frame, r.start_t * r.units.time_s),
            );
            let noise = r.noise_px.map(|n| format!(" (noise {n:.3} px)")).unwrap_or_default();
            row(ui, "misfit", format!("{:.3} px rms{noise}", r.rms_px));
            row(
                ui,
                "frames fitted",
                format!("{} in {} segments", r.frames_fitted, r.segments.len()),
            );
            // The compute time varies from run to run: on hover only (pictures stay the same).
            ui.label(RichText::new("iterations").small());
            ui.label(RichText::new(r.iterations.to_string()).small())
                .on_hover_text(format!("the fit took {:.1} s", r.compute_seconds));
            ui.end_row();
            row(
                ui,
                "units",
                format!("T = {:.5} s, L = {:.2} mm", r.units.time_s, r.units.length_mm),
            );
        });
    ui.label(
        RichText::new(if in_use {
            "The simulator runs the fitted model from the fitted start (the Model tab's sliders hold it)."
        } else {
            "The simulator runs another model now (the sliders moved, or a preset was chosen)."
        })
        .small(),
    );
    ui.button("Use the fitted model")
        .on_hover_text("the fitted drag and start in the simulator again")
        .clicked()
}

/// Over the whole window while a file is dragged over it.
pub fn drop_hint_ui(ctx: &egui::Context) {
    let hovering = ctx.input(|i| i.raw.hovered_files.len());
    if hovering == 0 {
        return;
    }
    let screen = ctx.content_rect();
    let painter = ctx.layer_painter(egui::LayerId::new(
        egui::Order::Foreground,
        egui::Id::unique("ringlab-drop-hint"),
    ));
    painter.rect_filled(screen, 0.0, Color32::from_black_alpha(140));
    painter.text(
        screen.center(),
        egui::Align2::CENTER_CENTER,
        "Drop a recording (format v1, .csv) or a film (.mp4) to open it",
        egui::FontId::proportional(26.0),
        Color32::WHITE,
    );
}

#[cfg(test)]
mod tests {
    use super::short_number;

    #[test]
    fn numbers_as_given_or_to_six_decimals() {
        assert_eq!(short_number(3.2), "3.2");
        assert_eq!(short_number(12.0), "12");
        assert_eq!(short_number(3.363243426806742), "3.363243");
        assert_eq!(short_number(1e-9), "0.000000001");
    }
}
