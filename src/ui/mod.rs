//! The window: egui panels around the 3D view (functions that draw egui end in `_ui`). The app
//! holds one run, or two side by side on one clock, each fed by an integrator thread
//! ([`crate::sim`]) or, for tests and headless pictures, computed at once. A recording
//! (File > Open recording, or dropped onto the window) is replayed beside the model and can be
//! fitted ([`recording_panel`]; its state is a [`RecordingSession`]), and diagnosed
//! ([`diagnose_panel`]: the mismatch shaded on the plots and the trace, the models adoptable).
//! A film (File > Open video) is tracked into a recording and shown beside the 3D view with
//! the marks and the model drawn over it (`film_view`).
//! For the classroom: presentation mode ([`presentation`]), cases opened and saved, the run as
//! CSV, pictures and videos ([`file_actions`], [`video_dialog`]; the work in
//! [`crate::export`]).

pub mod controls;
pub mod diagnose_panel;
pub mod import_dialog;
pub mod job_controls;
/// The adapter's adjustments and the lean painter live with the renderer; the window uses them.
pub use crate::render::adapter::{adapt_to_adapter, on_software_adapter};
pub use crate::render::lean_paint;
mod app_recording;
mod file_actions;
mod film_tracking;
mod film_view;
pub mod frames;
pub mod menus;
pub mod palette;
mod panels;
pub mod plots;
pub mod presentation;
pub mod recording_panel;
pub mod recording_view;
pub mod scene;
mod settings;
pub mod teach;
pub mod trace_panel;
pub mod video_dialog;
pub mod view3d;

pub use settings::{Detail3d, FAST_3D_SCALE, SETTINGS_KEY, Settings};

use crate::config::{Case, load_preset};
use crate::export::session::ExportSession;
use crate::render::{Gpu, OrbitCamera};
use crate::session::RecordingSession;
use crate::sim::{Player, SimHandle, Track};
use controls::Change;
use eframe::egui;
use presentation::Presentation;
use settings::builtin;
use std::sync::Arc;
use std::time::Duration;
use video_dialog::VideoDialog;
use web_time::Instant;

/// Live (threads, wall clock) or fixed at one time (computed at once, paused: tests, PNGs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mode {
    Live,
    Fixed { seconds: f64 },
}

// One per run shown (two at most): a boxed track would save nothing that counts.
#[allow(clippy::large_enum_variant)]
enum Source {
    Live(SimHandle),
    Fixed(Track),
}

struct Run {
    source: Source,
}

impl Run {
    fn new(case: Case, live: bool) -> Run {
        if live {
            // No thread to be had (a web page): the run is integrated in slices between frames.
            return Run { source: Source::Live(SimHandle::spawn_or_in_place(case)) };
        }
        Run { source: Source::Fixed(Track::compute(case)) }
    }

    fn track(&self) -> &Track {
        match &self.source {
            Source::Live(h) => h.shown(),
            Source::Fixed(t) => t,
        }
    }

    fn restart(&mut self, case: Case) {
        match &mut self.source {
            Source::Live(h) => h.restart(case),
            Source::Fixed(t) => *t = Track::compute(case),
        }
    }

    fn continue_from(&mut self, case: Case, t: f64) {
        match &mut self.source {
            Source::Live(h) => h.continue_from(case, t),
            // Fixed mode (tests, pictures) has no present state to go on from: a new run.
            Source::Fixed(tr) => *tr = Track::compute(case),
        }
    }

    fn run_id(&self) -> u64 {
        match &self.source {
            Source::Live(h) => h.run(),
            Source::Fixed(t) => t.run(),
        }
    }

    fn time_s(&self) -> f64 {
        self.track().case().units.time_s
    }
}

/// The side panel's tabs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SideTab {
    Model,
    Recording,
    Diagnose,
}

pub struct RinglabApp {
    pub settings: Settings,
    /// A recording, its loading and its fit.
    pub recording: RecordingSession,
    pub side_tab: SideTab,
    runs: Vec<Run>,
    pub player: Player,
    camera: OrbitCamera,
    live: bool,
    last_tick: Option<Instant>,
    error: Option<String>,
    /// A restart waiting for its first state on screen: when it was asked for, and the runs.
    restart_pending: Option<(Instant, Vec<u64>)>,
    /// The first frame showing a restarted run was built at this time (latency ends when the
    /// next frame starts, i.e. after it was painted).
    restart_shown: Option<Instant>,
    /// Time from the last parameter change to the first frame that showed its run.
    pub last_restart_latency: Option<Duration>,
    style_set: bool,
    /// The import dialog's complaint about its fields, until the next try.
    import_problem: Option<String>,
    /// Files asked for and being written: cases, CSV, pictures, videos.
    pub exports: ExportSession,
    pub presentation: Presentation,
    pub video_dialog: VideoDialog,
    screenshot: Option<file_actions::Screenshot>,
    /// The window's graphics device, for pictures of the 3D view (None: they open their own).
    gpu: Option<Arc<Gpu>>,
    /// The 3D view's size on the screen in pixels (the size of its picture).
    view_px: [u32; 2],
    /// The film's picture, where the recording was tracked from one.
    film_view: film_view::FilmView,
}

impl RinglabApp {
    pub fn new(settings: Settings, mode: Mode) -> RinglabApp {
        let live = mode == Mode::Live;
        let mut app = RinglabApp {
            settings,
            recording: RecordingSession::new(live),
            side_tab: SideTab::Model,
            runs: Vec::new(),
            player: Player::default(),
            camera: OrbitCamera::default_for(1.0),
            live,
            last_tick: None,
            error: None,
            restart_pending: None,
            restart_shown: None,
            last_restart_latency: None,
            style_set: false,
            import_problem: None,
            exports: ExportSession::new(live),
            presentation: Presentation::default(),
            video_dialog: VideoDialog::default(),
            screenshot: None,
            gpu: None,
            view_px: [1280, 720],
            film_view: film_view::FilmView::default(),
        };
        app.player.set_speed(app.settings.speed);
        // What the last tracker's file needed is used again (fields that no longer parse are
        // left to the dialog to complain about).
        if let Ok((format, opts)) = app.settings.import.to_options() {
            app.recording.import_format = format;
            app.recording.import_options = opts;
        }
        app.rebuild_runs();
        if let Mode::Fixed { seconds } = mode {
            app.player.pause();
            app.player.seek(seconds);
        }
        app
    }

    /// The cases of the run(s), or what is wrong with the parameters.
    fn cases(&self) -> Result<Vec<Case>, String> {
        let mut files = vec![(&self.settings.case, "left")];
        if self.settings.compare {
            files.push((&self.settings.compare_case, "right"));
        }
        files
            .iter()
            .map(|(f, side)| {
                f.build()
                    .map_err(|e| if self.settings.compare { format!("{side}: {e}") } else { e })
            })
            .collect()
    }

    /// Starts the run(s) afresh (new threads), the clock at zero.
    fn rebuild_runs(&mut self) {
        let cases = match self.cases() {
            Ok(c) => c,
            Err(e) => {
                // Stored settings that no longer build: back to the defaults.
                self.error = Some(format!("{e} (the parameters were reset)"));
                self.settings = Settings { speed: self.settings.speed, ..Settings::default() };
                self.cases().unwrap_or_default()
            }
        };
        let scale = cases.first().map(|c| c.model.body.r as f32).unwrap_or(1.0);
        self.camera = OrbitCamera::default_for(scale);
        self.runs = cases.into_iter().map(|c| Run::new(c, self.live)).collect();
        self.player.reset();
        self.note_restart();
    }

    fn note_restart(&mut self) {
        self.restart_pending =
            Some((Instant::now(), self.runs.iter().map(|r| r.run_id()).collect()));
        self.restart_shown = None;
    }

    /// Applies a change of the parameters: a restart from the initial state, or with
    /// `continue_on_change` and a change of drag alone, a continuation from now.
    pub fn apply_change(&mut self, change: Change) {
        if change == Change::None {
            return;
        }
        let cases = match self.cases() {
            Ok(c) => c,
            Err(e) => {
                self.error = Some(e);
                return;
            }
        };
        self.error = None;
        if cases.len() != self.runs.len() {
            self.rebuild_runs();
            return;
        }
        let keep = change == Change::Drag && self.settings.continue_on_change;
        let seconds = self.player.seconds();
        for (run, case) in self.runs.iter_mut().zip(cases) {
            if keep {
                let t = seconds / run.time_s();
                run.continue_from(case, t);
            } else {
                run.restart(case);
            }
        }
        if !keep {
            self.player.seek(0.0);
        }
        self.note_restart();
    }

    /// Every run back to its start.
    pub fn reset(&mut self) {
        if let Ok(cases) = self.cases() {
            for (run, case) in self.runs.iter_mut().zip(cases) {
                run.restart(case);
            }
        }
        self.player.reset();
        self.note_restart();
    }

    /// Loads a preset into the left (or, `second`, the right) case.
    pub fn load_preset(&mut self, name: &str, second: bool) {
        match load_preset(name) {
            Ok(f) => {
                if second {
                    self.settings.compare_preset = name.into();
                    self.settings.compare_case = f;
                } else {
                    self.settings.preset = name.into();
                    self.settings.case = f;
                }
                self.error = None;
                self.rebuild_runs();
            }
            Err(e) => self.error = Some(e.to_string()),
        }
    }

    /// The paper's ring and its disk-like drag side by side.
    pub fn ring_vs_disk(&mut self) {
        self.settings.compare = true;
        self.settings.preset = "paper-ring".into();
        self.settings.case = builtin("paper-ring");
        self.settings.compare_preset = "paper-disk-drag".into();
        self.settings.compare_case = builtin("paper-disk-drag");
        self.rebuild_runs();
    }

    pub fn set_compare(&mut self, on: bool) {
        if self.settings.compare != on {
            self.settings.compare = on;
            self.settings.edit_second &= on;
            self.rebuild_runs();
        }
    }

    /// The tracks shown (one, or two side by side).
    pub fn tracks(&self) -> Vec<&Track> {
        self.runs.iter().map(|r| r.track()).collect()
    }

    /// Moves the clock to time `t` of the first run, in its units.
    pub fn seek_model_time(&mut self, t: f64) {
        if let Some(r) = self.runs.first() {
            let s = t * r.time_s();
            self.player.seek(s);
        }
    }

    /// The display time of run `i` in its own units.
    fn run_time(&self, i: usize) -> f64 {
        self.player.seconds() / self.runs[i].time_s()
    }

    /// When the motion ends (seconds), once every run has ended.
    fn end_seconds(&self) -> Option<f64> {
        let mut end: f64 = 0.0;
        for r in &self.runs {
            let t = r.track();
            if t.failed().is_some() {
                continue;
            }
            end = end.max(t.end()?.t_end * r.time_s());
        }
        // The recording replays to its last frame even where the model stops before.
        Some(self.recording.end_seconds().map_or(end, |e| end.max(e)))
    }

    /// How far the scrubber reaches (seconds): the end, or what has arrived so far.
    fn known_seconds(&self) -> f64 {
        self.runs
            .iter()
            .map(|r| r.track().last_time().unwrap_or(0.0) * r.time_s())
            .fold(0.0, f64::max)
    }

    /// Advances the clock by the wall time since the last frame and takes in the states the
    /// display needs. Never waits for the integrator.
    /// Takes in, without waiting, the states the display needs up to `seconds` (and one
    /// beyond, to blend towards).
    fn pump_live(&mut self, seconds: f64) {
        for r in &mut self.runs {
            let ts = r.time_s();
            if let Source::Live(h) = &mut r.source {
                let dt = h.track.case().dt;
                h.pump(seconds / ts + 2.0 * dt);
            }
        }
    }

    /// Notes when the runs asked for by the last change first have a state to show.
    fn note_arrival(&mut self, now: Instant) {
        if let Some((_, ids)) = &self.restart_pending {
            let arrived = self
                .runs
                .iter()
                .zip(ids)
                .all(|(r, id)| r.track().run() == *id && !r.track().samples().is_empty());
            if arrived && self.restart_shown.is_none() {
                self.restart_shown = Some(now);
            }
        }
    }

    /// Takes in what the worker has sent since the frame began, so that a change made in the
    /// side panel shows in this same frame.
    fn pump_now(&mut self) {
        self.pump_live(self.player.seconds());
        self.note_arrival(Instant::now());
    }

    /// Advances the clock by the wall time since the last frame and takes in the states the
    /// display needs. Never waits for the integrator.
    pub fn tick(&mut self, now: Instant) {
        // The previous frame showed the restarted run; it has been painted by now.
        if self.restart_shown.take().is_some()
            && let Some((asked, _)) = self.restart_pending.take()
        {
            self.last_restart_latency = Some(now.duration_since(asked));
        }
        let wall = self.last_tick.map_or(0.0, |t| now.duration_since(t).as_secs_f64().min(0.1));
        self.last_tick = Some(now);
        self.player.set_speed(self.settings.speed);
        let next = self.player.seconds()
            + if self.player.is_playing() { wall * self.player.speed() } else { 0.0 };
        self.pump_live(next);
        let available = self
            .runs
            .iter()
            .filter(|r| !r.track().is_finished())
            .map(|r| r.track().last_time().unwrap_or(0.0) * r.time_s())
            .fold(f64::INFINITY, f64::min);
        let end = self.end_seconds();
        self.player.advance(wall, available, end);
        self.note_arrival(now);
    }

    /// Whether anything still moves (the window keeps repainting while so).
    pub fn is_animating(&self) -> bool {
        self.live
            && (self.player.is_playing()
                || self.runs.iter().any(|r| !r.track().is_finished())
                || self.restart_pending.is_some())
    }

    /// Pictures of the 3D view draw on this device (the window's) instead of opening their own.
    pub fn set_gpu(&mut self, gpu: Gpu) {
        self.gpu = Some(Arc::new(gpu));
    }

    fn keys(&mut self, ctx: &egui::Context) {
        self.classroom_keys(ctx);
        if ctx.egui_wants_keyboard_input() {
            return;
        }
        let (space, r) =
            ctx.input(|i| (i.key_pressed(egui::Key::Space), i.key_pressed(egui::Key::R)));
        if space {
            self.player.toggle();
        }
        if r {
            self.reset();
        }
    }

    /// The whole window, one frame.
    pub fn ui_root(&mut self, ui: &mut egui::Ui) {
        if !self.style_set {
            ui.ctx().set_theme(egui::Theme::Light);
            // Ctrl +/- are ours: the scale is kept per mode in the settings.
            ui.ctx().options_mut(|o| o.zoom_with_keyboard = false);
            self.style_set = true;
        }
        if self.live {
            self.tick(Instant::now());
        }
        self.keys(ui.ctx());
        self.presentation.apply(ui.ctx(), self.live);
        let zoom = self.zoom_now();
        if ui.ctx().zoom_factor() != zoom {
            ui.ctx().set_zoom_factor(zoom);
        }
        self.take_dropped_files(ui.ctx());
        self.take_recording_events();
        self.take_export_outcomes();

        // Panels leave their background to the window's clear colour (the same grey): on a
        // software rasteriser every filled pixel of egui costs, and the panels cover the window.
        let side = egui::Frame::new().inner_margin(egui::Margin::symmetric(8, 4));
        egui::Panel::top("top").frame(side).show(ui, |ui| self.top_bar_ui(ui));
        // While a picture of the window is on its way (eframe takes it of a later frame than
        // the one that asks) neither the message strip nor the video window shows: the picture
        // is of the run (for slides).
        let picture_frame = self.screenshot.is_some();
        if recording_panel::has_messages(&self.recording) && !picture_frame {
            egui::Panel::top("messages")
                .frame(side)
                .show(ui, |ui| recording_panel::messages_ui(ui, &mut self.recording));
        }
        // Presentation mode folds the side panel away (a button in the top bar unfolds it).
        if !self.presentation.on || self.presentation.side_open {
            egui::Panel::left("parameters").frame(side).default_size(300.0).resizable(false).show(
                ui,
                |ui| {
                    self.side_tabs_ui(ui);
                    egui::ScrollArea::vertical().show(ui, |ui| match self.side_tab {
                        SideTab::Model => self.parameters_panel_ui(ui),
                        SideTab::Recording => self.recording_tab_ui(ui),
                        SideTab::Diagnose => self.diagnose_tab_ui(ui),
                    });
                },
            );
        }
        if self.live {
            self.pump_now();
        }
        let (plots_height, traces_width) = self.panel_sizes(ui.ctx());
        egui::Panel::bottom("plots")
            .frame(side)
            .exact_size(plots_height)
            .show(ui, |ui| self.plots_panel_ui(ui));
        egui::Panel::right("traces")
            .frame(side)
            .default_size(traces_width)
            .resizable(false)
            .show(ui, |ui| self.traces_panel_ui(ui));
        if self.recording.film().is_some() {
            let width = self.film_panel_width(ui.available_size());
            egui::Panel::left("film")
                .frame(side)
                .exact_size(width)
                .resizable(false)
                .show(ui, |ui| self.film_panel_ui(ui));
        }
        egui::CentralPanel::default()
            .frame(egui::Frame::new().inner_margin(4))
            .show(ui, |ui| self.view_panel_ui(ui));

        self.import_dialog(ui.ctx());
        recording_panel::drop_hint_ui(ui.ctx());
        if !picture_frame {
            self.video_dialog_window(ui.ctx());
        }
        lean_paint::hand_over(ui.ctx());
        self.open_requested_dialog();
        self.pump_screenshot(ui.ctx());

        if self.is_animating() {
            ui.ctx().request_repaint();
        } else if self.recording.busy() || self.exports.busy() || self.screenshot.is_some() {
            // A fit's or a diagnosis's progress, a file being read: nothing else may be moving.
            ui.ctx().request_repaint_after(Duration::from_millis(100));
        }
    }
}

impl eframe::App for RinglabApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.ui_root(ui);
    }

    /// A web page's script reaches the app through this (`WebRunner::app_mut`).
    #[cfg(target_arch = "wasm32")]
    fn as_any_mut(&mut self) -> Option<&mut dyn std::any::Any> {
        Some(self)
    }

    fn clear_color(&self, visuals: &egui::Visuals) -> [f32; 4] {
        // The panels are not filled (see ui_root): the window's background is theirs.
        visuals.panel_fill.to_normalized_gamma_f32()
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        // Presentation mode is for this session: the window opens as a window next time.
        eframe::set_value(storage, SETTINGS_KEY, &self.settings);
    }

    /// egui's own memory (plot zoom and the like) is not worth keeping, and it would bring back
    /// tessellation options chosen for another adapter.
    fn persist_egui_memory(&self) -> bool {
        false
    }
}

/// The app as the window (desktop or page) starts it: the renderer installed on eframe's wgpu
/// device, the settings kept from the last session (or `case` instead), running live.
pub fn create_app(
    cc: &eframe::CreationContext<'_>,
    case: Option<crate::config::CaseFile>,
) -> RinglabApp {
    if let Some(rs) = &cc.wgpu_render_state {
        crate::render::callback::install(rs);
        adapt_to_adapter(&cc.egui_ctx, &rs.adapter.get_info());
    }
    let mut settings: Settings =
        cc.storage.and_then(|s| eframe::get_value(s, SETTINGS_KEY)).unwrap_or_default();
    if let Some(f) = case {
        settings.preset = f.name.clone();
        settings.case = f;
        settings.compare = false;
        settings.edit_second = false;
    }
    let mut app = RinglabApp::new(settings, Mode::Live);
    if let Some(rs) = &cc.wgpu_render_state {
        let gpu = Gpu {
            device: rs.device.clone(),
            queue: rs.queue.clone(),
            adapter: rs.adapter.get_info(),
        };
        app.set_gpu(gpu);
    }
    app
}

/// Opens the window (`ringlab` with no arguments; `case`: `ringlab --config FILE`, run instead
/// of the case kept from the last session).
#[cfg(not(target_arch = "wasm32"))]
pub fn run_window(case: Option<crate::config::CaseFile>) -> Result<(), eframe::Error> {
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("ringlab: rolling rings")
            .with_inner_size([1480.0, 920.0]),
        ..Default::default()
    };
    eframe::run_native("ringlab", options, Box::new(|cc| Ok(Box::new(create_app(cc, case)))))
}
