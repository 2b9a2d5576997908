//! The Diagnose tab, driven as a user would (egui_kittest, no GPU needed): a recording with a
//! concealed effect dropped onto the window, diagnosed, the mismatch shown on the plots and the
//! trace, the improved model put in the simulator; the diagnosis on its thread, cancelled. The
//! app runs in fixed mode (work done at once) except where the thread is the point.

mod common;

use common::Dropped;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use ringlab::analysis::diagnose::concealed::concealed_recording;
use ringlab::physics::EffectKind;
use ringlab::session::DiagnosedModel;
use ringlab::ui::diagnose_panel::DiagnoseAction;
use ringlab::ui::{Mode, RinglabApp, Settings, SideTab};
use std::path::PathBuf;
use std::sync::Arc;

/// A recording of the paper's ring with `kind` concealed (the first seed), as a file.
fn concealed_file(kind: EffectKind) -> PathBuf {
    let (rec, _) = concealed_recording(kind, 1).expect("a concealed recording");
    let dir = std::env::temp_dir().join(format!("ringlab-diagnose-window-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("concealed-{}.csv", kind.name()));
    let mut f = std::fs::File::create(&path).unwrap();
    ringlab::recording::write_recording(&mut f, &rec).unwrap();
    path
}

#[test]
fn a_concealed_effect_is_diagnosed_in_the_window_and_its_model_adopted() {
    let app = RinglabApp::new(Settings::default(), Mode::Fixed { seconds: 1.0 });
    let mut h = Harness::builder()
        .with_size([1480.0, 920.0])
        .build_ui_state(|ui, app: &mut RinglabApp| app.ui_root(ui), app);
    h.run_steps(2);
    let path = concealed_file(EffectKind::ReynoldsDrag);
    h.input_mut().dropped_files.push(Arc::new(Dropped(path.clone())));
    h.run_steps(2);
    assert!(h.state().recording.loaded().is_some(), "{:?}", h.state().recording.error);

    // The tab says what it will do before anything runs; nothing is shaded yet.
    h.get_by_label("Diagnose").click();
    h.run_steps(2);
    assert_eq!(h.state().side_tab, SideTab::Diagnose);
    assert!(h.query_by_label("mismatch (diagnosis)").is_none());
    // The tab's label and the button now: the button is drawn after the tab.
    h.get_all_by_label("Diagnose").last().expect("the button").click();
    h.run_steps(3);

    let app = h.state();
    let d = app.recording.diagnosed().expect("a diagnosis");
    assert_eq!(d.result.finding.first(), EffectKind::ReynoldsDrag, "{}", d.result.explanation);
    assert!(d.result.after.rms_px < 0.5 * d.result.before.rms_px);
    let (a, b) = app.recording.mismatch_display_s().expect("a mismatch window on the clock");
    assert!(a < b, "{a} {b}");
    // The finding, its explanation and the candidates are in the tab; the window is shaded
    // in the plots (their legend) and both models can be run.
    assert!(h.query_by_label("Left out: reynolds_drag").is_some());
    assert!(h.query_all_by_label_contains("Reynolds").count() > 0);
    assert!(h.query_by_label("mismatch (diagnosis)").is_some());
    assert!(h.query_by_label("pivot_friction").is_some(), "every candidate is ranked");

    h.get_by_label("Run the improved model").click();
    h.run_steps(2);
    let app = h.state();
    let d = app.recording.diagnosed().unwrap();
    let improved = d.improved.as_ref().expect("the improved model runs");
    assert_eq!(&app.settings.case, improved);
    let model = &app.tracks()[0].case().model;
    assert_eq!(model.c_drag, d.result.after.c);
    assert!(model.effects.reynolds_drag.is_some(), "the simulator runs with the named effect");
    assert!(h.query_by_label("Run the improved model (running)").is_some());

    h.get_by_label("Run the baseline").click();
    h.run_steps(2);
    let app = h.state();
    assert!(app.tracks()[0].case().model.effects.reynolds_drag.is_none());
    assert_eq!(
        app.tracks()[0].case().model.c_drag,
        app.recording.diagnosed().unwrap().result.before.c
    );
    std::fs::remove_file(&path).ok();
}

/// The thread as the live window has it: the call returns at once, the diagnosis can be
/// cancelled. The test waits for the work to end (not for a time).
#[test]
fn the_diagnosis_runs_on_its_thread_and_can_be_cancelled() {
    let mut app = RinglabApp::new(Settings::default(), Mode::Live);
    app.open_recording(common::test_data("sample-ring.csv"));
    app.finish_recording_jobs();
    app.act_on_diagnosis(DiagnoseAction::Diagnose);
    assert!(app.recording.diagnose_progress().is_some(), "the diagnosis runs on its thread");
    app.act_on_diagnosis(DiagnoseAction::Cancel);
    assert!(app.recording.diagnose_cancelling());
    app.finish_recording_jobs();
    assert!(app.recording.diagnosed().is_none());
    assert_eq!(app.recording.note.as_deref(), Some("the diagnosis was cancelled"));
    // Without a diagnosis there is nothing to adopt.
    app.act_on_diagnosis(DiagnoseAction::Adopt(DiagnosedModel::Improved));
    assert!(app.recording.error.is_none());
}
