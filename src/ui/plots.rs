//! Live plots against time: `v_p` (the paper's Fig. 3), `F_f` (Fig. 4c, with the theta_max
//! points marked), theta and the energy. Where the model is invalid (lift-off, slip) is shaded.

use super::palette::{LIFT_OFF_FILL, RUN_COLORS, SLIP_FILL};
use crate::physics::Sample;
use crate::sim::Track;
use eframe::egui::{self, Color32, Id};
use egui_plot::{Line, Plot, PlotPoints, Points, Span, VLine};

/// Points per series at most.
const MAX_POINTS: usize = 1500;

/// One run as the plots see it.
pub struct PlotRun<'a> {
    pub name: &'a str,
    pub track: &'a Track,
    /// The display time in the track's own units.
    pub t: f64,
    /// Multiplies the track's times to give the plots' time axis (the first run's units).
    pub time_factor: f64,
}

struct Quantity {
    id: &'static str,
    label: &'static str,
    value: fn(&Sample) -> f64,
}

const QUANTITIES: [Quantity; 4] = [
    Quantity { id: "v_p", label: "v_p: speed of A along the table (Fig. 3)", value: |s| s.v_p },
    Quantity { id: "F_f", label: "F_f: sideways friction (Fig. 4c); dots at theta_max", value: |s| s.f_f },
    Quantity { id: "theta", label: "theta: tilt (rad)", value: |s| s.theta() },
    Quantity { id: "energy", label: "energy", value: |s| s.energy },
];

fn series(run: &PlotRun, value: fn(&Sample) -> f64) -> Vec<[f64; 2]> {
    let s = run.track.samples_until(run.t);
    let stride = s.len().div_ceil(MAX_POINTS).max(1);
    let mut pts: Vec<[f64; 2]> = s.iter().step_by(stride).map(|x| [x.t * run.time_factor, value(x)]).collect();
    if let Some(now) = run.track.state_at(run.t).filter(|n| !n.clamped) {
        pts.push([run.t * run.time_factor, value(&now.sample)]);
    }
    pts
}

/// The four plots in a 2 x 2 grid filling the space given; `time_label`: the time axis' unit.
pub fn plots_ui(ui: &mut egui::Ui, runs: &[PlotRun], time_label: &str) {
    ui.horizontal(|ui| {
        ui.label(egui::RichText::new("Shaded: the model's assumptions fail there:").small());
        super::teach::swatch_ui(ui, LIFT_OFF_FILL);
        ui.label(egui::RichText::new("lift-off (F_N <= 0)").small());
        super::teach::swatch_ui(ui, SLIP_FILL);
        ui.label(egui::RichText::new("slip (friction needed > mu F_N)").small());
        if runs.len() > 1 {
            ui.separator();
            for (i, run) in runs.iter().enumerate() {
                super::teach::swatch_ui(ui, RUN_COLORS[i % RUN_COLORS.len()]);
                ui.label(egui::RichText::new(run.name).small());
            }
        }
    });
    let size = ui.available_size();
    let cell = egui::vec2((size.x - 12.0).max(100.0) / 2.0, (size.y - 8.0).max(80.0) / 2.0);
    let link = Id::unique("ringlab-plots-time");
    egui::Grid::new("plots").num_columns(2).spacing([8.0, 4.0]).show(ui, |ui| {
        for (k, q) in QUANTITIES.iter().enumerate() {
            ui.allocate_ui(cell, |ui| quantity_plot_ui(ui, q, runs, time_label, link, cell));
            if k % 2 == 1 {
                ui.end_row();
            }
        }
    });
}

fn quantity_plot_ui(ui: &mut egui::Ui, q: &Quantity, runs: &[PlotRun], time_label: &str, link: Id, cell: egui::Vec2) {
    ui.vertical(|ui| {
        ui.label(egui::RichText::new(q.label).small());
        let h = (cell.y - 20.0).max(40.0);
        let plot = Plot::new(q.id)
            .height(h)
            .width(cell.x)
            .link_axis(link, [true, false])
            .link_cursor(link, [true, false])
            .x_axis_label(time_label)
            .allow_scroll(false)
            .show_axes([true, true])
            .include_x(0.0);
        plot.show(ui, |p| {
            for (i, run) in runs.iter().enumerate() {
                let color = RUN_COLORS[i % RUN_COLORS.len()];
                for iv in run.track.lift_off_until(run.t) {
                    p.add(Span::new("", iv.start * run.time_factor..=iv.end * run.time_factor).fill(LIFT_OFF_FILL));
                }
                for iv in run.track.slip_until(run.t) {
                    p.add(Span::new("", iv.start * run.time_factor..=iv.end * run.time_factor).fill(SLIP_FILL));
                }
                p.line(Line::new(run.name, PlotPoints::new(series(run, q.value))).color(color).width(1.2));
                if q.id == "F_f" {
                    if let Some(a) = run.track.analysis() {
                        let pts: Vec<[f64; 2]> = a
                            .theta_max_points
                            .iter()
                            .filter(|m| m.t <= run.t)
                            .map(|m| [m.t * run.time_factor, m.f_f])
                            .collect();
                        p.points(Points::new(format!("{} at theta_max", run.name), PlotPoints::new(pts)).color(color).radius(2.0));
                    }
                }
            }
            if let Some(run) = runs.first() {
                p.vline(VLine::new("now", run.t * run.time_factor).color(Color32::from_gray(120)).width(1.0));
            }
        });
    });
}
