//! Frames of a run at any time, drawn as the window draws them: the 3D scene, the trace panel
//! or the whole window (one renderer for the screen, pictures and videos). A video is made
//! from them through `export::Frames`.

use super::palette::BODY_LINEAR;
use super::{RinglabApp, scene, trace_panel};
use crate::config::Case;
use crate::export::{Aim, Frames, render_views};
use crate::render::{Gpu, OrbitCamera, RenderError, SceneFrame, SceneRenderer, UiRenderer};
use crate::sim::Track;
use eframe::egui;
use image::RgbaImage;

enum Kind {
    ThreeD {
        tracks: Vec<Track>,
        camera: OrbitCamera,
        aim: Aim,
        contact: bool,
        renderer: SceneRenderer,
    },
    Top {
        tracks: Vec<(String, Track)>,
        contact: bool,
        bounds: Option<trace_panel::Bounds>,
        ui: UiRenderer,
    },
    App {
        app: Box<RinglabApp>,
        ui: UiRenderer,
    },
}

/// Draws frames of one or two runs (or the whole app) at any time.
pub struct FrameSource {
    kind: Kind,
    /// Frames drawn so far (egui's layout settles in the first few passes).
    drawn: usize,
}

impl FrameSource {
    /// The 3D scene of `cases` (one, or two side by side).
    pub fn three_d(
        gpu: &Gpu,
        cases: Vec<Case>,
        camera: OrbitCamera,
        aim: Aim,
        contact: bool,
    ) -> FrameSource {
        let tracks = cases.into_iter().map(Track::compute).collect();
        let renderer = SceneRenderer::new(&gpu.device, None);
        FrameSource { kind: Kind::ThreeD { tracks, camera, aim, contact, renderer }, drawn: 0 }
    }

    /// The trace panel of named cases; the panel covers the whole runs (it stands still).
    pub fn top(gpu: &Gpu, runs: Vec<(String, Case)>, contact: bool) -> FrameSource {
        let tracks: Vec<(String, Track)> =
            runs.into_iter().map(|(n, c)| (n, Track::compute(c))).collect();
        let bounds = tracks
            .iter()
            .filter_map(|(_, t)| trace_panel::Bounds::of(t, contact))
            .reduce(trace_panel::Bounds::union);
        FrameSource {
            kind: Kind::Top { tracks, contact, bounds, ui: UiRenderer::new(gpu) },
            drawn: 0,
        }
    }

    /// The whole window of `app` (in fixed mode: its runs computed, its clock moved per frame).
    pub fn app(gpu: &Gpu, app: RinglabApp) -> FrameSource {
        FrameSource { kind: Kind::App { app: Box::new(app), ui: UiRenderer::new(gpu) }, drawn: 0 }
    }

    fn first_case(&self) -> Option<&Case> {
        match &self.kind {
            Kind::ThreeD { tracks, .. } => tracks.first().map(|t| t.case()),
            Kind::Top { tracks, .. } => tracks.first().map(|(_, t)| t.case()),
            Kind::App { app, .. } => app.tracks().first().map(|t| t.case()),
        }
    }

    /// The time unit (seconds) of the first run: frame times are in it.
    pub fn time_unit_s(&self) -> f64 {
        self.first_case().map_or(1.0, |c| c.units.time_s)
    }

    /// When the first run ends (its time unit), once known.
    pub fn end_time(&self) -> Option<f64> {
        match &self.kind {
            Kind::ThreeD { tracks, .. } => tracks.first().and_then(|t| t.end()).map(|e| e.t_end),
            Kind::Top { tracks, .. } => tracks.first().and_then(|(_, t)| t.end()).map(|e| e.t_end),
            Kind::App { app, .. } => app.tracks().first().and_then(|t| t.end()).map(|e| e.t_end),
        }
    }

    /// The picture at time `t` of the first run (in its unit; a second run shows the same
    /// moment in its own unit).
    pub fn frame(&mut self, gpu: &Gpu, t: f64, size: [u32; 2]) -> Result<RgbaImage, RenderError> {
        let seconds = t * self.time_unit_s();
        let passes = if self.drawn == 0 { 3 } else { 2 };
        self.drawn += 1;
        match &mut self.kind {
            Kind::ThreeD { tracks, camera, aim, contact, renderer } => {
                let frames: Vec<SceneFrame> = tracks
                    .iter()
                    .enumerate()
                    .map(|(i, track)| {
                        let ti = seconds / track.case().units.time_s;
                        let mut cam = *camera;
                        if let Aim::PathMiddle(until) = aim {
                            let until = until.map_or(ti, |s| s / track.case().units.time_s);
                            if let Some(m) = path_middle(track, until) {
                                cam.target = [m[0] as f32, m[1] as f32, 0.0];
                            }
                        }
                        scene::scene_frame(
                            track,
                            ti,
                            &cam,
                            *aim == Aim::Follow,
                            *contact,
                            BODY_LINEAR[i % 2],
                        )
                    })
                    .collect();
                render_views(gpu, renderer, &frames, size)
            }
            Kind::Top { tracks, contact, bounds, ui } => {
                ui.render(gpu, size, passes, |u| top_ui(u, tracks, seconds, *contact, *bounds))
            }
            Kind::App { app, ui } => {
                app.seek_model_time(t);
                ui.render(gpu, size, passes, |u| app.ui_root(u))
            }
        }
    }
}

impl Frames for FrameSource {
    fn time_unit_s(&self) -> f64 {
        FrameSource::time_unit_s(self)
    }

    fn frame(&mut self, gpu: &Gpu, t: f64, size: [u32; 2]) -> Result<RgbaImage, RenderError> {
        FrameSource::frame(self, gpu, t, size)
    }
}

/// The middle of the box round the path of A up to `t`.
fn path_middle(track: &Track, t: f64) -> Option<[f64; 2]> {
    let path = track.samples_until(t);
    let first = path.first()?;
    let (mut lo, mut hi) = ([first.x_a, first.y_a], [first.x_a, first.y_a]);
    for s in path {
        lo = [lo[0].min(s.x_a), lo[1].min(s.y_a)];
        hi = [hi[0].max(s.x_a), hi[1].max(s.y_a)];
    }
    Some([0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])])
}

/// The trace panel of each run, side by side, at `seconds` of the shared clock.
fn top_ui(
    ui: &mut egui::Ui,
    tracks: &[(String, Track)],
    seconds: f64,
    contact: bool,
    bounds: Option<trace_panel::Bounds>,
) {
    // The app's theme (the panel's colours assume it); the first pass already uses it.
    ui.ctx().set_theme(egui::Theme::Light);
    egui::CentralPanel::default().show(ui, |ui| {
        let n = tracks.len().max(1) as f32;
        let w = (ui.available_width() - 6.0 * (n - 1.0)) / n;
        let h = ui.available_height();
        ui.horizontal(|ui| {
            for (name, t) in tracks {
                let time = seconds / t.case().units.time_s;
                ui.allocate_ui(egui::vec2(w, h), |ui| {
                    trace_panel::trace_panel_ui(
                        ui,
                        &format!("path of A from above: {name}"),
                        t,
                        time,
                        contact,
                        bounds,
                    );
                });
            }
        });
    });
}
