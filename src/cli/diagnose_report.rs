//! `ringlab diagnose --report DIR`: three figures (the trace of point A with both models, the
//! residual against time with the mismatch shaded, the candidates' scores) and a report.md
//! that a lab can paste into its notebook.

use anyhow::{Context, Result};
use ringlab::analysis::diagnose::explain::{describe, sig};
use ringlab::analysis::diagnose::{Diagnosis, Finding, ModelFit};
use ringlab::physics::EffectKind;
use ringlab::plot::canvas::{BLACK, GREY};
use ringlab::plot::{Axis, Canvas, Chart, Rgb};
use ringlab::recording::Recording;
use std::fmt::Write as _;
use std::path::Path;

const DATA: Rgb = [110, 110, 110];
const BEFORE: Rgb = [215, 60, 40];
const AFTER: Rgb = [30, 90, 200];
const SHADE: Rgb = [250, 200, 60];
const NOISE: Rgb = [40, 150, 60];
const FOLLOWED: Rgb = [235, 140, 20];

pub const TRACE_PNG: &str = "trace.png";
pub const RESIDUAL_PNG: &str = "residual.png";
pub const CANDIDATES_PNG: &str = "candidates.png";

fn label(f: &ModelFit) -> String {
    match f.effect {
        EffectKind::None => "baseline (paper's model)".into(),
        k => format!("with {k}"),
    }
}

/// Point A over the table, as the camera saw it: data dots, both models' lines.
fn trace(d: &Diagnosis) -> Canvas {
    let t = &d.trace;
    let pts = t.data_px.iter().flatten().chain(&t.before_px).chain(&t.after_px);
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in pts.filter(|p| p[0].is_finite() && p[1].is_finite()) {
        for i in 0..2 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    // The same scale on both axes, a margin round the path.
    let (w, h) = (900usize, 800usize);
    let span = ((hi[0] - lo[0]).max(hi[1] - lo[1]) * 1.08).max(20.0);
    let (cx, cy) = (0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]));
    let aspect = 760.0 / 680.0;
    let x = Axis::linear(cx - 0.5 * span * aspect, cx + 0.5 * span * aspect);
    // Image y grows downward: plot -y so the picture is the camera's.
    let y = Axis::linear(-(cy + 0.5 * span), -(cy - 0.5 * span));
    let mut c =
        Chart::new(w, h, "Point A: recording and models (image pixels)", "x (px)", "-y (px)", x, y);
    let data: Vec<(f64, f64)> = t.data_px.iter().flatten().map(|p| (p[0], -p[1])).collect();
    c.dots(&data, DATA, 1.6, 0.55);
    let line = |v: &[[f64; 2]]| -> Vec<(f64, f64)> { v.iter().map(|p| (p[0], -p[1])).collect() };
    c.line(&line(&t.before_px), BEFORE, 1.6);
    c.add_legend("recording (centroid of the marks)", DATA);
    c.add_legend(&label(&d.before), BEFORE);
    if !d.finding.named().is_empty() {
        c.line(&line(&t.after_px), AFTER, 1.6);
        c.add_legend(&label(&d.after), AFTER);
    }
    // The start.
    if let Some(p) = t.before_px.first() {
        let a = c.px(p[0], -p[1]);
        c.canvas.disc(a, 4.0, BLACK, 1.0);
    }
    c.finish(true)
}

/// The residual against time: the whole-run fits per frame (faint) and in test windows, the
/// baseline fitted only up to its departure and run on, the noise, the mismatch shaded.
fn residual(d: &Diagnosis) -> Canvas {
    let r = &d.residuals;
    let (t0, t1) = (r.t_s.first().copied().unwrap_or(0.0), r.t_s.last().copied().unwrap_or(1.0));
    let top = r
        .window_before_px
        .iter()
        .chain(&r.window_followed_px)
        .chain(&r.after_px)
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max);
    let y = Axis::log(0.1, (top * 1.5).max(3.0));
    let improved = !d.finding.named().is_empty();
    let title = format!(
        "Residual against time: baseline {:.2} px, {} {:.2} px rms",
        d.before.rms_px,
        if improved { "improved" } else { "nothing better:" },
        d.after.rms_px
    );
    let mut c = Chart::new(
        1000,
        540,
        &title,
        "time (s)",
        "model - recording (px rms)",
        Axis::linear(t0, t1),
        y,
    );
    if let Some(m) = &d.mismatch {
        c.band(m.start_s, m.end_s, SHADE, 0.22);
    }
    for w in &d.windows {
        c.band(w.start_s, w.end_s, SHADE, 0.3);
    }
    let per_frame =
        |v: &[f64]| -> Vec<(f64, f64)> { r.t_s.iter().zip(v).map(|(t, v)| (*t, *v)).collect() };
    let mids: Vec<f64> = r.window_s.iter().map(|(a, b)| 0.5 * (a + b)).collect();
    let windowed =
        |v: &[f64]| -> Vec<(f64, f64)> { mids.iter().zip(v).map(|(t, v)| (*t, *v)).collect() };
    c.dots(&per_frame(&r.before_px), BEFORE, 1.0, 0.2);
    c.line(&windowed(&r.window_threshold_px), NOISE, 1.2);
    c.dashed_hline(d.noise_px, NOISE);
    if d.mismatch.is_some() {
        c.line(&windowed(&r.window_followed_px), FOLLOWED, 1.6);
    }
    c.line(&windowed(&r.window_before_px), BEFORE, 2.0);
    if improved {
        c.dots(&per_frame(&r.after_px), AFTER, 1.0, 0.2);
        c.line(&windowed(&r.window_after_px), AFTER, 2.0);
    }
    let ms = (1000.0 * r.window_s.first().map_or(0.0, |w| w.1 - w.0)).round();
    c.add_legend(
        &format!("{}, fitted to the whole run ({ms} ms windows; dots: frames)", label(&d.before)),
        BEFORE,
    );
    if improved {
        c.add_legend(&format!("{}, fitted to the whole run", label(&d.after)), AFTER);
    }
    if let Some(m) = &d.mismatch {
        c.add_legend(&format!("baseline fitted up to {:.2} s only, run on", m.start_s), FOLLOWED);
        c.add_legend("mismatch (shaded; darker: windows beyond the noise)", SHADE);
    }
    c.add_legend(&format!("noise {:.2} px (dashed), window threshold", d.noise_px), NOISE);
    c.finish(false)
}

/// Signed log of a BIC difference, for bars that span decades.
fn symlog(v: f64) -> f64 {
    v.signum() * (1.0 + v.abs()).log10()
}

/// The candidates: BIC against the baseline (bars, signed log scale), with each one's misfit.
fn candidates(d: &Diagnosis) -> Canvas {
    let rows: Vec<_> =
        d.candidates.iter().filter(|c| c.error.is_none() && c.delta_score.is_finite()).collect();
    let (w, h) = (1000usize, 140 + 46 * rows.len().max(1));
    let lo = rows.iter().map(|c| symlog(c.delta_score)).fold(-1.0f64, f64::min);
    let hi = rows.iter().map(|c| symlog(c.delta_score)).fold(1.0f64, f64::max);
    let mut canvas = Canvas::new(w, h, [255, 255, 255]);
    let title = "Candidates: BIC against the baseline (lower is better; signed log scale)";
    canvas.text((w as f64 - Canvas::text_width(title, 2) as f64) / 2.0, 12.0, title, 2, BLACK);
    let (x0, x1) = (250.0, w as f64 - 250.0);
    let px = |v: f64| x0 + (symlog(v) - lo) / (hi - lo) * (x1 - x0);
    let zero = px(0.0);
    let top = 56.0;
    canvas.line((zero, top - 8.0), (zero, h as f64 - 40.0), 1.0, GREY);
    let need = px(-d.evidence);
    let mut yy = top - 8.0;
    while yy < h as f64 - 40.0 {
        canvas.line((need, yy), (need, (yy + 6.0).min(h as f64 - 40.0)), 1.0, NOISE);
        yy += 11.0;
    }
    for (i, c) in rows.iter().enumerate() {
        let y = top + 46.0 * i as f64;
        let color = if d.finding.named().contains(&c.effect) {
            AFTER
        } else if c.effect == EffectKind::None {
            BEFORE
        } else {
            [150, 150, 150]
        };
        let end = px(c.delta_score);
        canvas.fill_rect(
            zero.min(end),
            y,
            zero.max(end).max(zero.min(end) + 2.0),
            y + 26.0,
            color,
            1.0,
        );
        let name = c.effect.name();
        canvas.text(x0 - 16.0 - Canvas::text_width(name, 2) as f64, y + 4.0, name, 2, BLACK);
        let note = format!("{:+.1}  ({} px)", c.delta_score, sig(c.rms_px));
        canvas.text(x1 + 16.0, y + 8.0, &note, 1, BLACK);
    }
    let foot = format!(
        "dashed: the {:.0} below the baseline an effect needs to be named; blue: the one named",
        d.evidence
    );
    canvas.text(x0, h as f64 - 28.0, &foot, 1, BLACK);
    canvas
}

/// Writes the figures and report.md into `dir` (created if needed).
pub fn write(dir: &Path, file: &Path, rec: &Recording, d: &Diagnosis) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    for (name, canvas) in
        [(TRACE_PNG, trace(d)), (RESIDUAL_PNG, residual(d)), (CANDIDATES_PNG, candidates(d))]
    {
        let p = dir.join(name);
        canvas.save(&p).with_context(|| format!("writing {}", p.display()))?;
    }
    let md = markdown(file, rec, d);
    let p = dir.join("report.md");
    std::fs::write(&p, md).with_context(|| format!("writing {}", p.display()))?;
    Ok(())
}

fn params(f: &ModelFit) -> String {
    let pm =
        |v: f64, s: f64| if s.is_finite() { format!("{} +- {}", sig(v), sig(s)) } else { sig(v) };
    let mut s = format!(
        "C1 = {}, C2 = {}, C3 = {}",
        pm(f.c[0], f.c_sigma[0]),
        pm(f.c[1], f.c_sigma[1]),
        pm(f.c[2], f.c_sigma[2])
    );
    let _ = write!(
        s,
        "; R = {} mm, h = {} mm",
        pm(f.body_mm[0].0, f.body_mm[0].1),
        pm(f.body_mm[1].0, f.body_mm[1].1)
    );
    if let Some((v, sd)) = f.strength {
        let _ = write!(s, "; {} ({}) = {}", f.effect, f.effect.parameter(), pm(v, sd));
    }
    s
}

fn markdown(file: &Path, rec: &Recording, d: &Diagnosis) -> String {
    let mut m = String::new();
    let name = file
        .file_name()
        .map_or_else(|| file.display().to_string(), |n| n.to_string_lossy().into_owned());
    let _ = writeln!(m, "# Diagnosis of {name}\n");
    let _ = writeln!(
        m,
        "{} frames at {} fps ({} fitted, from the first inner turning point to the still end); {} {}; pixel noise {:.3} px{}. ringlab {}, {:.1} s.\n",
        d.frames,
        rec.header.fps,
        d.frames_fitted,
        rec.header.shape,
        format_args!("R = {} mm, h = {} mm", rec.header.outer_radius_mm, rec.header.width_mm),
        d.noise_px,
        match (&d.noise_correlation, d.noise_from_marks) {
            (Some(_), _) =>
                " (estimated from the marks, corrected for the tracker's correlation in time)",
            (None, true) => " (estimated from the marks)",
            (None, false) => "",
        },
        env!("CARGO_PKG_VERSION"),
        d.compute_seconds
    );
    match &d.finding {
        Finding::Named(kinds) => {
            for k in kinds {
                let _ = writeln!(m, "**Left out: {k}** ({}).\n", describe(*k));
            }
        }
        Finding::Nothing => {
            let _ =
                writeln!(m, "**Left out: none** (the baseline is consistent with the noise).\n");
        }
        Finding::Unexplained { partial } => {
            let part = partial.as_ref().map_or(String::new(), |p| {
                format!(
                    "; {p} explains {:.0}% of the excess, partially: it leaves {:.3} px beyond the noise",
                    100.0 * p.share,
                    d.excess_px(p.rms_px)
                )
            });
            let _ = writeln!(
                m,
                "**Left out: unexplained** (the baseline misses beyond the noise and no candidate explains most of it{part}).\n"
            );
        }
    }
    if !d.glitches.is_empty() {
        let _ = writeln!(
            m,
            "Tracker glitches left out of every fit: {} mark positions.\n",
            d.glitches.len()
        );
    }
    let _ = writeln!(m, "| | misfit over the whole run | fitted |");
    let _ = writeln!(m, "|---|---|---|");
    let excess = |f: &ModelFit| d.excess_px(f.rms_px);
    let _ = writeln!(
        m,
        "| before: {} | {:.3} px rms ({:.3} px beyond the noise) | {} |",
        label(&d.before),
        d.before.rms_px,
        excess(&d.before),
        params(&d.before)
    );
    let _ = writeln!(
        m,
        "| after: {} | {:.3} px rms ({:.3} px beyond the noise) | {} |",
        label(&d.after),
        d.after.rms_px,
        excess(&d.after),
        params(&d.after)
    );
    match &d.mismatch {
        Some(w) => {
            let _ = writeln!(
                m,
                "\nMismatch: {:.3} s to {:.3} s ({:.2} px rms, {:.0}% of the baseline's misfit beyond the noise).",
                w.start_s,
                w.end_s,
                w.rms_px,
                100.0 * w.share
            );
        }
        None => {
            let _ = writeln!(m, "\nMismatch: none beyond the noise.");
        }
    }
    let _ = writeln!(m, "\n{}\n", d.explanation);
    let _ = writeln!(m, "![Point A: recording, baseline and improved model]({TRACE_PNG})\n");
    let _ = writeln!(m, "![Residual against time, mismatch shaded]({RESIDUAL_PNG})\n");
    let _ = writeln!(m, "![Candidates' scores]({CANDIDATES_PNG})\n");
    let _ = writeln!(m, "## Candidates\n");
    let _ = writeln!(m, "| rank | candidate | misfit (px rms) | BIC - baseline | strength |");
    let _ = writeln!(m, "|---|---|---|---|---|");
    for (i, c) in d.candidates.iter().enumerate() {
        let strength = c.strength.map_or("-".to_string(), |(v, s)| {
            if s.is_finite() { format!("{} +- {}", sig(v), sig(s)) } else { sig(v) }
        });
        match &c.error {
            Some(e) => {
                let _ = writeln!(m, "| {} | {} | failed: {e} | | |", i + 1, c.effect);
            }
            None => {
                let stopped = c.stopped_note().map_or(String::new(), |n| format!(" ({n})"));
                let _ = writeln!(
                    m,
                    "| {} | {} | {:.3}{stopped} | {:+.1} | {strength} |",
                    i + 1,
                    c.effect,
                    c.rms_px,
                    c.delta_score
                );
            }
        }
    }
    let _ = writeln!(
        m,
        "\nHow: each model is fitted to the whole run as one prediction from one start state (its drag, its effect's strength and the 8 numbers of the start state free), on the pixels of every tracked mark; the misfit is the RMS of model minus recording over all of them, the same for every candidate. BIC = N ln(RSS/N) + k ln N (N = {} coordinates); an effect is named when its BIC is at least {:.0} below the baseline's. The mismatch windows are {}-frame windows whose mean squared residual exceeds the noise variance beyond chance.",
        d.before.residual_count,
        d.evidence,
        ((0.05 * d.fps).round() as usize).max(5)
    );
    m
}
