//! A chart on a canvas: a plot area with linear or logarithmic axes, ticks and labels, a
//! title, lines, dots, shaded bands and a legend.

use super::canvas::{BLACK, Canvas, GREY, LIGHT_GREY, Rgb, WHITE};

/// Text scales: titles and labels.
const TITLE: usize = 2;
const LABEL: usize = 2;
const TICK: usize = 1;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis {
    pub lo: f64,
    pub hi: f64,
    pub log: bool,
}

impl Axis {
    pub fn linear(lo: f64, hi: f64) -> Axis {
        let (lo, hi) = if hi > lo { (lo, hi) } else { (lo - 0.5, lo + 0.5) };
        Axis { lo, hi, log: false }
    }

    pub fn log(lo: f64, hi: f64) -> Axis {
        let lo = lo.max(1e-12);
        Axis { lo, hi: hi.max(lo * 1.0001), log: true }
    }

    /// Position of `v` in [0, 1] along the axis.
    fn frac(&self, v: f64) -> f64 {
        if self.log {
            (v.max(1e-300).ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }

    /// Tick values and labels.
    pub fn ticks(&self) -> Vec<(f64, String)> {
        if self.log {
            let (a, b) = (self.lo.log10().floor() as i32, self.hi.log10().ceil() as i32);
            let step = ((b - a) / 6 + 1).max(1);
            return (a..=b)
                .step_by(step as usize)
                .map(|e| 10f64.powi(e))
                .filter(|v| *v >= self.lo * 0.999 && *v <= self.hi * 1.001)
                .map(|v| (v, format_tick(v, v)))
                .collect();
        }
        let step = nice_step((self.hi - self.lo) / 6.0);
        let first = (self.lo / step).ceil() as i64;
        let last = (self.hi / step).floor() as i64;
        (first..=last).map(|k| k as f64 * step).map(|v| (v, format_tick(v, step))).collect()
    }
}

/// 1, 2 or 5 times a power of ten, at least `raw`.
pub fn nice_step(raw: f64) -> f64 {
    if !(raw.is_finite() && raw > 0.0) {
        return 1.0;
    }
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * p).find(|s| *s >= raw).unwrap_or(10.0 * p)
}

fn format_tick(v: f64, step: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let decimals = if step >= 1.0 { 0 } else { (-step.log10().floor()) as usize };
    if v.abs() >= 1e5 || v.abs() < 1e-3 { format!("{v:.0e}") } else { format!("{v:.decimals$}") }
}

/// A chart: the canvas, its plot area (pixels) and axes.
pub struct Chart {
    pub canvas: Canvas,
    pub area: (f64, f64, f64, f64),
    pub x: Axis,
    pub y: Axis,
    legend: Vec<(String, Rgb)>,
}

impl Chart {
    /// A `width x height` chart with a title, axis labels, frame, grid and ticks.
    pub fn new(
        width: usize,
        height: usize,
        title: &str,
        x_label: &str,
        y_label: &str,
        x: Axis,
        y: Axis,
    ) -> Chart {
        let mut canvas = Canvas::new(width, height, WHITE);
        let th = Canvas::text_height(TITLE) as f64;
        let lh = Canvas::text_height(LABEL) as f64;
        let area = (
            20.0 + lh + 60.0,
            16.0 + th + 12.0,
            width as f64 - 24.0,
            height as f64 - 30.0 - lh - 14.0,
        );
        let tw = Canvas::text_width(title, TITLE) as f64;
        canvas.text((width as f64 - tw) / 2.0, 12.0, title, TITLE, BLACK);
        let xw = Canvas::text_width(x_label, LABEL) as f64;
        canvas.text((area.0 + area.2 - xw) / 2.0, height as f64 - lh - 8.0, x_label, LABEL, BLACK);
        let yw = Canvas::text_width(y_label, LABEL) as f64;
        canvas.text_up(12.0, (area.1 + area.3 - yw) / 2.0, y_label, LABEL, BLACK);
        let mut chart = Chart { canvas, area, x, y, legend: Vec::new() };
        chart.axes();
        chart
    }

    /// Pixel position of a data point.
    pub fn px(&self, x: f64, y: f64) -> (f64, f64) {
        let (x0, y0, x1, y1) = self.area;
        (x0 + self.x.frac(x) * (x1 - x0), y1 - self.y.frac(y) * (y1 - y0))
    }

    fn axes(&mut self) {
        let (x0, y0, x1, y1) = self.area;
        for (v, label) in self.x.ticks() {
            let (px, _) = self.px(v, self.y.lo);
            self.canvas.line((px, y0), (px, y1), 1.0, LIGHT_GREY);
            self.canvas.line((px, y1), (px, y1 + 5.0), 1.0, BLACK);
            let w = Canvas::text_width(&label, TICK) as f64;
            self.canvas.text(px - w / 2.0, y1 + 8.0, &label, TICK, BLACK);
        }
        for (v, label) in self.y.ticks() {
            let (_, py) = self.px(self.x.lo, v);
            self.canvas.line((x0, py), (x1, py), 1.0, LIGHT_GREY);
            self.canvas.line((x0 - 5.0, py), (x0, py), 1.0, BLACK);
            let w = Canvas::text_width(&label, TICK) as f64;
            self.canvas.text(x0 - 8.0 - w, py - 4.0, &label, TICK, BLACK);
        }
        for (a, b) in
            [((x0, y0), (x1, y0)), ((x1, y0), (x1, y1)), ((x1, y1), (x0, y1)), ((x0, y1), (x0, y0))]
        {
            self.canvas.line(a, b, 1.0, BLACK);
        }
    }

    fn inside(&self, p: (f64, f64)) -> bool {
        let (x0, y0, x1, y1) = self.area;
        p.0 >= x0 - 1.0 && p.0 <= x1 + 1.0 && p.1 >= y0 - 1.0 && p.1 <= y1 + 1.0
    }

    /// A polyline through the points (broken at non-finite values and outside the area).
    pub fn line(&mut self, points: &[(f64, f64)], color: Rgb, width: f64) {
        let mut prev: Option<(f64, f64)> = None;
        for &(x, y) in points {
            let ok = x.is_finite()
                && y.is_finite()
                && (!self.y.log || y > 0.0)
                && (!self.x.log || x > 0.0);
            let p = ok.then(|| self.px(x, y)).filter(|p| self.inside(*p));
            if let (Some(a), Some(b)) = (prev, p) {
                self.canvas.line(a, b, width, color);
            }
            prev = p;
        }
    }

    /// A dashed horizontal line at `y`.
    pub fn dashed_hline(&mut self, y: f64, color: Rgb) {
        let (x0, _, x1, _) = self.area;
        let (_, py) = self.px(self.x.lo, y);
        if !self.inside((x0, py)) {
            return;
        }
        let mut x = x0;
        while x < x1 {
            self.canvas.line((x, py), ((x + 8.0).min(x1), py), 1.5, color);
            x += 14.0;
        }
    }

    /// Dots at the points.
    pub fn dots(&mut self, points: &[(f64, f64)], color: Rgb, radius: f64, alpha: f64) {
        for &(x, y) in points {
            if x.is_finite() && y.is_finite() {
                let p = self.px(x, y);
                if self.inside(p) {
                    self.canvas.disc(p, radius, color, alpha);
                }
            }
        }
    }

    /// A band over the whole height between `xa` and `xb` (data units).
    pub fn band(&mut self, xa: f64, xb: f64, color: Rgb, alpha: f64) {
        let (x0, y0, x1, y1) = self.area;
        let (pa, _) = self.px(xa, self.y.lo);
        let (pb, _) = self.px(xb, self.y.lo);
        self.canvas.fill_rect(pa.clamp(x0, x1), y0, pb.clamp(x0, x1), y1, color, alpha);
    }

    pub fn add_legend(&mut self, label: &str, color: Rgb) {
        self.legend.push((label.to_string(), color));
    }

    /// Draws the legend in the top-right (or top-left) corner of the area and returns the canvas.
    pub fn finish(mut self, left: bool) -> Canvas {
        if !self.legend.is_empty() {
            let (x0, y0, x1, _) = self.area;
            let w = self.legend.iter().map(|(l, _)| Canvas::text_width(l, TICK)).max().unwrap_or(0)
                as f64
                + 40.0;
            let h = 16.0 * self.legend.len() as f64 + 8.0;
            let lx = if left { x0 + 8.0 } else { x1 - w - 8.0 };
            let ly = y0 + 8.0;
            self.canvas.fill_rect(lx, ly, lx + w, ly + h, WHITE, 0.9);
            for (a, b) in [
                ((lx, ly), (lx + w, ly)),
                ((lx + w, ly), (lx + w, ly + h)),
                ((lx + w, ly + h), (lx, ly + h)),
                ((lx, ly + h), (lx, ly)),
            ] {
                self.canvas.line(a, b, 1.0, GREY);
            }
            for (i, (label, color)) in self.legend.iter().enumerate() {
                let y = ly + 12.0 + 16.0 * i as f64;
                self.canvas.line((lx + 6.0, y), (lx + 26.0, y), 3.0, *color);
                self.canvas.text(lx + 32.0, y - 4.0, label, TICK, BLACK);
            }
        }
        self.canvas
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_inside() {
        let t = Axis::linear(0.0, 7.3).ticks();
        assert_eq!(t.iter().map(|x| x.0).collect::<Vec<_>>(), vec![0.0, 2.0, 4.0, 6.0]);
        let l = Axis::log(0.3, 40.0).ticks();
        assert_eq!(l.iter().map(|x| x.1.as_str()).collect::<Vec<_>>(), vec!["1", "10"]);
        assert_eq!(nice_step(0.13), 0.2);
    }

    #[test]
    fn data_map_to_the_area() {
        let c = Chart::new(400, 300, "t", "x", "y", Axis::linear(0.0, 1.0), Axis::log(1.0, 100.0));
        let (x0, y0, x1, y1) = c.area;
        assert_eq!(c.px(0.0, 1.0), (x0, y1));
        let (px, py) = c.px(1.0, 10.0);
        assert!((px - x1).abs() < 1e-9 && (py - 0.5 * (y0 + y1)).abs() < 1e-9);
    }
}
