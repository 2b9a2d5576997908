//! The classroom's File and View actions in the window, driven as a user would (egui_kittest):
//! the menu entries ask for a path (in fixed mode no dialog opens; the test answers the request
//! with a temporary path, as the dialog would), then the case, the CSV, the pictures and the
//! video are checked in their files. Presentation mode: F11 and the menu, the side panel folded,
//! the scale kept per mode. The work runs at once in fixed mode: nothing waits for a time.

mod common;

use eframe::egui::{self, Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use ringlab::config::load_case_file;
use ringlab::export::session::{FileTask, PictureKind};
use ringlab::export::{VideoFormat, View};
use ringlab::ui::{Mode, RinglabApp, Settings};
use std::path::PathBuf;

fn fixed(seconds: f64) -> RinglabApp {
    RinglabApp::new(Settings::default(), Mode::Fixed { seconds })
}

/// A harness without a renderer (menus, keys, files).
fn harness(app: RinglabApp) -> Harness<'static, RinglabApp> {
    Harness::builder()
        .with_size([1480.0, 920.0])
        .build_ui_state(|ui, app: &mut RinglabApp| app.ui_root(ui), app)
}

/// A harness drawing through wgpu (lavapipe) with the scene renderer installed, as the window
/// has it: its screenshots are real renders.
fn drawing_harness(app: RinglabApp, size: [f32; 2]) -> Harness<'static, RinglabApp> {
    common::drawing::drawing_builder(size[0] as u32, size[1] as u32)
        .build_ui_state(|ui, app: &mut RinglabApp| app.ui_root(ui), app)
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ringlab-classroom-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Opens the File menu and clicks `entry`.
fn menu(h: &mut Harness<'static, RinglabApp>, entry: &str) {
    h.get_by_label("File").click();
    h.run_steps(2);
    h.get_by_label(entry).click();
    h.run_steps(2);
}

/// What the message strip says (the note, or the error).
fn message(app: &RinglabApp) -> String {
    app.recording.error.clone().or(app.recording.note.clone()).unwrap_or_default()
}

#[test]
fn the_file_menu_has_the_classroom_entries() {
    let mut h = harness(fixed(1.0));
    h.run_steps(2);
    h.get_by_label("File").click();
    h.run_steps(2);
    for entry in [
        "Open case…",
        "Save case…",
        "Export run as CSV…",
        "Save picture of the window… F12",
        "Save picture of the 3D view… Shift+F12",
        "Export video…",
    ] {
        assert!(h.query_by_label(entry).is_some(), "File > {entry} is missing");
    }
}

#[test]
fn save_case_writes_the_case_and_open_case_reads_it_back() {
    let dir = temp_dir("case");
    let mut h = harness(fixed(1.0));
    h.run_steps(2);
    // A case that is not a preset's: C1 moved by the slider.
    h.get_by_role_and_label(egui::accesskit::Role::Slider, "C1 (about e1, a diameter)")
        .increment_accesskit();
    h.run_steps(2);
    menu(&mut h, "Save case…");
    let task = h.state_mut().exports.take_request();
    assert_eq!(task, Some(FileTask::SaveCase), "the menu asks for a path");
    let path = dir.join("lesson");
    h.state_mut().file_chosen(FileTask::SaveCase, path.clone());
    let saved = dir.join("lesson.toml");
    let read = load_case_file(&saved).expect("the saved case reads back");
    assert_eq!(read, h.state().settings.case, "the same case, number for number");
    assert!(message(h.state()).contains("saved the case"), "{}", message(h.state()));

    // Another case in the window, then the saved one opened again.
    h.state_mut().load_preset("coin", false);
    assert_ne!(h.state().settings.case, read);
    menu(&mut h, "Open case…");
    assert_eq!(h.state_mut().exports.take_request(), Some(FileTask::OpenCase));
    h.state_mut().file_chosen(FileTask::OpenCase, saved);
    h.run_steps(2);
    assert_eq!(h.state().settings.case, read);
    assert_eq!(
        h.state().tracks()[0].case().model.c_drag,
        read.drag.c,
        "the run uses the opened case"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_bad_case_file_is_reported_with_its_file_and_the_case_stays() {
    let dir = temp_dir("bad-case");
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, "name = \"x\"\n[units]\nsystem = \"furlongs\"\n").unwrap();
    let mut app = fixed(1.0);
    let before = app.settings.case.clone();
    app.file_chosen(FileTask::OpenCase, bad.clone());
    let m = message(&app);
    assert!(m.contains("bad.toml"), "the error names the file: {m}");
    assert_eq!(app.settings.case, before);
    app.file_chosen(FileTask::OpenCase, dir.join("missing.toml"));
    assert!(message(&app).contains("missing.toml"), "{}", message(&app));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn export_run_as_csv_writes_what_simulate_writes() {
    let dir = temp_dir("csv");
    let mut h = harness(fixed(1.0));
    h.run_steps(2);
    menu(&mut h, "Export run as CSV…");
    assert_eq!(h.state_mut().exports.take_request(), Some(FileTask::ExportCsv));
    let csv = dir.join("run.csv");
    h.state_mut().file_chosen(FileTask::ExportCsv, csv.clone());
    h.state_mut().finish_export_jobs();
    assert!(message(h.state()).contains("rows"), "{}", message(h.state()));
    // The same case through the command line.
    let case = dir.join("case.toml");
    h.state_mut().file_chosen(FileTask::SaveCase, case.clone());
    let cli = dir.join("cli.csv");
    let out = common::ringlab(&[
        "simulate",
        "--config",
        case.to_str().unwrap(),
        "--out",
        cli.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let (ours, theirs) =
        (std::fs::read_to_string(&csv).unwrap(), std::fs::read_to_string(&cli).unwrap());
    assert!(ours.lines().count() > 100, "{} lines", ours.lines().count());
    assert_eq!(ours, theirs, "the window's CSV is simulate --out's");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn f11_and_the_view_menu_switch_presentation_mode_and_the_side_panel_folds() {
    let mut h = harness(fixed(1.0));
    h.run_steps(2);
    assert!(h.query_by_label("Model").is_some(), "the side panel's tabs");
    h.key_press(Key::F11);
    h.run_steps(2);
    assert!(h.state().presenting());
    assert!(h.query_by_label("Model").is_none(), "the side panel folded away");
    h.get_by_label("Parameters").click();
    h.run_steps(2);
    assert!(h.query_by_label("Model").is_some(), "unfolded on demand");
    h.key_press(Key::F11);
    h.run_steps(2);
    assert!(!h.state().presenting());
    // View > Presentation.
    h.get_by_label("View").click();
    h.run_steps(2);
    h.get_by_label("Presentation F11").click();
    h.run_steps(2);
    assert!(h.state().presenting());
    // And back, by the same menu.
    h.get_by_label("View").click();
    h.run_steps(2);
    h.get_by_label("Leave presentation F11").click();
    h.run_steps(2);
    assert!(!h.state().presenting());
}

#[test]
fn ctrl_plus_and_minus_scale_the_ui_and_each_mode_keeps_its_scale() {
    let mut h = harness(fixed(1.0));
    h.run_steps(2);
    assert_eq!(h.ctx.zoom_factor(), 1.0);
    h.key_press_modifiers(Modifiers::COMMAND, Key::Plus);
    h.run_steps(2);
    assert_eq!(h.state().settings.zoom, 1.1);
    assert_eq!(h.ctx.zoom_factor(), 1.1);
    h.key_press(Key::F11);
    h.run_steps(2);
    let p = ringlab::ui::presentation::PRESENTATION_ZOOM;
    assert_eq!(h.ctx.zoom_factor(), p, "presentation mode has its own scale");
    h.key_press_modifiers(Modifiers::COMMAND, Key::Minus);
    h.run_steps(2);
    let smaller = h.state().settings.presentation_zoom;
    assert!(smaller < p);
    h.key_press(Key::F11);
    h.run_steps(2);
    assert_eq!(h.ctx.zoom_factor(), 1.1, "back to the window's own");
    h.key_press(Key::F11);
    h.run_steps(2);
    assert_eq!(h.ctx.zoom_factor(), smaller, "and presentation's, as left");
    h.key_press_modifiers(Modifiers::COMMAND, Key::Num0);
    h.run_steps(2);
    assert_eq!(h.ctx.zoom_factor(), p, "Ctrl 0: the mode's own scale");
    // Kept with the settings (eframe storage).
    let kept: Settings =
        serde_json::from_value(serde_json::to_value(&h.state().settings).unwrap()).unwrap();
    assert_eq!((kept.zoom, kept.presentation_zoom), (1.1, p));
}

#[test]
fn f12_saves_the_window_and_shift_f12_the_3d_view() {
    let dir = temp_dir("pictures");
    let mut app = fixed(
        ringlab::config::load_preset("paper-ring").unwrap().build().unwrap().units.time_s * 30.0,
    );
    app.exports.last_folder = Some(dir.clone());
    let mut h = drawing_harness(app, [1000.0, 700.0]);
    h.run_steps(3);
    h.key_press(Key::F12);
    // The screenshot is taken at the end of a frame and written a frame later.
    h.run_steps(3);
    h.state_mut().finish_export_jobs();
    let window = dir.join("ringlab-paper-ring-t30.0.png");
    let img = image::open(&window)
        .unwrap_or_else(|e| panic!("{}: {e}; {}", window.display(), message(h.state())))
        .to_rgba8();
    assert_eq!(img.dimensions(), (1000, 700));
    let colours: std::collections::HashSet<[u8; 4]> = img.pixels().map(|p| p.0).collect();
    assert!(colours.len() > 200, "a real picture of the window: {} colours", colours.len());

    h.key_press_modifiers(Modifiers::SHIFT, Key::F12);
    h.run_steps(2);
    h.state_mut().finish_export_jobs();
    let view = dir.join("ringlab-paper-ring-3d-t30.0.png");
    let img = image::open(&view)
        .unwrap_or_else(|e| panic!("{}: {e}; {}", view.display(), message(h.state())))
        .to_rgba8();
    let (w, h3) = img.dimensions();
    assert!(
        w > 300 && w < 1000 && h3 > 200 && h3 < 700,
        "the 3D view's size on the screen: {w}x{h3}"
    );
    // A second F12 does not overwrite the first; the message strip (saying where the first
    // went) is left out of the picture: the same moment, the same picture.
    assert!(message(h.state()).contains("saved the 3D view"));
    h.key_press(Key::F12);
    h.run_steps(3);
    h.state_mut().finish_export_jobs();
    let second = image::open(dir.join("ringlab-paper-ring-t30.0-2.png"))
        .expect("a second picture")
        .to_rgba8();
    let first = image::open(&window).unwrap().to_rgba8();
    let differing = first.pixels().zip(second.pixels()).filter(|(a, b)| a != b).count();
    assert!(differing < 50, "{differing} pixels differ: the strip is in the picture");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_menu_asks_where_to_save_a_picture_and_writes_it_there() {
    let dir = temp_dir("picture-menu");
    let mut h = drawing_harness(fixed(1.0), [900.0, 600.0]);
    h.run_steps(3);
    menu(&mut h, "Save picture of the 3D view… Shift+F12");
    let task = h.state_mut().exports.take_request();
    assert_eq!(task, Some(FileTask::Picture(PictureKind::View3d)));
    h.state_mut().file_chosen(FileTask::Picture(PictureKind::View3d), dir.join("ring"));
    h.state_mut().finish_export_jobs();
    assert!(image::open(dir.join("ring.png")).is_ok(), "{}", message(h.state()));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn export_video_makes_a_gif_of_the_chosen_span() {
    let dir = temp_dir("video");
    let mut h = harness(fixed(1.0));
    h.run_steps(2);
    menu(&mut h, "Export video…");
    assert!(h.state().video_dialog.open, "the Export video window opens");
    assert!(h.query_by_label("Export…").is_some());
    // Small and short: the choices as the window's fields hold them.
    {
        let d = &mut h.state_mut().video_dialog;
        d.spec.from = 0.0;
        d.spec.to = 6.0;
        d.spec.fps = 10.0;
        d.spec.speed = 0.5;
        d.size = [120, 68];
        d.view = View::ThreeD;
        d.format = VideoFormat::Gif;
    }
    h.run_steps(2);
    h.get_by_label("Export…").click();
    h.run_steps(2);
    let Some(FileTask::Video(v)) = h.state_mut().exports.take_request() else {
        panic!("Export… asks for a file")
    };
    assert_eq!((v.size, v.spec.to, v.format), ([120, 68], 6.0, VideoFormat::Gif));
    let gif = dir.join("turn.gif");
    h.state_mut().file_chosen(FileTask::Video(v), gif.clone());
    h.state_mut().finish_export_jobs();
    assert!(message(h.state()).contains("frames"), "{}", message(h.state()));
    let time_s = h.state().tracks()[0].case().units.time_s;
    let frames = common::gif_frames(&gif);
    let expected = (6.0 * time_s * 10.0 / 0.5 + 1e-9).floor() as usize + 1;
    assert_eq!(frames.len(), expected);
    assert_eq!(frames[0].dimensions(), (120, 68));
    std::fs::remove_dir_all(&dir).ok();
}

/// The video on its thread, as the live window has it, cancelled: no file is left.
#[test]
fn a_video_runs_on_its_thread_and_cancel_leaves_no_file() {
    let dir = temp_dir("video-cancel");
    let mut app = RinglabApp::new(Settings::default(), Mode::Live);
    let mut v = app.video_dialog.request();
    v.spec = ringlab::export::VideoSpec { from: 0.0, to: 200.0, fps: 25.0, speed: 0.05 };
    let gif = dir.join("long.gif");
    app.file_chosen(FileTask::Video(v), gif.clone());
    assert!(
        app.exports.video_progress().is_some(),
        "the call returned at once: the video is on its thread"
    );
    app.exports.cancel_video();
    assert!(app.exports.video_cancelling());
    app.finish_export_jobs();
    assert!(message(&app).contains("cancelled"), "{}", message(&app));
    assert!(!gif.exists(), "a cancelled video leaves no file");
    std::fs::remove_dir_all(&dir).ok();
}
