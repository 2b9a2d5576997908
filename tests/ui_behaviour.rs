//! The window's controls driven as a user would (through egui_kittest, no GPU needed): keys,
//! a slider, the ring-versus-disk button. The runs are computed at once (fixed mode), so the
//! effects can be checked in the same frame.

use eframe::egui::{self, accesskit::Role};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use ringlab::ui::{Mode, RinglabApp, Settings};

fn harness(app: RinglabApp) -> Harness<'static, RinglabApp> {
    Harness::builder()
        .with_size([1480.0, 920.0])
        .build_ui_state(|ui, app: &mut RinglabApp| app.ui_root(ui), app)
}

fn fixed(settings: Settings, seconds: f64) -> RinglabApp {
    RinglabApp::new(settings, Mode::Fixed { seconds })
}

#[test]
fn space_plays_and_pauses_and_r_resets() {
    let mut h = harness(fixed(Settings::default(), 2.0));
    h.run_steps(2);
    assert!(!h.state().player.is_playing(), "fixed mode starts paused");
    h.key_press(egui::Key::Space);
    h.run_steps(1);
    assert!(h.state().player.is_playing());
    h.key_press(egui::Key::Space);
    h.run_steps(1);
    assert!(!h.state().player.is_playing());
    assert!(h.state().player.seconds() > 1.9);
    h.key_press(egui::Key::R);
    h.run_steps(1);
    assert_eq!(h.state().player.seconds(), 0.0);
}

#[test]
fn a_drag_slider_restarts_the_run_with_the_new_coefficient() {
    let mut h = harness(fixed(Settings::default(), 2.0));
    h.run_steps(2);
    let before = h.state().settings.case.drag.c[0];
    h.get_by_role_and_label(Role::Slider, "C1 (about e1, a diameter)").increment_accesskit();
    h.run_steps(2);
    let after = h.state().settings.case.drag.c[0];
    assert!(after > before, "C1 went from {before} to {after}");
    let tracks = h.state().tracks();
    assert_eq!(tracks[0].case().model.c_drag[0], after, "the run uses the new C1");
    assert_eq!(h.state().player.seconds(), 0.0, "a change restarts from the initial state");
}

#[test]
fn ring_vs_disk_puts_two_runs_side_by_side() {
    let mut h = harness(fixed(Settings::default(), 2.0));
    h.run_steps(2);
    h.get_by_label("Ring vs disk").click();
    h.run_steps(2);
    let app = h.state();
    assert!(app.settings.compare);
    let tracks = app.tracks();
    assert_eq!(tracks.len(), 2);
    assert_eq!(tracks[0].case().name, "paper-ring");
    assert_eq!(tracks[1].case().name, "paper-disk-drag");
    assert!(tracks[0].inflection_time().is_some() && tracks[1].inflection_time().is_none());
}

#[test]
fn a_bad_value_is_reported_not_run() {
    let mut settings = Settings::default();
    settings.case.body.thickness = Some(5.0); // a wall thicker than the radius
    let mut h = harness(fixed(settings, 1.0));
    h.run_steps(2);
    // Stored settings that do not build fall back to the defaults, with a note.
    assert!(h.query_by_label_contains("the parameters were reset").is_some());
    assert_eq!(h.state().tracks().len(), 1);
}
