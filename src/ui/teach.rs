//! The words: the phase now, and why a ring turns back where a disk does not (after the
//! paper's section "Physical origin of retrograde turn").

use super::palette::phase_color;
use crate::physics::motion::Phase;
use crate::sim::Track;
use eframe::egui::{self, RichText};

pub const WHY_TITLE: &str = "Why does the ring turn back?";

/// The explanation, in a few short paragraphs.
pub const WHY_TEXT: &[&str] = &[
    "Air resists the ring's rotation about each of its axes with its own strength: C1 about \
     the line of nodes e1, C2 about the symmetry axis e2, C3 about e3 (the paper's eq. 5).",
    "At the lowest point of every wobble (theta at its largest) the sideways friction F_f at \
     the contact must supply the centripetal push that bends the path. While F_f > 0 the path \
     bends with the spin: prograde loops, then a straight walk.",
    "Air flows through a ring's hole, so the drag about its diameters (C1, C3) stays small. \
     Slowly the drag reshapes the motion until F_f at those lowest points dips, spikes and \
     turns negative: the push now bends the path against the spin. The path inflects and the \
     ring spirals backwards round a new centre.",
    "A disk traps air between itself and the table: the drag about its diameter is large \
     (C1, C3 >> C2), the tilting and turning rates die out quickly, F_f stays positive, and it \
     spirals the way it spins until it stops.",
];

/// One line naming what the body is doing at time `t` (the track's own time).
pub fn phase_words(track: &Track, t: f64) -> (String, egui::Color32) {
    if let Some(msg) = track.failed() {
        return (format!("the run could not start: {msg}"), egui::Color32::RED);
    }
    if let Some(end) = track.end().filter(|e| t >= e.t_end) {
        let how = match end.reason.as_str() {
            "flat" => "lying flat: the motion is over",
            "rest" => "at rest",
            "t_end" => "stopped at the end time",
            "other_rim" => "stopped: it would tip onto the other rim (outside the model)",
            _ => "stopped: the integration failed",
        };
        let phase = track.phase_at(t);
        return (how.to_string(), phase_color(phase));
    }
    match track.phase_at(t) {
        Some(p) => (p.describe().to_string(), phase_color(Some(p))),
        None => ("starting: the first cycle is not complete yet".to_string(), phase_color(None)),
    }
}

/// The sign of F_f at the last lowest point (theta_max) before `t`, in words.
pub fn friction_words(track: &Track, t: f64) -> Option<String> {
    let a = track.analysis()?;
    let p = a.theta_max_points.iter().rev().find(|p| p.t <= t)?;
    let sense = if p.f_f > 0.0 {
        "bends the path with the spin"
    } else {
        "bends the path against the spin"
    };
    Some(format!("F_f at the last lowest point: {:+.3} ({sense})", p.f_f))
}

/// The phase label over the 3D view, and the "why" note when `show_why`.
pub fn phase_label_ui(ui: &mut egui::Ui, label: &str, track: &Track, t: f64) {
    let (words, color) = phase_words(track, t);
    ui.horizontal_wrapped(|ui| {
        ui.label(RichText::new(format!("{label}:")).strong());
        ui.label(RichText::new(words).color(color).strong());
    });
    if let Some(f) = friction_words(track, t) {
        ui.label(RichText::new(f).small());
    }
}

pub fn why_note_ui(ui: &mut egui::Ui) {
    ui.label(RichText::new(WHY_TITLE).strong());
    for p in WHY_TEXT {
        ui.label(*p);
    }
}

/// The legend of phase colours.
pub fn phase_legend_ui(ui: &mut egui::Ui) {
    ui.horizontal_wrapped(|ui| {
        for (p, name) in [
            (Phase::Prograde, "prograde"),
            (Phase::Walk, "walk"),
            (Phase::Retrograde, "retrograde"),
        ] {
            swatch_ui(ui, phase_color(Some(p)));
            ui.label(name);
        }
    });
}

/// A small filled square of `color`, as in a legend.
pub fn swatch_ui(ui: &mut egui::Ui, color: egui::Color32) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(14.0, 8.0), egui::Sense::hover());
    ui.painter().rect_filled(rect, 2.0, color);
}
