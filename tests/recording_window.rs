//! A recording in the window, driven as a user would (egui_kittest, no GPU needed): dropped
//! onto the window (the same way in as File > Open recording once the dialog has its path;
//! kittest cannot drive a native dialog), a bad file, the fit on its thread and cancelled.
//! The app runs in fixed mode (work done at once, no timing) except where the threads are the
//! point, and there the test waits for the work to end, never for a time.

mod common;

use common::Dropped;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use ringlab::session::RecordingSession;
use ringlab::ui::recording_panel::RecordingAction;
use ringlab::ui::{Mode, RinglabApp, Settings, SideTab};
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn harness() -> Harness<'static, RinglabApp> {
    let app = RinglabApp::new(Settings::default(), Mode::Fixed { seconds: 1.0 });
    Harness::builder()
        .with_size([1480.0, 920.0])
        .build_ui_state(|ui, app: &mut RinglabApp| app.ui_root(ui), app)
}

fn drop_file(h: &mut Harness<'static, RinglabApp>, path: &Path) {
    h.input_mut().dropped_files.push(Arc::new(Dropped(path.to_path_buf())));
    h.run_steps(2);
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ringlab-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn a_dropped_recording_is_shown_and_the_model_starts_from_it() {
    let mut h = harness();
    h.run_steps(2);
    drop_file(&mut h, &common::test_data("sample-ring.csv"));
    let app = h.state();
    let l = app.recording.loaded().expect("loaded");
    assert_eq!(l.frames().len(), 1884);
    assert_eq!(app.side_tab, SideTab::Recording, "the Recording tab comes forward");
    assert!(app.recording.error.is_none());
    // The model now has the recording's body and starts at its first inner turning point
    // (frame 0 of the sample): the recording's model units, its mean radius 20.16 mm.
    let case = app.tracks()[0].case().clone();
    assert!(case.name.contains("sample-ring.csv, not fitted"), "{}", case.name);
    assert!((case.units.length_mm - 20.16).abs() < 1e-9);
    assert!((case.initial.theta - 0.56).abs() < 0.02, "theta0 {}", case.initial.theta);
    assert!((case.initial.phi_dot - 4.4).abs() < 0.2, "phidot0 {}", case.initial.phi_dot);
    assert!(!app.settings.compare);
    // What the file says is in the tab, the recording's name in the trace panel's legend.
    assert!(h.query_by_label_contains("1884 at 300 fps").is_some());
    // In the trace panel's legend and the plots'.
    assert_eq!(h.query_all_by_label("recording: sample-ring.csv").count(), 2);
    // The clock replays the recording to its last frame even where the model stops before.
    let end = h.state().recording.end_seconds().expect("an end");
    assert!((end - 1883.0 / 300.0).abs() < 1e-9);
}

#[test]
fn a_bad_file_shows_its_error_with_file_and_line_and_the_app_keeps_running() {
    let dir = temp_dir("window-bad");
    let good = std::fs::read_to_string(common::test_data("sample-ring.csv")).unwrap();
    let head: String = good.lines().take(30).map(|l| format!("{l}\n")).collect();
    let bad = dir.join("bad.csv");
    std::fs::write(&bad, head.replace("\n5,605.20,", "\n5,abc,")).unwrap();

    let mut h = harness();
    h.run_steps(2);
    drop_file(&mut h, &bad);
    let shown = h.query_by_label_contains("bad.csv:16: x1 = 'abc' is not a number");
    assert!(shown.is_some(), "the error names the file and the line");
    assert!(h.state().recording.loaded().is_none());
    assert_eq!(h.state().tracks().len(), 1, "the model still runs");

    // The app goes on: keys work, the message can be dismissed, a good file opens after it.
    h.key_press(egui::Key::Space);
    h.run_steps(1);
    assert!(h.state().player.is_playing());
    h.get_by_label("Dismiss").click();
    h.run_steps(2);
    assert!(h.query_by_label_contains("is not a number").is_none(), "dismissed");
    drop_file(&mut h, &common::test_data("sample-ring.csv"));
    assert!(h.state().recording.loaded().is_some());

    // A file that is not there, and one whose marks give no pose (two per frame).
    drop_file(&mut h, Path::new("/nonexistent/ring.csv"));
    assert!(h.query_by_label_contains("/nonexistent/ring.csv: cannot read the file").is_some());
    assert!(h.state().recording.loaded().is_some(), "the loaded recording stays");
    let two: String = head
        .lines()
        .map(|l| match l.split(',').collect::<Vec<_>>()[..] {
            [f, x1, y1, _, _, x3, y3, _, _] if !l.starts_with("frame") => {
                format!("{f},{x1},{y1},,,{x3},{y3},,\n")
            }
            _ => format!("{l}\n"),
        })
        .collect();
    let marks = dir.join("two-marks.csv");
    std::fs::write(&marks, two).unwrap();
    drop_file(&mut h, &marks);
    assert!(h.query_by_label_contains("two-marks.csv: no frame has three or more marks").is_some());
    std::fs::remove_dir_all(&dir).ok();
}

/// The threads as the live window has them: reading and the fit each on their own, the fit
/// cancelled. The test waits for the work to end (not for a time).
#[test]
fn the_fit_runs_on_its_thread_and_can_be_cancelled() {
    let mut app = RinglabApp::new(Settings::default(), Mode::Live);
    app.open_recording(common::test_data("sample-ring.csv"));
    app.finish_recording_jobs();
    assert!(app.recording.loaded().is_some(), "{:?}", app.recording.error);
    app.act_on_recording(RecordingAction::Fit);
    assert!(
        app.recording.fit_progress().is_some(),
        "the fit runs on its thread: the call returned at once"
    );
    app.act_on_recording(RecordingAction::CancelFit);
    assert!(app.recording.fit_cancelling());
    app.finish_recording_jobs();
    assert!(app.recording.fitted().is_none());
    assert_eq!(app.recording.note.as_deref(), Some("the fit was cancelled"));
    assert!(app.recording.error.is_none());
}

#[test]
fn a_session_reads_on_its_thread() {
    let mut s = RecordingSession::new(true);
    s.open(common::test_data("sample-ring.csv"));
    assert!(s.loading().is_some());
    let events = s.wait();
    assert_eq!(events.len(), 1);
    assert!(s.loaded().is_some() && s.loading().is_none());
    // Frames on the display's clock: the model's t = 0 at frame 0 of the sample.
    assert_eq!(s.frame_at(0.0), Some(0));
    assert_eq!(s.frame_at(1.0), Some(300));
    assert_eq!(s.frame_at(-1.0), None);
    assert_eq!(s.frame_at(1e6), Some(1883), "the last frame after the end");
    // The pose at a frame is the frame's; between two frames it is blended.
    let f = |i: usize| s.loaded().unwrap().frames()[i];
    let (a0, p0) = s.pose_at(0.0).expect("a pose");
    assert_eq!((a0, p0), (f(0).angles.unwrap(), f(0).a_mm.unwrap()));
    let (am, pm) = s.pose_at(0.5 / 300.0).expect("a pose");
    let (a1, p1) = (f(1).angles.unwrap(), f(1).a_mm.unwrap());
    assert!(
        (am.phi - 0.5 * (a0.phi + a1.phi)).abs() < 1e-9
            && (pm[0] - 0.5 * (p0[0] + p1[0])).abs() < 1e-9
    );
    s.close();
    assert!(s.loaded().is_none());
}

/// The File menu: Close recording is there once a recording is (Open recording would start the
/// desktop's dialog, which kittest cannot drive).
#[test]
fn the_file_menu_closes_a_recording() {
    let mut h = harness();
    h.run_steps(2);
    drop_file(&mut h, &common::test_data("sample-ring.csv"));
    assert!(h.state().recording.loaded().is_some());
    h.get_by_label("File").click();
    h.run_steps(2);
    assert!(h.query_by_label("Open recording…").is_some());
    // The menu's item beside the Recording tab's button (both ask for the same action).
    assert_eq!(h.query_all_by_label("Close recording").count(), 2);
    h.get_all_by_label("Close recording").last().expect("two of them").click();
    h.run_steps(2);
    assert!(h.state().recording.loaded().is_none());
    assert!(h.query_by_label("No recording loaded.").is_some());
}

#[test]
fn a_dropped_deeplabcut_file_asks_for_what_it_lacks_and_remembers_it() {
    let rec = ringlab::recording::read_recording(&common::test_data("sample-ring.csv")).unwrap();
    let short = ringlab::recording::Recording { frames: rec.frames[..600].to_vec(), ..rec };
    let dir = temp_dir("dlc-window");
    let file = dir.join("tracked.csv");
    std::fs::write(&file, common::deeplabcut_text(&short)).unwrap();

    let mut h = harness();
    h.run_steps(2);
    drop_file(&mut h, &file);
    assert!(h.state().recording.loaded().is_none());
    assert!(h.state().recording.pending_import().is_some(), "the file waits for its options");
    assert!(h.query_by_label("Open a tracker's file").is_some(), "the dialog is shown");
    assert!(h.query_by_label_contains("frame rate is not in the file").is_some());

    // A field that does not parse is named, and nothing is read.
    h.state_mut().settings.import.fps = "three hundred".into();
    h.get_by_label("Open").click();
    h.run_steps(2);
    assert!(
        h.query_by_label_contains("frames per second: 'three hundred' is not a positive number")
            .is_some()
    );
    assert!(h.state().recording.loaded().is_none());

    {
        let form = &mut h.state_mut().settings.import;
        form.fps = "300".into();
        form.px_per_mm = "3.364764".into();
        form.shape = "ring".into();
        form.outer_radius_mm = "20.66".into();
        form.width_mm = "18".into();
        form.thickness_mm = "1".into();
    }
    // (The window re-centres on its new size a frame after it grew.)
    h.run_steps(2);
    h.get_by_label("Open").click();
    h.run_steps(3);
    let app = h.state();
    assert!(
        app.recording.pending_import().is_none(),
        "the dialog is gone: {:?} {:?}",
        app.recording.pending_import(),
        app.import_problem_text()
    );
    let l = app.recording.loaded().expect("read with the options");
    assert_eq!(l.frames().len(), 600);
    assert_eq!(l.recording.header.fps, 300.0);
    assert!(h.query_by_label_contains("DeepLabCut CSV; marks 1-4: m1, m2, m3, m4").is_some());

    // The next file of the lab is read with what was given, without asking.
    h.state_mut().recording.close();
    let second = dir.join("tracked-again.csv");
    std::fs::copy(&file, &second).unwrap();
    drop_file(&mut h, &second);
    assert!(h.state().recording.pending_import().is_none());
    assert!(h.state().recording.loaded().is_some_and(|l| l.path == second));
    // And it is kept with the settings, for the next session.
    let restored = RinglabApp::new(h.state().settings.clone(), Mode::Fixed { seconds: 1.0 });
    assert_eq!(restored.recording.import_options.fps, Some(300.0));
}
