//! The controls: the case's parameters (sliders, typed or dragged, with units), the presets,
//! and the playback bar.

use crate::config::{CaseFile, preset_names};
use crate::physics::Units;
use crate::sim::{Player, SPEED_MAX, SPEED_MIN};
use eframe::egui::{self, RichText, Slider};

/// What a change to the parameters asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Change {
    None,
    /// Geometry, start or shape: a new run from the initial state.
    Restart,
    /// Drag or friction only: may continue from the current state.
    Drag,
}

impl Change {
    fn and(self, other: Change) -> Change {
        match (self, other) {
            (Change::Restart, _) | (_, Change::Restart) => Change::Restart,
            (Change::Drag, _) | (_, Change::Drag) => Change::Drag,
            _ => Change::None,
        }
    }
}

/// Unit suffixes of a case file's units.
pub struct UnitLabels {
    pub length: String,
    pub rate: String,
    pub time: String,
}

impl UnitLabels {
    pub fn of(units: &Units) -> UnitLabels {
        if units.is_physical() {
            UnitLabels { length: " mm".into(), rate: " rad/s".into(), time: "s".into() }
        } else {
            UnitLabels { length: " L".into(), rate: " rad/T".into(), time: "T".into() }
        }
    }
}

fn slider(
    ui: &mut egui::Ui,
    v: &mut f64,
    range: std::ops::RangeInclusive<f64>,
    text: &str,
    suffix: &str,
    log: bool,
) -> bool {
    ui.add(Slider::new(v, range).logarithmic(log).text(text).suffix(suffix).max_decimals(4))
        .changed()
}

/// Typical scales of a case file's units, for slider ranges: (length of the body, rate).
fn scales(f: &CaseFile) -> (f64, f64) {
    let len = f.body.outer_radius.abs().max(1e-3);
    let rate = f.initial.phi_dot.abs().max(1.0);
    (len, rate)
}

/// The sliders of one case file. Returns what changed.
pub fn parameters_ui(
    ui: &mut egui::Ui,
    f: &mut CaseFile,
    units: Option<&Units>,
    base: &CaseFile,
) -> Change {
    let mut change = Change::None;
    let labels = units.map(UnitLabels::of).unwrap_or(UnitLabels {
        length: String::new(),
        rate: String::new(),
        time: String::new(),
    });
    let (len, rate) = scales(base);

    ui.label(RichText::new("Air drag (eq. 5, dimensionless)").strong());
    for (i, name) in
        ["C1 (about e1, a diameter)", "C2 (about e2, the axis)", "C3 (about e3)"].iter().enumerate()
    {
        if slider(ui, &mut f.drag.c[i], 0.001..=1.0, name, "", true) {
            change = change.and(Change::Drag);
        }
    }
    if slider(ui, &mut f.run.mu, 0.05..=1.5, "mu (static friction)", "", false) {
        change = change.and(Change::Drag);
    }
    change = change.and(slope_ui(ui, f));

    ui.add_space(6.0);
    ui.label(RichText::new("Start").strong());
    if slider(ui, &mut f.initial.theta, 0.02..=1.5, "theta0 (tilt)", " rad", false) {
        change = change.and(Change::Restart);
    }
    if slider(
        ui,
        &mut f.initial.phi_dot,
        0.0..=4.0 * rate,
        "phi'0 (precession)",
        &labels.rate,
        false,
    ) {
        change = change.and(Change::Restart);
    }
    if slider(
        ui,
        &mut f.initial.psi_dot,
        -2.0 * rate..=2.0 * rate,
        "psi'0 (spin)",
        &labels.rate,
        false,
    ) {
        change = change.and(Change::Restart);
    }

    ui.add_space(6.0);
    ui.label(RichText::new("Body").strong());
    let mut disk = f.body.shape == "disk";
    ui.horizontal(|ui| {
        if ui.radio_value(&mut disk, false, "ring").changed()
            || ui.radio_value(&mut disk, true, "disk").changed()
        {
            change = change.and(Change::Restart);
        }
    });
    if disk != (f.body.shape == "disk") {
        f.body.shape = if disk { "disk".into() } else { "ring".into() };
        if !disk && f.body.thickness.is_none() {
            f.body.thickness = Some(0.05 * f.body.outer_radius);
        }
    }
    if slider(
        ui,
        &mut f.body.outer_radius,
        0.2 * len..=3.0 * len,
        "R (outer radius)",
        &labels.length,
        false,
    ) {
        change = change.and(Change::Restart);
    }
    if slider(ui, &mut f.body.width, 0.02 * len..=3.0 * len, "h (width)", &labels.length, false) {
        change = change.and(Change::Restart);
    }
    if !disk {
        let r = f.body.outer_radius;
        let mut w = f.body.thickness.unwrap_or(0.05 * r);
        if slider(ui, &mut w, 0.005 * len..=r, "w (wall)", &labels.length, false) {
            f.body.thickness = Some(w);
            change = change.and(Change::Restart);
        }
    }
    change
}

/// The table's slope (`effects/table_slope.rs`): its tilt from level and the direction it
/// falls toward, in degrees; a tilt of zero is a level table (the paper's model).
fn slope_ui(ui: &mut egui::Ui, f: &mut CaseFile) -> Change {
    let [mut angle, mut direction] = f.effects.table_slope.unwrap_or([0.0, 0.0]);
    let mut moved = slider(ui, &mut angle, 0.0..=1.0, "table slope", " deg", false);
    moved |= slider(ui, &mut direction, 0.0..=360.0, "slope toward", " deg", false);
    if !moved {
        return Change::None;
    }
    f.effects.table_slope = (angle > 0.0).then_some([angle, direction]);
    Change::Drag
}

/// A preset picker; returns the chosen preset's file when one was picked.
pub fn preset_picker_ui(ui: &mut egui::Ui, label: &str, current: &str) -> Option<String> {
    let mut picked = None;
    egui::ComboBox::from_label(label).selected_text(current).show_ui(ui, |ui| {
        for name in preset_names() {
            if ui.selectable_label(current == name, name).clicked() {
                picked = Some(name.to_string());
            }
        }
    });
    picked
}

/// What the playback bar asks for.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PlaybackActions {
    pub reset: bool,
    pub step: bool,
    pub seek: Option<f64>,
}

/// Play/pause, step, reset, speed and the time scrubber. `end_seconds`: where the runs end,
/// if known (else the scrubber reaches to what has arrived). `time_unit_s`: seconds per unit
/// of the time shown.
pub fn playback_ui(
    ui: &mut egui::Ui,
    player: &mut Player,
    end_seconds: f64,
    time_unit_s: f64,
    time_label: &str,
) -> PlaybackActions {
    let mut act = PlaybackActions::default();
    ui.horizontal(|ui| {
        let text = if player.is_playing() { "Pause" } else { "Play" };
        if ui.button(text).on_hover_text("space").clicked() {
            player.toggle();
        }
        if ui.button("Step").on_hover_text("one output interval").clicked() {
            act.step = true;
        }
        if ui.button("Reset").on_hover_text("R: back to the start").clicked() {
            act.reset = true;
        }
        let mut speed = player.speed();
        if ui
            .add(
                Slider::new(&mut speed, SPEED_MIN..=SPEED_MAX)
                    .logarithmic(true)
                    .text("speed")
                    .suffix("x")
                    .max_decimals(2),
            )
            .changed()
        {
            player.set_speed(speed);
        }
        let unit = time_unit_s.max(1e-12);
        let mut t = player.seconds() / unit;
        let end = (end_seconds / unit).max(t).max(1e-6);
        let w = (ui.available_width() - 150.0).max(80.0);
        ui.spacing_mut().slider_width = w;
        if ui
            .add(Slider::new(&mut t, 0.0..=end).text(format!("t ({time_label})")).max_decimals(2))
            .changed()
        {
            act.seek = Some(t * unit);
        }
    });
    act
}
