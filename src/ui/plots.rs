//! Live plots against time: `v_p` (the paper's Fig. 3), `F_f` (Fig. 4c, with the theta_max
//! points marked), theta and the energy. Where the model is invalid (lift-off, slip) is shaded.
//! A recording's series ([`DataLine`]) share the plots of their quantity: `v_p` of data and
//! model in one plot is the paper's Fig. 3 and 4a together.

use super::palette::{LIFT_OFF_FILL, MISMATCH_FILL, RUN_COLORS, SLIP_FILL};
use crate::physics::{Interval, Sample};
use crate::sim::Track;
use eframe::egui::{self, Color32, Id};
use egui_plot::{FilledArea, Line, Plot, PlotPoints, Points, VLine};

/// Points per series at most (a plot is about 500 pixels wide, and every point is triangles
/// to draw on the CPU under lavapipe).
const BUCKETS: usize = 400;

/// One run as the plots see it.
pub struct PlotRun<'a> {
    pub name: &'a str,
    pub track: &'a Track,
    /// The display time in the track's own units.
    pub t: f64,
    /// Multiplies the track's times to give the plots' time axis (the first run's units).
    pub time_factor: f64,
}

/// A measured series drawn with the runs' in the plot of one quantity.
pub struct DataLine<'a> {
    /// The plot's id: "v_p", "F_f", "theta" or "energy".
    pub quantity: &'static str,
    pub name: &'a str,
    /// (time on the plots' axis, value in the first run's units), up to the display time.
    pub points: Vec<[f64; 2]>,
    pub color: Color32,
}

struct Quantity {
    id: &'static str,
    label: &'static str,
    value: fn(&Sample) -> f64,
}

const QUANTITIES: [Quantity; 4] = [
    Quantity { id: "v_p", label: "v_p: speed of A along the table (Fig. 3)", value: |s| s.v_p },
    Quantity {
        id: "F_f",
        label: "F_f: sideways friction (Fig. 4c); dots at theta_max",
        value: |s| s.f_f,
    },
    Quantity { id: "theta", label: "theta: tilt (rad)", value: |s| s.theta() },
    Quantity { id: "energy", label: "energy", value: |s| s.energy },
];

/// The points of a series thinned to about `buckets` by "largest triangle three buckets"
/// (Steinarsson): from each bucket the point that spans the largest triangle with the last
/// kept point and the next bucket's mean, so peaks and the shape of fast oscillations survive.
pub fn thin(points: &[[f64; 2]], buckets: usize) -> Vec<[f64; 2]> {
    let n = points.len();
    if buckets < 3 || n <= buckets {
        return points.to_vec();
    }
    let width = (n - 2) as f64 / (buckets - 2) as f64;
    let mut out = Vec::with_capacity(buckets);
    out.push(points[0]);
    let mut last = points[0];
    for b in 0..buckets - 2 {
        let start = 1 + (b as f64 * width) as usize;
        let end = (1 + ((b + 1) as f64 * width) as usize).min(n - 1);
        let next_end = (1 + ((b + 2) as f64 * width) as usize).min(n);
        let next = &points[end..next_end.max(end + 1).min(n)];
        let k = next.len().max(1) as f64;
        let mean = next.iter().fold([0.0, 0.0], |m, p| [m[0] + p[0] / k, m[1] + p[1] / k]);
        let area = |p: &[f64; 2]| {
            ((last[0] - mean[0]) * (p[1] - last[1]) - (last[0] - p[0]) * (mean[1] - last[1])).abs()
        };
        if let Some(best) =
            points[start..end.max(start + 1)].iter().max_by(|a, b| area(a).total_cmp(&area(b)))
        {
            out.push(*best);
            last = *best;
        }
    }
    out.push(points[n - 1]);
    out
}

/// The invalid intervals of a run as one filled area per kind (a band from `lo` to `hi` over
/// each interval, zero height between them): one plot item instead of one per interval, which
/// matters when a run has seventy slip intervals and four plots show them.
fn bands(
    intervals: &[Interval],
    factor: f64,
    lo: f64,
    hi: f64,
) -> Option<(Vec<f64>, Vec<f64>, Vec<f64>)> {
    if intervals.is_empty() {
        return None;
    }
    let (mut xs, mut ys_min, mut ys_max) = (Vec::new(), Vec::new(), Vec::new());
    for iv in intervals {
        let (a, b) = (iv.start * factor, iv.end * factor);
        xs.extend([a, a, b, b]);
        ys_min.extend([lo; 4]);
        ys_max.extend([lo, hi, hi, lo]);
    }
    Some((xs, ys_min, ys_max))
}

fn series(run: &PlotRun, value: fn(&Sample) -> f64) -> Vec<[f64; 2]> {
    let s = run.track.samples_until(run.t);
    let all: Vec<[f64; 2]> = s.iter().map(|x| [x.t * run.time_factor, value(x)]).collect();
    let mut pts = thin(&all, BUCKETS);
    if let Some(now) = run.track.state_at(run.t).filter(|n| !n.clamped) {
        pts.push([run.t * run.time_factor, value(&now.sample)]);
    }
    pts
}

/// The four plots in a 2 x 2 grid filling the space given; `time_label`: the time axis' unit;
/// `mismatch`: a diagnosis's mismatch window on the time axis, shaded.
pub fn plots_ui(
    ui: &mut egui::Ui,
    runs: &[PlotRun],
    time_label: &str,
    data: &[DataLine],
    mismatch: Option<[f64; 2]>,
) {
    ui.horizontal(|ui| {
        ui.label(egui::RichText::new("Shaded: the model's assumptions fail there:").small());
        super::teach::swatch_ui(ui, LIFT_OFF_FILL);
        ui.label(egui::RichText::new("lift-off (F_N <= 0)").small());
        super::teach::swatch_ui(ui, SLIP_FILL);
        ui.label(egui::RichText::new("slip (friction needed > mu F_N)").small());
        if runs.len() > 1 || !data.is_empty() {
            ui.separator();
            for (i, run) in runs.iter().enumerate() {
                super::teach::swatch_ui(ui, RUN_COLORS[i % RUN_COLORS.len()]);
                ui.label(egui::RichText::new(run.name).small());
            }
        }
        if mismatch.is_some() {
            ui.separator();
            super::teach::swatch_ui(ui, MISMATCH_FILL);
            ui.label(egui::RichText::new("mismatch (diagnosis)").small());
        }
        // One entry per recording (its lines in several plots share the name and colour).
        let mut named: Vec<&str> = Vec::new();
        for d in data {
            if named.contains(&d.name) {
                continue;
            }
            named.push(d.name);
            super::teach::swatch_ui(ui, d.color);
            ui.label(egui::RichText::new(d.name).small());
        }
    });
    let size = ui.available_size();
    let cell = egui::vec2((size.x - 12.0).max(100.0) / 2.0, (size.y - 8.0).max(80.0) / 2.0);
    let link = Id::unique("ringlab-plots-time");
    egui::Grid::new("plots").num_columns(2).spacing([8.0, 4.0]).show(ui, |ui| {
        for (k, q) in QUANTITIES.iter().enumerate() {
            let lines: Vec<&DataLine> = data.iter().filter(|d| d.quantity == q.id).collect();
            ui.allocate_ui(cell, |ui| {
                quantity_plot_ui(ui, q, runs, &lines, time_label, link, cell, mismatch)
            });
            if k % 2 == 1 {
                ui.end_row();
            }
        }
    });
}

#[allow(clippy::too_many_arguments)]
fn quantity_plot_ui(
    ui: &mut egui::Ui,
    q: &Quantity,
    runs: &[PlotRun],
    data: &[&DataLine],
    time_label: &str,
    link: Id,
    cell: egui::Vec2,
    mismatch: Option<[f64; 2]>,
) {
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
            .show_background(false)
            // Fewer, wider-spaced grid lines: each is drawn on the CPU under lavapipe.
            .grid_spacing(egui::Rangef::new(24.0, 300.0))
            .show_axes([true, true])
            .include_x(0.0);
        let lines: Vec<Vec<[f64; 2]>> = runs.iter().map(|run| series(run, q.value)).collect();
        let measured: Vec<Vec<[f64; 2]>> = data.iter().map(|d| thin(&d.points, BUCKETS)).collect();
        let (lo, hi) = lines
            .iter()
            .chain(&measured)
            .flatten()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p[1]), hi.max(p[1])));
        let pad = 0.05 * (hi - lo).max(1e-9);
        let (lo, hi) = (lo - pad, hi + pad);
        let thick = super::presentation::line_scale(ui.ctx());
        plot.show(ui, |p| {
            if let Some([a, b]) = mismatch.filter(|_| lo.is_finite() && hi.is_finite()) {
                let iv = [Interval { start: a, end: b }];
                if let Some((xs, y0, y1)) = bands(&iv, 1.0, lo, hi) {
                    p.add(
                        FilledArea::new("mismatch", &xs, &y0, &y1)
                            .fill_color(MISMATCH_FILL)
                            .allow_hover(false),
                    );
                }
            }
            for (i, (run, line)) in runs.iter().zip(lines).enumerate() {
                let color = RUN_COLORS[i % RUN_COLORS.len()];
                if lo.is_finite() && hi.is_finite() {
                    for (ivs, fill) in [
                        (run.track.slip_until(run.t), SLIP_FILL),
                        (run.track.lift_off_until(run.t), LIFT_OFF_FILL),
                    ] {
                        if let Some((xs, a, b)) = bands(&ivs, run.time_factor, lo, hi) {
                            p.add(
                                FilledArea::new("", &xs, &a, &b)
                                    .fill_color(fill)
                                    .allow_hover(false),
                            );
                        }
                    }
                }
                p.line(
                    Line::new(run.name, PlotPoints::new(line))
                        .color(color)
                        .width(1.6 * thick)
                        .allow_band(false),
                );
                if q.id == "F_f"
                    && let Some(a) = run.track.analysis()
                {
                    let pts: Vec<[f64; 2]> = a
                        .theta_max_points
                        .iter()
                        .filter(|m| m.t <= run.t)
                        .map(|m| [m.t * run.time_factor, m.f_f])
                        .collect();
                    p.points(
                        Points::new(format!("{} at theta_max", run.name), PlotPoints::new(pts))
                            .color(color)
                            .radius(2.0),
                    );
                }
            }
            // The data over the model, thinner: the noise shows, and the model under it.
            for (d, pts) in data.iter().zip(measured) {
                p.line(
                    Line::new(d.name, PlotPoints::new(pts))
                        .color(d.color)
                        .width(1.1 * thick)
                        .allow_band(false),
                );
            }
            if let Some(run) = runs.first() {
                p.vline(
                    VLine::new("now", run.t * run.time_factor)
                        .color(Color32::from_gray(120))
                        .width(1.0),
                );
            }
        });
    });
}

#[cfg(test)]
mod tests {
    use super::thin;

    #[test]
    fn thinning_keeps_the_peaks_in_time_order() {
        let pts: Vec<[f64; 2]> = (0..10_000).map(|k| [k as f64, (k as f64 * 0.05).sin()]).collect();
        let e = thin(&pts, 400);
        assert!(e.len() <= 400);
        assert!(e.windows(2).all(|w| w[1][0] > w[0][0]));
        let max = e.iter().map(|p| p[1]).fold(f64::MIN, f64::max);
        let min = e.iter().map(|p| p[1]).fold(f64::MAX, f64::min);
        assert!(max > 0.95 && min < -0.95, "the peaks survive ({min}, {max})");
        assert_eq!(thin(&pts[..50], 400).len(), 50);
    }
}
