//! Pictures compared with references in `tests/snapshots/` (`UPDATE_SNAPSHOTS=1 cargo test
//! --release` rewrites the failing ones; see docs/snapshots.md). Deterministic: the runs are computed
//! at once (no thread), shown at a fixed time, from a fixed camera, without MSAA, through the
//! software adapter (CI forces lavapipe with VK_DRIVER_FILES).
//!
//! Tolerance: a pixel fails when its colour differs by more than 1.0 in the weighted YIQ
//! distance of `dify` (the default is 0.6; lavapipe renders were identical run to run, so
//! this only leaves room for a different Mesa or LLVM build rounding the shading differently),
//! and at most 0.05% of the pixels may fail (a handful of edge pixels). A real change (the
//! ring moved, a trace missing, a label changed) changes thousands of pixels.

mod common;

use common::drawing::{drawing_builder, snapshot_options};
use egui_kittest::kittest::Queryable;
use ringlab::config::load_preset;
use ringlab::render::{Gpu, OrbitCamera, SceneRenderer};
use ringlab::sim::Track;
use ringlab::ui::palette::BODY_LINEAR;
use ringlab::ui::{Mode, RinglabApp, Settings, scene, trace_panel};

/// The window's background: the app leaves it to the clear colour (its panels are not
/// filled), and the test renderer clears to transparent.
fn background(ui: &mut eframe::egui::Ui) {
    let fill = ui.visuals().panel_fill;
    ui.painter().rect_filled(ui.max_rect(), 0.0, fill);
}

fn paper_track(name: &str) -> Track {
    Track::compute(load_preset(name).expect("preset").build().expect("builds"))
}

/// Seconds of the paper's case at model time `t`.
fn seconds(t: f64) -> f64 {
    t * load_preset("paper-ring").expect("preset").build().expect("builds").units.time_s
}

fn app_snapshot(name: &str, settings: Settings, t: f64) {
    let (w, h) = (1480u32, 920u32);
    let mut app = RinglabApp::new(settings, Mode::Fixed { seconds: seconds(t) });
    let mut harness = drawing_builder(w, h).build_ui(|ui| {
        background(ui);
        app.ui_root(ui)
    });
    harness.run_steps(3);
    harness.snapshot_options(name, &snapshot_options(w, h));
}

#[test]
fn app_paper_ring() {
    app_snapshot("app_paper_ring", Settings::default(), 60.0);
}

#[test]
fn app_ring_vs_disk() {
    let settings = Settings { compare: true, ..Settings::default() };
    app_snapshot("app_ring_vs_disk", settings, 60.0);
}

/// The sample recording opened and fitted (the Fit button, run at once in fixed mode), shown
/// with the fitted model at t = 40.
#[test]
fn app_sample_recording_fitted() {
    let (w, h) = (1480u32, 920u32);
    let mut app = RinglabApp::new(Settings::default(), Mode::Fixed { seconds: 0.0 });
    app.open_recording(
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/sample-ring.csv"),
    );
    let mut harness = drawing_builder(w, h).build_ui_state(
        |ui, app: &mut RinglabApp| {
            background(ui);
            app.ui_root(ui)
        },
        app,
    );
    harness.run_steps(2);
    harness.get_by_label("Fit").click();
    harness.run_steps(2);
    let app = harness.state();
    let fit = &app.recording.fitted().expect("fitted").result;
    assert_eq!(app.tracks()[0].case().model.c_drag, fit.c, "the simulator runs the fitted drag");
    harness.state_mut().seek_model_time(40.0);
    harness.run_steps(3);
    harness.snapshot_options("app_sample_recording_fitted", &snapshot_options(w, h));
}

/// A recording with Reynolds-dependent drag concealed (the first seed of the diagnosis's
/// tests), diagnosed in the window: the Diagnose tab with the finding, the candidates and the
/// two models against the data; the mismatch shaded in the plots and drawn on the trace; the
/// improved model running.
#[test]
fn app_diagnosed_reynolds_drag() {
    let (w, h) = (1480u32, 920u32);
    let (rec, _) = ringlab::analysis::diagnose::concealed::concealed_recording(
        ringlab::physics::EffectKind::ReynoldsDrag,
        1,
    )
    .unwrap();
    // The file's name shows in the picture: a fixed one, in a folder of this process's own.
    let dir = std::env::temp_dir().join(format!("ringlab-snapshot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("concealed-reynolds_drag.csv");
    ringlab::recording::write_recording(&mut std::fs::File::create(&path).unwrap(), &rec).unwrap();
    let mut app = RinglabApp::new(Settings::default(), Mode::Fixed { seconds: 0.0 });
    app.open_recording(path.clone());
    app.side_tab = ringlab::ui::SideTab::Diagnose;
    app.act_on_diagnosis(ringlab::ui::diagnose_panel::DiagnoseAction::Diagnose);
    app.act_on_diagnosis(ringlab::ui::diagnose_panel::DiagnoseAction::Adopt(
        ringlab::session::DiagnosedModel::Improved,
    ));
    assert!(
        app.recording
            .diagnosed()
            .is_some_and(|d| d.improved.as_ref().is_ok_and(|c| *c == app.settings.case))
    );
    std::fs::remove_dir_all(&dir).ok();
    let mut harness = drawing_builder(w, h).build_ui_state(
        |ui, app: &mut RinglabApp| {
            background(ui);
            app.ui_root(ui)
        },
        app,
    );
    harness.state_mut().player.seek(3.0);
    harness.run_steps(3);
    harness.snapshot_options("app_diagnosed_reynolds_drag", &snapshot_options(w, h));
}

/// Presentation mode on a 1920x1080 projector: the UI at its presentation scale (1.5, so
/// 1280x720 points), the projector theme with thick paths, the side panel folded away.
#[test]
fn app_presentation_paper_ring() {
    let zoom = ringlab::ui::presentation::PRESENTATION_ZOOM;
    let (w, h) = (1920u32, 1080u32);
    let mut app = RinglabApp::new(Settings::default(), Mode::Fixed { seconds: seconds(60.0) });
    app.set_presentation(true);
    let mut harness =
        drawing_builder(w, h).with_size([w as f32 / zoom, h as f32 / zoom]).build_ui(|ui| {
            background(ui);
            app.ui_root(ui)
        });
    harness.run_steps(3);
    assert_eq!(harness.ctx.zoom_factor(), zoom);
    assert!(harness.query_by_label("Model").is_none(), "the side panel is folded away");
    harness.snapshot_options("app_presentation_paper_ring", &snapshot_options(w, h));
}

#[test]
fn scene_3d_paper_ring() {
    let gpu = Gpu::new().expect("a Vulkan adapter (lavapipe)");
    let mut renderer = SceneRenderer::new(&gpu.device, None);
    let track = paper_track("paper-ring");
    let camera = OrbitCamera::default_for(track.case().model.body.r as f32);
    let frame = scene::scene_frame(&track, 40.0, &camera, true, true, BODY_LINEAR[0]);
    let (w, h) = (640, 360);
    let img = gpu.render_scene(&mut renderer, &frame, [w, h]).expect("renders");
    egui_kittest::image_snapshot_options(&img, "scene_3d_paper_ring", &snapshot_options(w, h));
}

#[test]
fn trace_panel_paper_ring() {
    let track = paper_track("paper-ring");
    let (w, h) = (560u32, 480u32);
    let t = track.end().expect("ended").t_end;
    let mut harness = drawing_builder(w, h).build_ui(|ui| {
        background(ui);
        eframe::egui::CentralPanel::default()
            .frame(eframe::egui::Frame::new().inner_margin(8))
            .show(ui, |ui| {
                trace_panel::trace_panel_ui(
                    ui,
                    "path of A from above: paper-ring",
                    &track,
                    t,
                    true,
                    None,
                );
            });
    });
    harness.run_steps(2);
    harness.snapshot_options("trace_panel_paper_ring", &snapshot_options(w, h));
}

/// On lavapipe the app's egui shapes go to ringlab's lean painter (`shaders/ui.wgsl`) instead
/// of egui-wgpu's shader; both must draw the same picture.
#[test]
fn lean_painter_draws_what_egui_wgpu_draws() {
    let gpu = Gpu::new().expect("a Vulkan adapter (lavapipe)");
    let mut ui = ringlab::render::UiRenderer::new(&gpu);
    let mut app = RinglabApp::new(Settings::default(), Mode::Fixed { seconds: seconds(40.0) });
    let size = [1000, 700];
    ringlab::ui::lean_paint::set_enabled(&ui.ctx, false);
    let by_egui = ui.render(&gpu, size, 3, |u| app.ui_root(u)).expect("renders");
    assert!(ringlab::ui::lean_paint::last_batch(&ui.ctx).is_none(), "egui-wgpu drew everything");
    ringlab::ui::lean_paint::set_enabled(&ui.ctx, true);
    let by_lean = ui.render(&gpu, size, 3, |u| app.ui_root(u)).expect("renders");
    let batch = ringlab::ui::lean_paint::last_batch(&ui.ctx).expect("the lean painter drew");
    assert!(batch.primitives().count() > 5, "the panels, plots and text went to the lean painter");
    let differing = by_egui
        .pixels()
        .zip(by_lean.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0.iter()).any(|(x, y)| x.abs_diff(*y) > 2))
        .count();
    assert!(differing <= 20, "{differing} pixels differ by more than 2 levels");
    // And it is not a blank picture that would agree with another blank one.
    let distinct: std::collections::HashSet<[u8; 4]> = by_lean.pixels().map(|p| p.0).collect();
    assert!(distinct.len() > 200, "{} colours", distinct.len());
}
