//! The window's panels around the 3D view.

use super::controls::{self, UnitLabels};
use super::menus::{self, MenuAction};
use super::palette::{BODY_LINEAR, DATA_COLOR};
use super::recording_panel;
use super::recording_view::DataView;
use super::video_dialog::{VideoDialogAction, video_dialog_ui};
use super::{
    Detail3d, RinglabApp, SideTab, diagnose_panel, plots, scene, teach, trace_panel, view3d,
};
use crate::config::load_preset;
use crate::export::session::FileTask;
use crate::render::{OrbitCamera, SceneFrame};
use crate::session::DiagnosedModel;
use crate::sim::Track;
use eframe::egui::{self, RichText};

impl RinglabApp {
    /// The top bar: the menus and the two runs' buttons, then the playback; in presentation
    /// mode the playback has a row of its own (the scale leaves too few points for one).
    pub(super) fn top_bar_ui(&mut self, ui: &mut egui::Ui) {
        if self.presentation.on {
            ui.horizontal(|ui| self.menus_and_runs_ui(ui));
            ui.horizontal(|ui| self.playback_row_ui(ui));
        } else {
            ui.horizontal(|ui| {
                self.menus_and_runs_ui(ui);
                ui.separator();
                self.playback_row_ui(ui);
            });
        }
    }

    fn menus_and_runs_ui(&mut self, ui: &mut egui::Ui) {
        ui.label(RichText::new("ringlab").strong().size(16.0));
        let presenting = self.presentation.on;
        let action = menus::file_menu_ui(ui, &self.recording, &self.exports);
        self.act_on_menu(action);
        let action = menus::view_menu_ui(ui, presenting);
        self.act_on_menu(action);
        if presenting {
            let label = if self.presentation.side_open { "Hide parameters" } else { "Parameters" };
            if ui
                .button(label)
                .on_hover_text("the side panel: the model's parameters, the recording")
                .clicked()
            {
                self.presentation.side_open = !self.presentation.side_open;
            }
            if ui.button("Leave presentation").on_hover_text("F11").clicked() {
                self.act_on_menu(MenuAction::Presentation(false));
            }
        }
        ui.separator();
        if ui
            .button("Ring vs disk")
            .on_hover_text("the paper's ring and its disk-like drag, side by side")
            .clicked()
        {
            self.ring_vs_disk();
        }
        let mut compare = self.settings.compare;
        if ui.checkbox(&mut compare, "side by side").changed() {
            self.set_compare(compare);
        }
    }

    fn playback_row_ui(&mut self, ui: &mut egui::Ui) {
        let time_s = self.runs.first().map(|r| r.time_s()).unwrap_or(1.0);
        let label = self
            .runs
            .first()
            .map(|r| UnitLabels::of(&r.track().case().units).time)
            .unwrap_or_default();
        let end = self.end_seconds().unwrap_or_else(|| self.known_seconds());
        let act = controls::playback_ui(ui, &mut self.player, end, time_s, &label);
        if act.reset {
            self.reset();
        }
        if act.step {
            let dt = self.runs.first().map(|r| r.track().case().dt * r.time_s()).unwrap_or(0.0);
            self.player.step(dt, self.end_seconds());
        }
        if let Some(s) = act.seek {
            self.player.seek(s);
        }
        self.settings.speed = self.player.speed();
    }

    /// The side panel's tabs: the model's parameters, the recording.
    pub(super) fn side_tabs_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.selectable_value(
                &mut self.side_tab,
                SideTab::Model,
                RichText::new("Model").strong(),
            );
            let busy =
                if self.recording.fit_progress().is_some() || self.recording.loading().is_some() {
                    " …"
                } else {
                    ""
                };
            ui.selectable_value(
                &mut self.side_tab,
                SideTab::Recording,
                RichText::new(format!("Recording{busy}")).strong(),
            );
            let busy = if self.recording.diagnose_progress().is_some() { " …" } else { "" };
            ui.selectable_value(
                &mut self.side_tab,
                SideTab::Diagnose,
                RichText::new(format!("Diagnose{busy}")).strong(),
            );
        });
        ui.separator();
    }

    pub(super) fn recording_tab_ui(&mut self, ui: &mut egui::Ui) {
        let in_use = self.recording.fitted().is_some_and(|f| f.case == self.settings.case);
        let action = recording_panel::recording_panel_ui(ui, &self.recording, in_use);
        self.act_on_recording(action);
    }

    pub(super) fn diagnose_tab_ui(&mut self, ui: &mut egui::Ui) {
        let in_use = self.recording.diagnosed().and_then(|d| {
            if d.improved.as_ref().is_ok_and(|c| *c == self.settings.case) {
                Some(DiagnosedModel::Improved)
            } else if d.baseline.as_ref().is_ok_and(|c| *c == self.settings.case) {
                Some(DiagnosedModel::Baseline)
            } else {
                None
            }
        });
        let action = diagnose_panel::diagnose_panel_ui(ui, &self.recording, in_use);
        self.act_on_diagnosis(action);
    }

    /// The recording as shown now, in the first run's units.
    fn data_view(&self) -> Option<DataView> {
        let run = self.runs.first()?;
        let units = run.track().case().units;
        DataView::at(&self.recording, &units, self.player.seconds(), run.time_s())
    }

    pub(super) fn parameters_panel_ui(&mut self, ui: &mut egui::Ui) {
        let second = self.settings.compare && self.settings.edit_second;
        if let Some(name) = controls::preset_picker_ui(ui, "preset", &self.settings.preset) {
            self.load_preset(&name, false);
        }
        if self.settings.compare {
            if let Some(name) =
                controls::preset_picker_ui(ui, "right preset", &self.settings.compare_preset)
            {
                self.load_preset(&name, true);
            }
            ui.horizontal(|ui| {
                ui.label("sliders edit:");
                ui.radio_value(&mut self.settings.edit_second, false, "left");
                ui.radio_value(&mut self.settings.edit_second, true, "right");
            });
        }
        let units = self.runs.get(usize::from(second)).map(|r| r.track().case().units);
        if let Some(u) = &units {
            let text = if u.is_physical() {
                "units: mm, s".to_string()
            } else {
                format!("units: L = mean radius = {:.2} mm, T = {:.4} s", u.length_mm, u.time_s)
            };
            ui.label(RichText::new(text).small());
        }
        ui.separator();
        let (preset, file) = if second {
            (self.settings.compare_preset.clone(), &mut self.settings.compare_case)
        } else {
            (self.settings.preset.clone(), &mut self.settings.case)
        };
        let base = load_preset(&preset).unwrap_or_else(|_| file.clone());
        let change = controls::parameters_ui(ui, file, units.as_ref(), &base);
        ui.separator();
        ui.checkbox(&mut self.settings.continue_on_change, "drag changes continue from now")
            .on_hover_text("off: every change restarts from the initial state");
        ui.checkbox(&mut self.settings.follow, "camera follows the ring");
        ui.checkbox(&mut self.settings.show_contact, "show the contact point's path");
        ui.checkbox(&mut self.settings.show_why, "show why it turns back");
        detail_3d_ui(ui, &mut self.settings.detail_3d);
        if let Some(e) = &self.error {
            ui.colored_label(egui::Color32::from_rgb(190, 20, 20), e);
        }
        if self.settings.show_why {
            ui.separator();
            teach::why_note_ui(ui);
        }
        self.apply_change(change);
    }

    pub(super) fn plots_panel_ui(&mut self, ui: &mut egui::Ui) {
        let first_ts = self.runs.first().map(|r| r.time_s()).unwrap_or(1.0);
        let names = self.run_names();
        let runs: Vec<plots::PlotRun> = self
            .runs
            .iter()
            .enumerate()
            .map(|(i, r)| plots::PlotRun {
                name: &names[i],
                track: r.track(),
                t: self.run_time(i),
                time_factor: r.time_s() / first_ts,
            })
            .collect();
        let label = self
            .runs
            .first()
            .map(|r| format!("t ({})", UnitLabels::of(&r.track().case().units).time))
            .unwrap_or_default();
        let data = self.data_view();
        let lines = data.as_ref().map(|d| d.plot_lines()).unwrap_or_default();
        let mismatch = data.as_ref().and_then(|d| d.mismatch_plot);
        plots::plots_ui(ui, &runs, &label, &lines, mismatch);
    }

    pub(super) fn run_names(&self) -> Vec<String> {
        let mut v = vec![self.settings.preset.clone()];
        if self.settings.compare {
            v.push(self.settings.compare_preset.clone());
        }
        v
    }

    pub(super) fn traces_panel_ui(&mut self, ui: &mut egui::Ui) {
        let contact = self.settings.show_contact;
        teach::phase_legend_ui(ui);
        let data = self.data_view();
        if let Some(d) = &data {
            ui.horizontal_wrapped(|ui| {
                teach::swatch_ui(ui, DATA_COLOR);
                ui.label(&d.name);
                ui.label(RichText::new("(square: now)").small());
            });
        }
        let names = self.run_names();
        let bounds = self
            .runs
            .iter()
            .filter_map(|r| trace_panel::Bounds::of(r.track(), contact))
            .chain(data.as_ref().and_then(|d| d.bounds))
            .reduce(trace_panel::Bounds::union);
        let n = self.runs.len().max(1);
        let w = (ui.available_width() - 6.0 * (n as f32 - 1.0)) / n as f32;
        let h = ui.available_height();
        ui.horizontal(|ui| {
            for i in 0..self.runs.len() {
                let t = self.run_time(i);
                // The recording goes with the first run (the one a recording's model is put in).
                let overlays: Vec<trace_panel::Overlay> =
                    data.iter().filter(|_| i == 0).flat_map(|d| d.overlays()).collect();
                ui.allocate_ui(egui::vec2(w, h), |ui| {
                    let title = format!("path of A from above: {}", names[i]);
                    trace_panel::trace_panel_with_ui(
                        ui,
                        &title,
                        self.runs[i].track(),
                        t,
                        contact,
                        bounds,
                        &overlays,
                    );
                });
            }
        });
    }

    /// What the 3D view draws for view `i` seen by `cam`: the run (and the recording in the
    /// first view), its paths thicker in presentation mode.
    fn view_frame(
        &self,
        i: usize,
        cam: &OrbitCamera,
        data: Option<&DataView>,
        thick: f32,
    ) -> SceneFrame {
        let (follow, contact) = (self.settings.follow, self.settings.show_contact);
        let mut frame = scene::scene_frame(
            self.runs[i].track(),
            self.run_time(i),
            cam,
            follow,
            contact,
            BODY_LINEAR[i % 2],
        );
        if let Some(d) = data.filter(|_| i == 0) {
            scene::add_recording(&mut frame, &d.path, d.ring.as_ref().map(|(b, p)| (b, *p)));
        }
        if thick != 1.0 {
            for s in &mut frame.traces {
                s.extra = s.extra.map(|x| x * thick);
            }
        }
        frame
    }

    /// The 3D view's frames as they are now (its picture).
    pub(super) fn view_frames(&self) -> Vec<SceneFrame> {
        let data = self.data_view();
        let thick = if self.presentation.on { super::presentation::THICK_LINES } else { 1.0 };
        (0..self.runs.len())
            .map(|i| self.view_frame(i, &self.camera, data.as_ref(), thick))
            .collect()
    }

    pub(super) fn view_panel_ui(&mut self, ui: &mut egui::Ui) {
        let home = OrbitCamera::default_for(
            self.runs.first().map(|r| r.track().case().model.body.r as f32).unwrap_or(1.0),
        );
        let times: Vec<f64> = (0..self.runs.len()).map(|i| self.run_time(i)).collect();
        let tracks: Vec<&Track> = self.runs.iter().map(|r| r.track()).collect();
        let data = self.data_view();
        let scale = self.settings.detail_3d.scale(super::on_software_adapter(ui.ctx()));
        let thick = super::presentation::line_scale(ui.ctx());
        let mut camera = self.camera;
        let rects = view3d::view3d_ui(ui, &mut camera, home, tracks.len(), scale, |i, cam| {
            self.view_frame(i, cam, data.as_ref(), thick)
        });
        self.camera = camera;
        if let (Some(first), Some(last)) = (rects.first(), rects.last()) {
            let ppp = ui.ctx().pixels_per_point();
            let size = first.union(*last).size() * ppp;
            self.view_px = [size.x.round().max(16.0) as u32, size.y.round().max(16.0) as u32];
        }
        let names = self.run_names();
        for (i, rect) in rects.iter().enumerate() {
            let area = rect.shrink(8.0);
            let mut child = ui.new_child(
                egui::UiBuilder::new()
                    .max_rect(area)
                    .layout(egui::Layout::top_down(egui::Align::Min)),
            );
            egui::Frame::new()
                .fill(egui::Color32::from_white_alpha(215))
                .corner_radius(ui.visuals().widgets.noninteractive.corner_radius)
                .inner_margin(6.0)
                .show(&mut child, |ui| {
                    ui.set_max_width(area.width().min(460.0));
                    teach::phase_label_ui(ui, &names[i], tracks[i], times[i]);
                });
        }
        if self.restart_pending.is_some() && self.restart_shown.is_none() && self.live {
            // Still waiting: ask for another frame at once.
            ui.ctx().request_repaint();
        }
    }

    /// The plots' height and the trace panel's width: fixed in the window; in presentation
    /// mode shares of the screen (a projector's may be small in points).
    pub(super) fn panel_sizes(&self, ctx: &egui::Context) -> (f32, f32) {
        let two = self.settings.compare;
        if !self.presentation.on {
            return (280.0, if two { 520.0 } else { 340.0 });
        }
        let screen = ctx.content_rect().size();
        ((0.36 * screen.y).max(150.0), screen.x * if two { 0.42 } else { 0.3 })
    }

    /// File > Export video…'s window, and what it asked for.
    pub(super) fn video_dialog_window(&mut self, ctx: &egui::Context) {
        let (label, time_s) = match self.runs.first() {
            Some(r) => (UnitLabels::of(&r.track().case().units).time, r.time_s()),
            None => (String::new(), 1.0),
        };
        match video_dialog_ui(ctx, &mut self.video_dialog, &self.exports, &label, time_s) {
            VideoDialogAction::None => {}
            VideoDialogAction::Export(v) => self.request_file(FileTask::Video(v)),
            VideoDialogAction::Cancel => self.exports.cancel_video(),
        }
    }
}

/// The 3D view's resolution (see [`Detail3d`]).
fn detail_3d_ui(ui: &mut egui::Ui, detail: &mut Detail3d) {
    egui::ComboBox::from_label("3D detail")
        .selected_text(detail.describe())
        .show_ui(ui, |ui| {
            for d in Detail3d::ALL {
                ui.selectable_value(detail, d, d.describe());
            }
        })
        .response
        .on_hover_text("fast draws the 3D view at 0.7 of its width and height and scales it up: the frame rate on a computer without a GPU");
}
