//! The side panel's Diagnose tab: the diagnosis of the loaded recording (`analysis::diagnose`)
//! told as `ringlab diagnose` tells it: what was left out and why, the mismatch window, the
//! misfit before and after, the candidates ranked; the baseline and the improved model against
//! the data (the trace of point A in the image, the residual against time with the mismatch
//! shaded); buttons that put either model in the simulator. The state is the session's
//! ([`RecordingSession`]); this only draws it and says what the user asked for.

use super::job_controls::{JobClick, JobView, job_controls_ui};
use super::palette::{BASELINE_COLOR, DATA_COLOR, IMPROVED_COLOR, MISMATCH_COLOR, MISMATCH_FILL};
use super::plots::thin;
use crate::analysis::diagnose::{Diagnosis, Finding};
use crate::session::{Diagnosed, DiagnosedModel, RecordingSession};
use eframe::egui::{self, RichText};
use egui_plot::{FilledArea, HLine, Line, Plot, PlotPoints, Points};

/// What the user asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiagnoseAction {
    None,
    Diagnose,
    Cancel,
    /// Run this model of the diagnosis in the simulator.
    Adopt(DiagnosedModel),
}

/// Points of a path in the trace plot at most (every one is triangles on a software rasteriser).
const TRACE_POINTS: usize = 1200;

/// The Diagnose tab. `in_use`: which of the diagnosis's models the simulator runs now.
pub fn diagnose_panel_ui(
    ui: &mut egui::Ui,
    session: &RecordingSession,
    in_use: Option<DiagnosedModel>,
) -> DiagnoseAction {
    let mut action = DiagnoseAction::None;
    ui.label(RichText::new("Diagnose the recording").strong());
    ui.label(
        RichText::new(
            "Where do model and recording part, and what physics was left out? The paper's model and one \
             model per suspect (Reynolds drag, rolling and pivot friction, slip, air drag on the travel, \
             lens distortion) are fitted over the whole run and ranked by BIC (tens of seconds).",
        )
        .small(),
    );
    if session.loaded().is_none() {
        ui.label("Open a recording first (File > Open recording…, or drop one onto the window).");
        return action;
    }
    let job = JobView {
        name: "Diagnose",
        hover: "runs off the window's thread",
        progress: session.diagnose_progress(),
        cancelling: session.diagnose_cancelling(),
        done: session.diagnosed().is_some(),
    };
    match job_controls_ui(ui, job) {
        JobClick::Start => action = DiagnoseAction::Diagnose,
        JobClick::Cancel => action = DiagnoseAction::Cancel,
        JobClick::None => {}
    }
    if let Some(d) = session.diagnosed() {
        ui.separator();
        if let Some(a) = result_ui(ui, d, in_use) {
            action = DiagnoseAction::Adopt(a);
        }
    }
    action
}

fn row(ui: &mut egui::Ui, key: &str, value: String) {
    ui.label(RichText::new(key).small());
    ui.label(RichText::new(value).small());
    ui.end_row();
}

fn pm(v: f64, s: f64) -> String {
    if s.is_finite() { format!("{v:.4} ± {s:.2e}") } else { format!("{v:.4} (not constrained)") }
}

/// The finding, the plots and the buttons; the model asked for, if any.
fn result_ui(
    ui: &mut egui::Ui,
    d: &Diagnosed,
    in_use: Option<DiagnosedModel>,
) -> Option<DiagnosedModel> {
    let r = &d.result;
    let (headline, colour) = match &r.finding {
        Finding::Nothing => ("Left out: nothing the recording can show".to_string(), DATA_COLOR),
        Finding::Named(k) => (
            format!("Left out: {}", k.iter().map(|k| k.name()).collect::<Vec<_>>().join(" + ")),
            MISMATCH_COLOR,
        ),
        Finding::Unexplained { partial } => (
            format!(
                "Left out: something no candidate explains{}",
                partial.as_ref().map_or(String::new(), |p| format!(
                    " ({p} explains {:.0}%, partially: {:.2} px beyond the noise left)",
                    100.0 * p.share,
                    r.excess_px(p.rms_px)
                ))
            ),
            MISMATCH_COLOR,
        ),
    };
    ui.label(RichText::new(headline).strong().size(15.0).color(colour));
    egui::Grid::new("diagnosis-facts")
        .num_columns(2)
        .spacing([10.0, 2.0])
        .max_col_width(super::recording_panel::value_width(ui))
        .show(ui, |ui| {
            let window = r.mismatch.as_ref().map_or("none beyond the noise".to_string(), |m| {
                format!(
                    "{:.2} s to {:.2} s of the recording ({:.2} px rms there)",
                    m.start_s, m.end_s, m.rms_px
                )
            });
            row(ui, "mismatch", window);
            let noise_from = match (&r.noise_correlation, r.noise_from_marks) {
                (Some(c), _) => format!(
                    "from the tracks, {:.3} px read, corrected: correlated {:.2} frame to frame",
                    c.tracks_px,
                    c.rho.get(1).copied().unwrap_or(0.0)
                ),
                (None, true) => "from the tracks".to_string(),
                (None, false) => "from the fit".to_string(),
            };
            row(ui, "pixel noise", format!("{:.3} px ({noise_from})", r.noise_px));
            row(ui, "glitches", format!("{} mark positions left out", r.glitches.len()));
            row(ui, "misfit", format!("{:.3} px -> {:.3} px", r.before.rms_px, r.after.rms_px));
            row(
                ui,
                "beyond the noise",
                format!(
                    "{:.3} px -> {:.3} px",
                    r.excess_px(r.before.rms_px),
                    r.excess_px(r.after.rms_px)
                ),
            );
            for (kind, (v, s)) in
                r.after.also.iter().copied().chain(r.after.strength.map(|s| (r.after.effect, s)))
            {
                row(ui, kind.parameter(), pm(v, s));
            }
            if let Some((v, s)) = r.after.tilt_deg {
                row(ui, "camera tilt (deg)", pm(v, s));
            }
            // Which speed the fitted Re follows: 0 the centre's (the paper's), 1 the rim's.
            if let Some((v, s)) = r.after.rim_share {
                row(ui, "Re speed: rim share", pm(v, s));
            }
            for i in 0..3 {
                row(ui, &format!("C{}", i + 1), pm(r.after.c[i], r.after.c_sigma[i]));
            }
            row(ui, "frames", format!("{} of {} fitted", r.frames_fitted, r.frames));
            // The compute time varies from run to run: on hover only (pictures stay the same).
            ui.label(RichText::new("candidates").small());
            ui.label(RichText::new(format!("{} ranked by BIC", r.candidates.len())))
                .on_hover_text(format!("the diagnosis took {:.1} s", r.compute_seconds));
            ui.end_row();
        });
    ui.add_space(4.0);
    let mut asked = None;
    ui.horizontal_wrapped(|ui| {
        for (which, label, case) in [
            (DiagnosedModel::Improved, "Run the improved model", &d.improved),
            (DiagnosedModel::Baseline, "Run the baseline", &d.baseline),
        ] {
            let shown = if in_use == Some(which) {
                format!("{label} (running)")
            } else {
                label.to_string()
            };
            let hover = match case {
                Ok(c) => c.description.clone(),
                Err(e) => format!("cannot be run: {e}"),
            };
            if ui.add_enabled(case.is_ok(), egui::Button::new(shown)).on_hover_text(hover).clicked()
            {
                asked = Some(which);
            }
        }
    });
    legend_ui(ui, r);
    trace_plot_ui(ui, r);
    residual_plot_ui(ui, r);
    ui.add_space(4.0);
    ui.label(RichText::new(&r.explanation).small());
    ui.add_space(4.0);
    candidates_ui(ui, r);
    asked
}

fn candidates_ui(ui: &mut egui::Ui, r: &Diagnosis) {
    egui::Grid::new("diagnosis-candidates").num_columns(4).spacing([8.0, 1.0]).striped(true).show(
        ui,
        |ui| {
            for h in ["candidate", "rms px", "BIC vs base", "strength"] {
                ui.label(RichText::new(h).small().strong());
            }
            ui.end_row();
            for c in &r.candidates {
                let name = RichText::new(c.effect.name()).small();
                ui.label(if r.finding.named().contains(&c.effect) { name.strong() } else { name });
                ui.label(RichText::new(format!("{:.3}", c.rms_px)).small());
                ui.label(RichText::new(format!("{:+.1}", c.delta_score)).small());
                let s = match (&c.error, c.strength) {
                    (Some(e), _) => format!("not fitted: {e}"),
                    (None, Some((v, _))) => format!("{v:.4}"),
                    (None, None) => String::new(),
                };
                let label = ui.label(RichText::new(s).small());
                if let Some(note) = c.stopped_note() {
                    label.on_hover_text(note);
                }
                ui.end_row();
            }
        },
    );
    ui.label(
        RichText::new(format!(
            "An effect is named when its BIC is at least {} below the baseline's.",
            r.evidence
        ))
        .small(),
    );
}

fn legend_ui(ui: &mut egui::Ui, r: &Diagnosis) {
    ui.horizontal_wrapped(|ui| {
        super::teach::swatch_ui(ui, DATA_COLOR);
        ui.label(RichText::new("data").small());
        super::teach::swatch_ui(ui, BASELINE_COLOR);
        ui.label(RichText::new("baseline").small());
        super::teach::swatch_ui(ui, IMPROVED_COLOR);
        ui.label(RichText::new(format!("with {}", r.after.effects_label())).small());
        if r.mismatch.is_some() {
            super::teach::swatch_ui(ui, MISMATCH_FILL);
            ui.label(RichText::new("mismatch").small());
        }
    });
}

/// Every `k`-th point, so that about `max` remain.
fn every<T: Copy>(v: &[T], max: usize) -> Vec<T> {
    let k = v.len().div_ceil(max.max(1)).max(1);
    v.iter().step_by(k).copied().collect()
}

/// Point A in the image: the data, the baseline and the improved model (image y downwards, as
/// the camera saw it).
fn trace_plot_ui(ui: &mut egui::Ui, r: &Diagnosis) {
    let t = &r.trace;
    let flip = |p: [f64; 2]| [p[0], -p[1]];
    let data: Vec<[f64; 2]> =
        every(&t.data_px.iter().flatten().copied().collect::<Vec<_>>(), TRACE_POINTS)
            .into_iter()
            .map(flip)
            .collect();
    let before: Vec<[f64; 2]> = every(&t.before_px, TRACE_POINTS).into_iter().map(flip).collect();
    let after: Vec<[f64; 2]> = every(&t.after_px, TRACE_POINTS).into_iter().map(flip).collect();
    ui.label(RichText::new("point A in the image (px)").small());
    Plot::new("diagnosis-trace")
        .height(200.0)
        .data_aspect(1.0)
        .allow_scroll(false)
        .show_background(false)
        .grid_spacing(egui::Rangef::new(24.0, 300.0))
        .y_axis_formatter(|m, _| format!("{:.0}", -m.value))
        .show(ui, |p| {
            p.points(Points::new("data", PlotPoints::new(data)).color(DATA_COLOR).radius(1.0));
            p.line(Line::new("baseline", PlotPoints::new(before)).color(BASELINE_COLOR).width(1.2));
            p.line(Line::new("improved", PlotPoints::new(after)).color(IMPROVED_COLOR).width(1.2));
        });
}

/// The residual against time (RMS over each frame's marks), both models, the noise level, the
/// mismatch window shaded.
fn residual_plot_ui(ui: &mut egui::Ui, r: &Diagnosis) {
    let s = &r.residuals;
    let series = |v: &[f64]| -> Vec<[f64; 2]> {
        let pts: Vec<[f64; 2]> =
            s.t_s.iter().zip(v).filter(|(_, y)| y.is_finite()).map(|(&t, &y)| [t, y]).collect();
        thin(&pts, 400)
    };
    let before = series(&s.before_px);
    let after = series(&s.after_px);
    let hi = before.iter().chain(&after).map(|p| p[1]).fold(r.noise_px, f64::max) * 1.05;
    ui.label(RichText::new("residual against time (px rms per frame)").small());
    Plot::new("diagnosis-residual")
        .height(150.0)
        .allow_scroll(false)
        .show_background(false)
        .grid_spacing(egui::Rangef::new(24.0, 300.0))
        .x_axis_label("recording time (s)")
        .include_y(0.0)
        .show(ui, |p| {
            if let Some(m) = &r.mismatch {
                let xs = [m.start_s, m.start_s, m.end_s, m.end_s];
                p.add(
                    FilledArea::new("mismatch", &xs, &[0.0; 4], &[0.0, hi, hi, 0.0])
                        .fill_color(MISMATCH_FILL)
                        .allow_hover(false),
                );
            }
            p.line(Line::new("baseline", PlotPoints::new(before)).color(BASELINE_COLOR).width(1.2));
            p.line(Line::new("improved", PlotPoints::new(after)).color(IMPROVED_COLOR).width(1.2));
            p.hline(
                HLine::new("noise", r.noise_px).color(egui::Color32::from_gray(120)).width(1.0),
            );
        });
}
