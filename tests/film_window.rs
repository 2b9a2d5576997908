//! A film in the window (File > Open video, or a drop): tracked into a recording that fits as
//! any recording does, shown beside the 3D view with the tracked marks and, once fitted, the
//! model's marks and path drawn over the frame at the clock's time. The app runs in fixed mode
//! (the tracking, the fit and the frames' decoding done at once) except where the thread is
//! the point. The film is `tests/data/video/colours-none-short.mp4` (the start of the shared
//! `colours-none.mp4`: four coloured marks, 1280x1024, the steel ring); ffmpeg decodes it,
//! so without ffmpeg on PATH these tests say so and pass (CI installs it).
//!
//! The snapshot `app_film_fitted` (docs/snapshots.md): the window with the film open, fitted,
//! at its stored frame 150: rewrite it with `UPDATE_SNAPSHOTS=1 cargo test --release --test
//! film_window` and look at it.

mod common;

use common::Dropped;
use common::drawing::{drawing_builder, snapshot_options};
use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use ringlab::config::load_preset;
use ringlab::recording::import::BodyMm;
use ringlab::ui::recording_panel::RecordingAction;
use ringlab::ui::{Mode, RinglabApp, Settings, SideTab};
use std::path::PathBuf;
use std::sync::Arc;

fn film() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/video/colours-none-short.mp4")
}

/// Whether ffmpeg is there to decode the film (CI must have it).
fn have_ffmpeg() -> bool {
    let found = ringlab::film::source::find_program("ffmpeg").is_some()
        && ringlab::film::source::find_program("ffprobe").is_some();
    if !found {
        assert!(std::env::var("CI").is_err(), "ffmpeg is not on PATH in CI");
        eprintln!("ffmpeg is not installed here: the film is not tested");
    }
    found
}

fn steel_ring() -> BodyMm {
    BodyMm::of_case(&load_preset("steel-ring").expect("preset")).expect("a body")
}

/// The app in fixed mode with the steel ring as the import options' body.
fn app() -> RinglabApp {
    let mut app = RinglabApp::new(Settings::default(), Mode::Fixed { seconds: 0.0 });
    app.recording.import_options.body = Some(steel_ring());
    app
}

/// The window of `size` points with `path` dropped onto it, tracked and shown.
fn dropped_on_the_window(path: PathBuf, size: [f32; 2]) -> Harness<'static, RinglabApp> {
    let mut h = Harness::builder()
        .with_size(size)
        .build_ui_state(|ui, app: &mut RinglabApp| app.ui_root(ui), app());
    h.run_steps(2);
    h.input_mut().dropped_files.push(Arc::new(Dropped(path)));
    h.run_steps(3);
    h
}

#[test]
fn a_dropped_film_is_tracked_and_its_frame_shown() {
    if !have_ffmpeg() {
        return;
    }
    let mut h = dropped_on_the_window(film(), [1480.0, 920.0]);
    let app = h.state();
    assert!(app.recording.error.is_none(), "{:?}", app.recording.error);
    assert_eq!(app.side_tab, SideTab::Recording);
    let l = app.recording.loaded().expect("the film's recording is loaded");
    assert!(l.frames().len() >= 100, "{} frames", l.frames().len());
    assert!(l.recording.mark_count() > 3 * l.frames().len(), "most marks are found");
    let f = app.recording.film().expect("the film is kept");
    assert_eq!((f.report.width_px, f.report.height_px), (1280, 1024));
    // The panel shows the frame at the clock's time (0: the model's start, the recording's
    // first inner turning point), the frame decoded and drawn.
    let k = app.recording.frame_at(0.0).expect("a frame at t = 0");
    assert_eq!(app.film_frame_shown(), Some(k));
    assert!(h.query_by_label(&format!("film frame {k}")).is_some());
    assert!(h.query_by_label_contains("film: colours-none-short.mp4").is_some());
    // The clock moves the frame.
    let later = h.state().recording.frame_seconds(k + 40).expect("a time");
    h.state_mut().player.seek(later);
    h.run_steps(2);
    assert_eq!(h.state().film_frame_shown(), Some(k + 40));
}

/// On a laptop's screen the recording's facts wrap in the side panel: the long notes of a film
/// through a near camera once widened it over the view and pushed the film out of the window.
#[test]
fn the_film_shows_beside_the_facts_in_a_small_window() {
    if !have_ffmpeg() {
        return;
    }
    let near = film().with_file_name("dark-perspective-start.mp4");
    let h = dropped_on_the_window(near, [1280.0, 720.0]);
    let k = h.state().film_frame_shown().expect("a frame shown");
    let frame = h.get_by_label(&format!("film frame {k}")).rect();
    let facts = h.get_by_label("pixel noise").rect();
    assert!(facts.right() < 320.0, "the side panel ends at {}", facts.right());
    assert!(frame.left() > facts.right() && frame.right() < 1280.0, "the film at {frame:?}");
    assert!(frame.width() > 200.0, "the film {} points wide", frame.width());
}

#[test]
fn a_film_without_a_body_asks_for_one_then_opens() {
    if !have_ffmpeg() {
        return;
    }
    let mut app = RinglabApp::new(Settings::default(), Mode::Fixed { seconds: 0.0 });
    app.recording.import_options.body = None;
    app.open_recording(film());
    let pending = app.recording.pending_import().expect("the import dialog asks");
    assert!(pending.error.to_string().contains("the body is not in the file"), "{}", pending.error);
    assert!(app.recording.loaded().is_none());
    let mut opts = app.recording.import_options.clone();
    opts.body = Some(steel_ring());
    app.recording.retry_import(None, opts);
    app.finish_recording_jobs();
    assert!(app.recording.film().is_some(), "{:?}", app.recording.error);
}

#[test]
fn the_tracking_runs_on_its_thread_and_can_be_cancelled() {
    if !have_ffmpeg() {
        return;
    }
    let mut app = RinglabApp::new(Settings::default(), Mode::Live);
    app.recording.import_options.body = Some(steel_ring());
    app.open_recording(film());
    assert!(app.recording.loading().is_some(), "the call returned at once");
    app.act_on_recording(RecordingAction::CancelOpen);
    app.finish_recording_jobs();
    assert!(app.recording.loaded().is_none());
    assert_eq!(app.recording.note.as_deref(), Some("the tracking was cancelled"));
    assert!(app.recording.error.is_none());
}

/// The film opened and fitted (in fixed mode the fit runs at once), shown at its stored frame
/// 150: the frame with the tracked marks, the model's marks and both paths of A.
#[test]
fn app_film_fitted() {
    if !have_ffmpeg() {
        return;
    }
    let (w, h) = (1480u32, 920u32);
    let mut app = app();
    app.open_recording(film());
    app.act_on_recording(RecordingAction::Fit);
    let fitted = app.recording.fitted().expect("fitted");
    let marks = fitted.marks.as_ref().expect("the model's marks, for the film");
    assert!(marks.iter().filter(|m| m.is_some()).count() > 100, "the model covers the film");
    assert!(fitted.result.rms_px < 1.0, "rms {} px", fitted.result.rms_px);
    let at = app.recording.frame_seconds(150).expect("a time");
    let mut harness = drawing_builder(w, h).build_ui_state(
        |ui, app: &mut RinglabApp| {
            let fill = ui.visuals().panel_fill;
            ui.painter().rect_filled(ui.max_rect(), 0.0, fill);
            app.ui_root(ui)
        },
        app,
    );
    harness.state_mut().player.seek(at);
    harness.run_steps(3);
    assert_eq!(harness.state().film_frame_shown(), Some(150));
    harness.snapshot_options("app_film_fitted", &snapshot_options(w, h));
}

/// Diagnosed, the film shows the diagnosis's model: its marks follow the tracked ones.
#[test]
fn a_diagnosed_film_draws_the_diagnosis_model() {
    if !have_ffmpeg() {
        return;
    }
    let mut app = app();
    app.open_recording(film());
    app.act_on_diagnosis(ringlab::ui::diagnose_panel::DiagnoseAction::Diagnose);
    let d = app.recording.diagnosed().expect("diagnosed");
    let [_, improved] = d.model_marks.as_ref().expect("the models' marks, for a film");
    let shown = app.recording.model_marks().expect("the model is drawn");
    assert!(Arc::ptr_eq(shown, improved), "the diagnosis's chosen model");
    let rec = &app.recording.loaded().expect("loaded").recording;
    let (mut sum, mut n) = (0.0, 0usize);
    for (tracked, model) in rec.frames.iter().zip(shown.iter()) {
        let Some(model) = model else { continue };
        for (t, m) in tracked.iter().zip(model) {
            if let Some(t) = t {
                sum += (t[0] - m[0]).powi(2) + (t[1] - m[1]).powi(2);
                n += 1;
            }
        }
    }
    assert!(n > 3 * 100, "{n} marks compared");
    // Per coordinate, as the diagnosis counts it (0.50 px against its 0.32 when written).
    let rms = (sum / (2 * n) as f64).sqrt();
    assert!(
        rms < 2.0 * d.result.after.rms_px + 0.2,
        "rms {rms} px, the diagnosis's {}",
        d.result.after.rms_px
    );
}

/// File > Export film with overlay: the film the recording was tracked from, as an MP4 of as
/// many frames, with the marks drawn over it.
#[test]
fn the_film_is_exported_with_its_overlay() {
    if !have_ffmpeg() {
        return;
    }
    let mut app = app();
    app.recording.open_film(film(), None);
    app.finish_recording_jobs();
    let frames = app.recording.loaded().expect("loaded").frames().len();
    let dir = std::env::temp_dir().join(format!("ringlab-film-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let out = dir.join("overlay");
    app.file_chosen(ringlab::export::session::FileTask::FilmOverlay, out.clone());
    let said = app.exports.wait();
    assert!(said.iter().all(Result::is_ok), "{said:?}");
    let out = out.with_extension("mp4");
    let probe = std::process::Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-show_entries", "stream=nb_read_frames"])
        .args(["-of", "csv=p=0"])
        .arg(&out)
        .output()
        .expect("ffprobe runs");
    assert_eq!(String::from_utf8_lossy(&probe.stdout).trim(), frames.to_string());
    std::fs::remove_dir_all(&dir).ok();
}

/// The film panel's Tracking section: a frame range typed and Track again track the film
/// anew with it (the recording then starts at the first frame given and stops at the last);
/// a bad field is named and nothing is tracked.
#[test]
fn the_film_is_tracked_again_with_the_frames_given() {
    if !have_ffmpeg() {
        return;
    }
    let mut h = dropped_on_the_window(film(), [1480.0, 920.0]);
    let whole = h.state().recording.loaded().expect("tracked").frames().len();
    h.get_by_label("Tracking").click();
    h.run_steps(2);
    // The section's fields in their order: first frame, last frame, region, scale.
    let set = |h: &mut Harness<'_, RinglabApp>, field: usize, text: &str| {
        let fields: Vec<_> = h.get_all_by_role(egui::accesskit::Role::TextInput).collect();
        assert_eq!(fields.len(), 4, "the Tracking section's four fields");
        fields[field].set_text_value_accesskit(text);
        h.run_steps(2);
    };
    set(&mut h, 0, "4x");
    h.get_by_label("Track again").click();
    h.run_steps(2);
    assert!(h.query_by_label_contains("first frame '4x'").is_some(), "the bad field is named");
    let f = h.state().recording.film().expect("film").options.clone();
    assert_eq!((f.from_frame, f.to_frame), (0, None), "nothing tracked with a bad field");
    set(&mut h, 0, "40");
    set(&mut h, 1, "160");
    h.get_by_label("Track again").click();
    h.run_steps(4);
    let app = h.state();
    assert!(app.recording.error.is_none(), "{:?}", app.recording.error);
    let f = app.recording.film().expect("tracked again");
    assert_eq!((f.options.from_frame, f.options.to_frame), (40, Some(160)));
    let l = app.recording.loaded().expect("the new recording");
    assert!(l.frames().len() <= 121 && l.frames().len() < whole, "{} frames", l.frames().len());
    assert!(l.recording.first_frame >= 40, "first frame {}", l.recording.first_frame);
}
