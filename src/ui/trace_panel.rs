//! The top-down trace panel: the path of A seen from above, coloured by phase, with the
//! contact point's path (optional), the start, the inflection, the current position and a
//! scale bar; a recording's path over it ([`Overlay`]).

use super::palette::{CONTACT_RGB, phase_color};
use super::scene::simplify;
use crate::physics::Units;
use crate::render::nice_step;
use crate::sim::Track;
use eframe::egui::{self, Align2, Color32, FontId, Pos2, Rect, Shape, Stroke, Vec2};

/// States of one path at most (the panel is a few hundred pixels wide, and every point is
/// triangles to draw); longer tracks are thinned.
const MAX_POINTS: usize = 3000;
const INK: Color32 = Color32::from_rgb(30, 30, 36);

/// The table region a panel shows, in table coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub min: [f64; 2],
    pub max: [f64; 2],
}

impl Bounds {
    /// Everything `track` has received (A, and P when `contact`), so that the view only grows.
    pub fn of(track: &Track, contact: bool) -> Option<Bounds> {
        let mut it = track.samples().iter();
        let first = it.next()?;
        let mut b = Bounds { min: [first.x_a, first.y_a], max: [first.x_a, first.y_a] };
        for s in track.samples() {
            b.add(s.x_a, s.y_a);
            if contact {
                b.add(s.x_p, s.y_p);
            }
        }
        Some(b)
    }

    fn add(&mut self, x: f64, y: f64) {
        self.min = [self.min[0].min(x), self.min[1].min(y)];
        self.max = [self.max[0].max(x), self.max[1].max(y)];
    }

    /// The box around `points` (None without points).
    pub fn of_points(points: &[[f64; 2]]) -> Option<Bounds> {
        let first = points.first()?;
        let mut b = Bounds { min: *first, max: *first };
        for p in points {
            b.add(p[0], p[1]);
        }
        Some(b)
    }

    pub fn union(self, o: Bounds) -> Bounds {
        let mut b = self;
        b.add(o.min[0], o.min[1]);
        b.add(o.max[0], o.max[1]);
        b
    }
}

/// Table to screen: equal scales, y up, the bounds fitted with a margin.
struct Mapping {
    centre: [f64; 2],
    px_per_unit: f64,
    screen_centre: Pos2,
}

impl Mapping {
    fn new(b: &Bounds, rect: Rect, margin_units: f64) -> Mapping {
        let w = (b.max[0] - b.min[0]).max(1e-9) + 2.0 * margin_units;
        let h = (b.max[1] - b.min[1]).max(1e-9) + 2.0 * margin_units;
        let px = (rect.width() as f64 / w).min(rect.height() as f64 / h);
        Mapping {
            centre: [0.5 * (b.min[0] + b.max[0]), 0.5 * (b.min[1] + b.max[1])],
            px_per_unit: px,
            screen_centre: rect.center(),
        }
    }

    fn to_screen(&self, x: f64, y: f64) -> Pos2 {
        Pos2::new(
            self.screen_centre.x + ((x - self.centre[0]) * self.px_per_unit) as f32,
            self.screen_centre.y - ((y - self.centre[1]) * self.px_per_unit) as f32,
        )
    }

    fn to_world(&self, p: Pos2) -> [f64; 2] {
        [
            self.centre[0] + (p.x - self.screen_centre.x) as f64 / self.px_per_unit,
            self.centre[1] - (p.y - self.screen_centre.y) as f64 / self.px_per_unit,
        ]
    }
}

/// One length in words, in the case's units.
pub fn length_label(len: f64, units: &Units) -> String {
    if units.is_physical() {
        format!("{} mm", fmt_len(len))
    } else {
        format!("{} L ({} mm)", fmt_len(len), fmt_len(len * units.length_mm))
    }
}

/// A length with three significant digits at most, without trailing zeros.
fn fmt_len(x: f64) -> String {
    if x >= 100.0 || x.fract() == 0.0 {
        return format!("{x:.0}");
    }
    let decimals = (2 - x.abs().log10().floor() as i32).clamp(0, 6) as usize;
    let s = format!("{x:.decimals$}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

/// Another path drawn over the model's (a recording's point A), in the track's units and
/// frame.
pub struct Overlay<'a> {
    /// The path so far.
    pub points: &'a [[f64; 2]],
    pub color: Color32,
    /// Where it is now.
    pub now: Option<[f64; 2]>,
    /// Line width (points).
    pub width: f32,
    /// Single points marked with a cross (a tracker's glitches on a recording's path).
    pub crosses: &'a [[f64; 2]],
}

/// Draws the panel for `track` at its time `t`, filling the space given. `bounds`: the region
/// to show (shared by panels side by side so that they have one scale).
pub fn trace_panel_ui(
    ui: &mut egui::Ui,
    title: &str,
    track: &Track,
    t: f64,
    show_contact: bool,
    bounds: Option<Bounds>,
) {
    trace_panel_with_ui(ui, title, track, t, show_contact, bounds, &[]);
}

/// [`trace_panel_ui`] with other paths over the model's (their bounds belong in `bounds`).
pub fn trace_panel_with_ui(
    ui: &mut egui::Ui,
    title: &str,
    track: &Track,
    t: f64,
    show_contact: bool,
    bounds: Option<Bounds>,
    overlays: &[Overlay],
) {
    let size = ui.available_size().max(Vec2::splat(60.0));
    let (rect, _) = ui.allocate_exact_size(size, egui::Sense::hover());
    let painter = ui.painter_at(rect);
    // Thicker paths in presentation mode.
    let thick = super::presentation::line_scale(ui.ctx());
    // No fill: the panel's own background shows (filled pixels cost on a software rasteriser).
    painter.rect_stroke(
        rect,
        4.0,
        Stroke::new(1.0, Color32::from_gray(170)),
        egui::StrokeKind::Inside,
    );
    let font = FontId::proportional(12.0);
    painter.text(
        rect.left_top() + Vec2::new(8.0, 6.0),
        Align2::LEFT_TOP,
        title,
        FontId::proportional(13.0),
        INK,
    );
    let r = track.case().model.body.r;
    let Some(b) = bounds.or_else(|| Bounds::of(track, show_contact)) else {
        painter.text(
            rect.center(),
            Align2::CENTER_CENTER,
            "waiting for the first states",
            font,
            INK,
        );
        return;
    };
    let plot = rect.shrink2(Vec2::new(10.0, 26.0));
    let map = Mapping::new(&b, plot, 0.8 * r);

    // Light grid at a nice spacing, clipped to the plot: few lines, since a one-pixel line
    // costs a software rasteriser a block of sixteen pixels for every four it covers.
    let units = track.case().units;
    let span_units = plot.width() as f64 / map.px_per_unit;
    let grid = nice_step(span_units / 5.0);
    let grid_stroke = Stroke::new(1.0, Color32::from_rgb(228, 226, 218));
    let (lo, hi) = (map.to_world(rect.left_bottom()), map.to_world(rect.right_top()));
    let mut gx = (lo[0] / grid).ceil() * grid;
    while gx <= hi[0] {
        let x = map.to_screen(gx, 0.0).x;
        painter.vline(x, rect.y_range(), grid_stroke);
        gx += grid;
    }
    let mut gy = (lo[1] / grid).ceil() * grid;
    while gy <= hi[1] {
        let y = map.to_screen(0.0, gy).y;
        painter.hline(rect.x_range(), y, grid_stroke);
        gy += grid;
    }

    let path = track.path_until(t, MAX_POINTS);
    let scr = |p: [f64; 2]| map.to_screen(p[0], p[1]);
    // Half a pixel of error is invisible; most output states are not needed to draw the arcs.
    let tol = 0.5 / map.px_per_unit;
    if show_contact && path.len() > 1 {
        let c =
            Color32::from_rgb(CONTACT_RGB[0], CONTACT_RGB[1], CONTACT_RGB[2]).gamma_multiply(0.45);
        let p: Vec<[f64; 2]> = path.iter().map(|q| q.p).collect();
        let kept = simplify(&p, tol, |_| false);
        painter.add(Shape::line(kept.iter().map(|&i| scr(p[i])).collect(), Stroke::new(1.0, c)));
    }
    // The path of A in runs of one colour (one phase).
    let a: Vec<[f64; 2]> = path.iter().map(|q| q.a).collect();
    let phases: Vec<_> = path.iter().map(|q| track.phase_at(q.t)).collect();
    let kept = simplify(&a, tol, |i| phases[i] != phases[i - 1]);
    let mut run: Vec<Pos2> = Vec::new();
    let mut run_phase = None;
    for (k, &i) in kept.iter().enumerate() {
        let phase = phases[i];
        let p = scr(a[i]);
        if k > 0 && phase != run_phase && !run.is_empty() {
            run.push(p);
            painter.add(Shape::line(
                std::mem::take(&mut run),
                Stroke::new(1.8 * thick, phase_color(run_phase)),
            ));
        }
        run_phase = phase;
        run.push(p);
    }
    if run.len() > 1 {
        painter.add(Shape::line(run, Stroke::new(1.8 * thick, phase_color(run_phase))));
    }
    // Over the model's path, thinner, so that where the two agree both show.
    for o in overlays {
        let kept = simplify(o.points, tol, |_| false);
        if kept.len() > 1 {
            painter.add(Shape::line(
                kept.iter().map(|&i| scr(o.points[i])).collect(),
                Stroke::new(o.width * thick, o.color),
            ));
        }
    }

    if let Some(first) = path.first() {
        let p = scr(first.a);
        painter.circle_stroke(p, 5.0, Stroke::new(1.5, INK));
        painter.text(p + Vec2::new(7.0, -7.0), Align2::LEFT_BOTTOM, "start", font.clone(), INK);
    }
    if let Some(ti) = track.inflection_time().filter(|&ti| ti <= t)
        && let Some(s) = track.state_at(ti)
    {
        let p = map.to_screen(s.sample.x_a, s.sample.y_a);
        painter.circle_stroke(p, 7.0, Stroke::new(2.0, INK));
        painter.circle_filled(p, 2.5, INK);
        painter.text(p + Vec2::new(9.0, 9.0), Align2::LEFT_TOP, "inflection", font.clone(), INK);
    }
    if let Some(n) = track.state_at(t).map(|s| s.sample) {
        if show_contact {
            painter.circle_filled(
                map.to_screen(n.x_p, n.y_p),
                3.0,
                Color32::from_rgb(CONTACT_RGB[0], CONTACT_RGB[1], CONTACT_RGB[2]),
            );
        }
        let p = map.to_screen(n.x_a, n.y_a);
        painter.circle_filled(p, 5.0, phase_color(track.phase_at(t)));
        painter.circle_stroke(p, 5.0, Stroke::new(1.5, Color32::WHITE));
    }
    // Crosses where an overlay marks single points.
    for o in overlays {
        for &q in o.crosses {
            let c = scr(q);
            let d = Vec2::splat(4.0);
            let stroke = Stroke::new(1.8, o.color);
            painter.line_segment([c - d, c + d], stroke);
            painter.line_segment([c + Vec2::new(-4.0, 4.0), c + Vec2::new(4.0, -4.0)], stroke);
        }
    }
    // A square for the overlay's present position (the model's is round).
    for (o, p) in overlays.iter().filter_map(|o| o.now.map(|p| (o, scr(p)))) {
        let r = Rect::from_center_size(p, Vec2::splat(9.0));
        painter.rect_filled(r, 1.0, o.color);
        painter.rect_stroke(r, 1.0, Stroke::new(1.5, Color32::WHITE), egui::StrokeKind::Outside);
    }

    // Scale bar: a nice length about a fifth of the width, bottom left.
    let bar = nice_step(span_units / 5.0);
    let bar_px = (bar * map.px_per_unit) as f32;
    let a = Pos2::new(rect.left() + 12.0, rect.bottom() - 12.0);
    let bz = a + Vec2::new(bar_px, 0.0);
    painter.line_segment([a, bz], Stroke::new(2.0, INK));
    for p in [a, bz] {
        painter.line_segment(
            [p - Vec2::new(0.0, 4.0), p + Vec2::new(0.0, 4.0)],
            Stroke::new(1.5, INK),
        );
    }
    painter.text(
        a + Vec2::new(bar_px + 6.0, 0.0),
        Align2::LEFT_CENTER,
        length_label(bar, &units),
        font,
        INK,
    );
}

#[cfg(test)]
mod tests {
    use super::fmt_len;

    #[test]
    fn lengths_read_well() {
        assert_eq!(fmt_len(4.032), "4.03");
        assert_eq!(fmt_len(0.2), "0.2");
        assert_eq!(fmt_len(40.32), "40.3");
        assert_eq!(fmt_len(200.0), "200");
        assert_eq!(fmt_len(0.05), "0.05");
    }
}
