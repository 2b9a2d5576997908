//! `ringlab bench-view`: the speed figures of the visualizer (`docs/speed.md`, "The window and
//! the renderer").
//! Each figure is a measurement of this machine, printed, never asserted.
//!
//! - `offscreen`: the 3D scene with its traces at 1280x720, rendered and waited for (and once
//!   more with the read-back), median of N frames.
//! - `app-offscreen`: the whole app (egui, 3D, plots) drawn offscreen at the window's size.
//! - `stream`: the integrator thread on its own (how many times real time it runs, no gaps),
//!   and paced like a 60 Hz display at 20x (frames that found their state missing).
//! - `window`: the real window (run it under Xvfb): frame intervals, the time from a parameter
//!   change to the first frame showing the new run, and the resident memory over time, while
//!   the paper ring plays, restarts every 2 s and loops.

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use eframe::egui;
use ringlab::config::{Case, load_preset};
use ringlab::render::{Gpu, OrbitCamera, SceneRenderer, UiRenderer};
use ringlab::sim::{SimHandle, Track};
use ringlab::ui::controls::Change;
use ringlab::ui::palette::BODY_LINEAR;
use ringlab::ui::{Detail3d, Mode, RinglabApp, Settings, on_software_adapter, scene};
use serde::Serialize;
use std::time::{Duration, Instant};

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum What {
    Offscreen,
    AppOffscreen,
    Stream,
    Window,
}

#[derive(Args, Debug)]
pub struct BenchViewArgs {
    /// Which measurement
    #[arg(value_enum)]
    pub what: What,
    /// Frames to time (offscreen measurements)
    #[arg(long, default_value_t = 60)]
    pub frames: usize,
    /// How long the window runs (window measurement), seconds
    #[arg(long, default_value_t = 60.0)]
    pub seconds: f64,
    /// The 3D view's detail in the window measurement (as the window's "3D detail" setting)
    #[arg(long, value_enum, default_value_t = DetailArg::Auto)]
    pub detail: DetailArg,
    /// Window measurement: draw egui's shapes with egui-wgpu's own shader even on a software
    /// rasteriser (the window hands them to ringlab's lean painter there), for comparison
    #[arg(long)]
    pub egui_painter: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DetailArg {
    Auto,
    Full,
    Fast,
}

impl DetailArg {
    fn detail(self) -> Detail3d {
        match self {
            DetailArg::Auto => Detail3d::Auto,
            DetailArg::Full => Detail3d::Full,
            DetailArg::Fast => Detail3d::Fast,
        }
    }
}

fn stats(mut v: Vec<f64>) -> Stat {
    v.sort_by(|a, b| a.total_cmp(b));
    let q =
        |f: f64| v.get(((v.len() as f64 - 1.0) * f).round() as usize).copied().unwrap_or(f64::NAN);
    Stat {
        n: v.len(),
        min_ms: q(0.0),
        median_ms: q(0.5),
        p90_ms: q(0.9),
        max_ms: v.last().copied().unwrap_or(f64::NAN),
    }
}

#[derive(Serialize, Debug)]
struct Stat {
    n: usize,
    min_ms: f64,
    median_ms: f64,
    p90_ms: f64,
    max_ms: f64,
}

fn paper_case() -> Result<Case> {
    load_preset("paper-ring")?.build().map_err(anyhow::Error::msg)
}

pub fn run(args: &BenchViewArgs) -> Result<()> {
    match args.what {
        What::Offscreen => offscreen(args.frames),
        What::AppOffscreen => app_offscreen(args.frames),
        What::Stream => stream(),
        What::Window => window(args.seconds, args.detail.detail(), args.egui_painter),
    }
}

fn offscreen(frames: usize) -> Result<()> {
    let gpu = Gpu::new()?;
    let mut renderer = SceneRenderer::new(&gpu.device, None);
    let track = Track::compute(paper_case()?);
    let camera = OrbitCamera::default_for(track.case().model.body.r as f32);
    let size = [1280, 720];
    let t_end = track.end().map_or(100.0, |e| e.t_end);
    let mut render_ms = Vec::new();
    let mut readback_ms = Vec::new();
    let mut segments = 0;
    let mut cpu0 = None;
    for k in 0..frames.max(1) + 3 {
        if k == 3 {
            cpu0 = cpu_seconds();
        }
        // Times across the run, late enough that the traces are long.
        let t = 0.4 * t_end + 0.5 * t_end * (k as f64 / frames.max(1) as f64);
        let frame = scene::scene_frame(&track, t, &camera, true, true, BODY_LINEAR[0]);
        segments = frame.traces.len();
        let clock = Instant::now();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        renderer.render(&gpu.device, &gpu.queue, &mut encoder, 0, &frame, size);
        let index = gpu.queue.submit([encoder.finish()]);
        gpu.device
            .poll(wgpu::PollType::Wait {
                submission_index: Some(index),
                timeout: Some(Duration::from_secs(30)),
            })
            .context("waiting for the frame")?;
        let rendered = clock.elapsed().as_secs_f64() * 1e3;
        let clock = Instant::now();
        let texture = renderer.color_texture(0).context("no target")?;
        let _img = ringlab::render::headless::read_texture(&gpu.device, &gpu.queue, texture)?;
        let read = clock.elapsed().as_secs_f64() * 1e3;
        if k >= 3 {
            // The first frames build pipelines' caches and meshes.
            render_ms.push(rendered);
            readback_ms.push(rendered + read);
        }
    }
    let cpu_ms = match (cpu0, cpu_seconds()) {
        (Some(a), Some(b)) => Some((b - a) * 1e3 / render_ms.len() as f64),
        _ => None,
    };
    let report = serde_json::json!({
        "what": "offscreen 3D frame, paper ring with traces, 1280x720",
        "adapter": gpu.adapter.name,
        "trace_segments": segments,
        "cpu_ms_per_frame_with_readback": cpu_ms,
        "render": stats(render_ms),
        "render_and_readback": stats(readback_ms),
    });
    println!("{}", serde_json::to_string_pretty(&report)?);
    Ok(())
}

fn app_offscreen(frames: usize) -> Result<()> {
    let gpu = Gpu::new()?;
    let mut ui = UiRenderer::new(&gpu);
    let case = paper_case()?;
    let mut times = Vec::new();
    let mut app = RinglabApp::new(Settings::default(), Mode::Fixed { seconds: 0.0 });
    let mut cpu = 0.0;
    for k in 0..frames.max(1) + 2 {
        app.player.seek((40.0 + k as f64) * case.units.time_s);
        let c0 = cpu_seconds();
        let clock = Instant::now();
        let _img = ui.render(&gpu, [1480, 920], 1, |u| app.ui_root(u))?;
        if k >= 2 {
            times.push(clock.elapsed().as_secs_f64() * 1e3);
            cpu += cpu_seconds().zip(c0).map_or(0.0, |(b, a)| b - a);
        }
    }
    // What egui asked of the rasteriser, counted on one more frame (not timed).
    ui.count_drawing = true;
    ui.render(&gpu, [1480, 920], 1, |u| app.ui_root(u))?;
    let drawing = ui.last_stats;
    let report = serde_json::json!({
        "what": "whole app drawn offscreen at 1480x920 (one egui pass + 3D + plots + read-back)",
        "adapter": gpu.adapter.name,
        "cpu_ms_per_frame": cpu * 1e3 / frames.max(1) as f64,
        "egui_drawing": drawing,
        "frame": stats(times),
    });
    println!("{}", serde_json::to_string_pretty(&report)?);
    Ok(())
}

fn stream() -> Result<()> {
    let case = paper_case()?;
    let dt = case.dt;
    let time_s = case.units.time_s;

    // Flat out: the display takes everything as soon as it is there.
    let clock = Instant::now();
    let mut h = SimHandle::spawn(case.clone())?;
    while !h.track.is_finished() {
        h.pump(f64::INFINITY);
        std::thread::yield_now();
    }
    let wall = clock.elapsed().as_secs_f64();
    let t_end = h.track.end().map_or(0.0, |e| e.t_end);
    let samples = h.track.samples();
    let gaps = samples[..samples.len() - 1]
        .iter()
        .enumerate()
        .filter(|(k, s)| (s.t - *k as f64 * dt).abs() > 1e-9)
        .count();
    let flat_out = t_end * time_s / wall;

    // Paced: a 60 Hz display at 20x real time, pumping what each frame needs.
    let speed = 20.0;
    let frame = 1.0 / 60.0;
    let mut h = SimHandle::spawn(case)?;
    let start = Instant::now();
    let mut starved = 0;
    let mut frames = 0;
    let mut k = 1;
    loop {
        let target = start + Duration::from_secs_f64(k as f64 * frame);
        if let Some(wait) = target.checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
        let display = (k as f64 * frame * speed / time_s).min(t_end);
        h.pump(display + 2.0 * dt);
        frames += 1;
        if h.track.last_time().is_none_or(|t| t < display) {
            starved += 1;
        }
        if display >= t_end {
            break;
        }
        k += 1;
    }
    let report = serde_json::json!({
        "what": "integrator thread, paper ring from start to flat",
        "flat_out": {
            "model_time": t_end,
            "real_seconds_of_motion": t_end * time_s,
            "wall_seconds": wall,
            "times_real_time": flat_out,
            "states": samples.len(),
            "gaps": gaps,
        },
        "paced_60hz_at_20x": { "frames": frames, "frames_without_their_state": starved },
    });
    println!("{}", serde_json::to_string_pretty(&report)?);
    Ok(())
}

/// CPU time this process has used (all threads, user and system), seconds (Linux; ticks of
/// 10 ms). Under load from other processes it measures the work better than wall time does.
fn cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/stat").ok()?;
    let rest = s.rsplit_once(')')?.1;
    let f: Vec<&str> = rest.split_whitespace().collect();
    let utime: f64 = f.get(11)?.parse().ok()?;
    let stime: f64 = f.get(12)?.parse().ok()?;
    Some((utime + stime) / 100.0)
}

/// Resident memory of this process, MiB (Linux).
fn rss_mib() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

struct WindowBench {
    app: RinglabApp,
    started: Instant,
    seconds: f64,
    last_frame: Option<Instant>,
    intervals: Vec<f64>,
    ui_ms: Vec<f64>,
    latencies: Vec<f64>,
    last_change: Instant,
    flip: bool,
    rss: Vec<(f64, f64)>,
    next_rss: f64,
    done: bool,
    /// CPU seconds and frames counted from the end of the warm-up second.
    cpu_start: Option<(f64, usize)>,
    /// Whether the adapter is a software rasteriser (seen on the first frame).
    software: Option<bool>,
    /// Whether egui's shapes went to the lean painter.
    lean: bool,
}

impl eframe::App for WindowBench {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let now = Instant::now();
        let elapsed = now.duration_since(self.started).as_secs_f64();
        self.software.get_or_insert_with(|| on_software_adapter(ui.ctx()));
        self.lean = ringlab::ui::lean_paint::is_enabled(ui.ctx());
        // Skip the first second (start-up, first pipelines).
        if let Some(prev) = self.last_frame.filter(|_| elapsed > 1.0) {
            self.intervals.push(now.duration_since(prev).as_secs_f64() * 1e3);
            if self.cpu_start.is_none() {
                self.cpu_start = cpu_seconds().map(|c| (c, self.intervals.len()));
            }
        }
        self.last_frame = Some(now);
        if elapsed >= self.next_rss {
            self.rss.push((elapsed, rss_mib().unwrap_or(f64::NAN)));
            self.next_rss += if self.seconds > 120.0 { 30.0 } else { 5.0 };
        }
        // A slider change every two seconds (C1 between two values): the run restarts.
        if now.duration_since(self.last_change) > Duration::from_secs(2) {
            if let Some(l) = self.app.last_restart_latency.take() {
                self.latencies.push(l.as_secs_f64() * 1e3);
            }
            self.flip = !self.flip;
            self.app.settings.case.drag.c[0] = if self.flip { 0.031 } else { 0.03 };
            self.app.apply_change(Change::Drag);
            self.last_change = now;
        }
        if !self.app.player.is_playing() {
            self.app.reset();
        }
        let clock = Instant::now();
        self.app.ui_root(ui);
        self.ui_ms.push(clock.elapsed().as_secs_f64() * 1e3);
        ui.ctx().request_repaint();
        if elapsed >= self.seconds && !self.done {
            self.done = true;
            self.report();
            ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }
}

impl WindowBench {
    fn report(&self) {
        let cpu_ms_per_frame = match (self.cpu_start, cpu_seconds()) {
            (Some((c0, n0)), Some(c1)) if self.intervals.len() > n0 => {
                Some((c1 - c0) * 1e3 / (self.intervals.len() - n0) as f64)
            }
            _ => None,
        };
        let software = self.software.unwrap_or(false);
        let detail = self.app.settings.detail_3d;
        let report = serde_json::json!({
            "cpu_ms_per_frame": cpu_ms_per_frame,
            "what": "the window (1480x920) playing the paper ring at 1x, restarting every 2 s",
            "software_adapter": software,
            "egui_shapes_drawn_by": if self.lean { "ringlab's lean painter (shaders/ui.wgsl)" } else { "egui-wgpu" },
            "detail_3d": format!("{}: the 3D view drawn at {} of its width and height", detail.describe(), detail.scale(software)),
            "seconds": self.seconds,
            "frame_interval": stats(self.intervals.clone()),
            "ui_build_cpu": stats(self.ui_ms.clone()),
            "change_to_first_frame_of_new_run": stats(self.latencies.clone()),
            "rss_mib": self.rss,
        });
        match serde_json::to_string_pretty(&report) {
            Ok(s) => println!("{s}"),
            Err(e) => eprintln!("cannot print the report: {e}"),
        }
    }
}

fn window(seconds: f64, detail: Detail3d, egui_painter: bool) -> Result<()> {
    if !(seconds > 0.0) {
        bail!("--seconds must be positive");
    }
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("ringlab bench")
            .with_inner_size([1480.0, 920.0]),
        persist_window: false,
        ..Default::default()
    };
    eframe::run_native(
        "ringlab-bench",
        options,
        Box::new(move |cc| {
            if let Some(rs) = &cc.wgpu_render_state {
                ringlab::render::callback::install(rs);
                ringlab::ui::adapt_to_adapter(&cc.egui_ctx, &rs.adapter.get_info());
                if egui_painter {
                    ringlab::ui::lean_paint::set_enabled(&cc.egui_ctx, false);
                }
            }
            let settings = Settings { speed: 1.0, detail_3d: detail, ..Settings::default() };
            let now = Instant::now();
            Ok(Box::new(WindowBench {
                app: RinglabApp::new(settings, Mode::Live),
                started: now,
                seconds,
                last_frame: None,
                intervals: Vec::new(),
                ui_ms: Vec::new(),
                latencies: Vec::new(),
                last_change: now,
                flip: false,
                rss: Vec::new(),
                next_rss: 0.0,
                done: false,
                cpu_start: None,
                software: None,
                lean: false,
            }))
        }),
    )
    .map_err(|e| anyhow::anyhow!("cannot open the window: {e}"))
}
