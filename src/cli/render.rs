//! `ringlab render`: a picture without a window, through the same renderer as the app.

use super::case_args::CaseArgs;
use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use ringlab::config::{Case, load_preset};
use ringlab::render::{Gpu, OrbitCamera, SceneRenderer, UiRenderer};
use ringlab::sim::Track;
use ringlab::ui::palette::BODY_LINEAR;
use ringlab::session::DiagnosedModel;
use ringlab::ui::diagnose_panel::DiagnoseAction;
use ringlab::ui::recording_panel::RecordingAction;
use ringlab::ui::{Detail3d, Mode, RinglabApp, Settings, SideTab, scene, trace_panel};
use std::path::{Path, PathBuf};

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum View {
    /// The 3D scene: the body on the table with its traces
    #[value(name = "3d")]
    ThreeD,
    /// The top-down trace panel
    Top,
    /// The whole app window
    App,
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    #[command(flatten)]
    pub case: CaseArgs,
    /// The moment to show, in the case's time unit (as `simulate` counts it)
    #[arg(long, allow_negative_numbers = true)]
    pub time: f64,
    /// Picture width in pixels
    #[arg(long, default_value_t = 1280)]
    pub width: u32,
    /// Picture height in pixels
    #[arg(long, default_value_t = 720)]
    pub height: u32,
    /// What to draw
    #[arg(long, value_enum, default_value = "3d")]
    pub view: View,
    /// A second preset side by side on the same clock (ring vs disk: --compare paper-disk-drag)
    #[arg(long, value_name = "PRESET")]
    pub compare: Option<String>,
    /// Fixed camera as YAW,PITCH,DISTANCE (radians, radians, outer radii) looking at the
    /// middle of the path so far; default: the app's view, following the body
    #[arg(long, value_name = "YAW,PITCH,DIST")]
    pub camera: Option<String>,
    /// Leave out the contact point's path
    #[arg(long)]
    pub no_contact: bool,
    /// Show the "why" note (app view)
    #[arg(long)]
    pub why: bool,
    /// A recording to open (app view), replayed beside the model started from it; --time is
    /// then in that model's time unit
    #[arg(long, value_name = "FILE.csv")]
    pub recording: Option<PathBuf>,
    /// Fit the model to --recording first (the window's Fit button)
    #[arg(long, requires = "recording")]
    pub fit: bool,
    /// Diagnose --recording (the window's Diagnose tab) and run its improved model
    #[arg(long, requires = "recording", conflicts_with = "fit")]
    pub diagnose: bool,
    /// Output PNG file
    #[arg(long, value_name = "FILE.png")]
    pub out: PathBuf,
}

fn parse_camera(s: &str, r: f32) -> Result<OrbitCamera> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| x.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .with_context(|| format!("--camera '{s}': expected three numbers YAW,PITCH,DIST"))?;
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) || v[2] <= 0.0 {
        bail!("--camera '{s}': expected YAW,PITCH,DIST with a positive distance");
    }
    Ok(OrbitCamera { target: [0.0; 3], yaw: v[0], pitch: v[1].clamp(0.05, 1.52), distance: v[2] * r })
}

pub fn run(args: &RenderArgs) -> Result<()> {
    if !(args.time.is_finite() && args.time >= 0.0) {
        bail!("--time = {}: must be a time at or after the start (0)", args.time);
    }
    for (v, flag) in [(args.width, "--width"), (args.height, "--height")] {
        if !(16..=8192).contains(&v) {
            bail!("{flag} = {v}: must be between 16 and 8192 pixels");
        }
    }
    if args.out.extension().and_then(|e| e.to_str()).map(|e| e.eq_ignore_ascii_case("png")) != Some(true) {
        bail!("--out {}: only PNG pictures are written (name the file .png)", args.out.display());
    }
    let file = args.case.case_file()?;
    let case = args.case.case()?;
    let second = match &args.compare {
        Some(name) => {
            let f = load_preset(name)?;
            let c = f.build().map_err(anyhow::Error::msg).with_context(|| format!("preset '{name}'"))?;
            Some((name.clone(), f, c))
        }
        None => None,
    };
    let gpu = Gpu::new()?;
    let size = [args.width, args.height];
    let seconds = args.time * case.units.time_s;
    let image = match args.view {
        View::ThreeD => {
            let mut cases = vec![case.clone()];
            cases.extend(second.as_ref().map(|s| s.2.clone()));
            render_3d(&gpu, &cases, seconds, size, args)?
        }
        View::Top => {
            let mut tracks = vec![(file.name.clone(), Track::compute(case.clone()))];
            tracks.extend(second.as_ref().map(|s| (s.0.clone(), Track::compute(s.2.clone()))));
            let contact = !args.no_contact;
            let bounds = tracks.iter().filter_map(|(_, t)| trace_panel::Bounds::of(t, contact)).reduce(trace_panel::Bounds::union);
            let mut ui_renderer = UiRenderer::new(&gpu);
            ui_renderer.render(&gpu, size, 3, |ui| {
                egui_top_ui(ui, &tracks, seconds, contact, bounds);
            })?
        }
        View::App => {
            // A picture: the 3D view at every pixel, whatever the adapter.
            let mut settings = Settings {
                case: file.clone(),
                preset: file.name.clone(),
                show_contact: !args.no_contact,
                show_why: args.why,
                detail_3d: Detail3d::Full,
                ..Settings::default()
            };
            if let Some((name, f, _)) = &second {
                settings.compare = true;
                settings.compare_preset = name.clone();
                settings.compare_case = f.clone();
            }
            let mut app = RinglabApp::new(settings, Mode::Fixed { seconds });
            if let Some(path) = &args.recording {
                open_recording(&mut app, path, args.fit)?;
                if args.diagnose {
                    diagnose_recording(&mut app)?;
                }
                app.seek_model_time(args.time);
            }
            let mut ui_renderer = UiRenderer::new(&gpu);
            ui_renderer.render(&gpu, size, 3, |ui| app.ui_root(ui))?
        }
    };
    save_png(&image, &args.out)?;
    println!("wrote {} ({}x{}, {} at t = {}, {})", args.out.display(), size[0], size[1], view_name(args.view), args.time, gpu.adapter.name);
    Ok(())
}

/// Opens `path` in the app (and fits it), as the window's menu and Fit button do.
fn open_recording(app: &mut RinglabApp, path: &Path, fit: bool) -> Result<()> {
    app.open_recording(path.to_path_buf());
    app.finish_recording_jobs();
    if let Some(e) = app.recording.error.take() {
        bail!("{e}");
    }
    if fit {
        app.act_on_recording(RecordingAction::Fit);
        app.finish_recording_jobs();
        if let Some(e) = app.recording.error.take() {
            bail!("{e}");
        }
    }
    Ok(())
}

/// Diagnoses the open recording and runs the improved model, as the Diagnose tab's buttons do.
fn diagnose_recording(app: &mut RinglabApp) -> Result<()> {
    app.side_tab = SideTab::Diagnose;
    app.act_on_diagnosis(DiagnoseAction::Diagnose);
    app.finish_recording_jobs();
    if let Some(e) = app.recording.error.take() {
        bail!("{e}");
    }
    app.act_on_diagnosis(DiagnoseAction::Adopt(DiagnosedModel::Improved));
    if let Some(e) = app.recording.error.take() {
        bail!("{e}");
    }
    Ok(())
}

fn view_name(v: View) -> &'static str {
    match v {
        View::ThreeD => "3D scene",
        View::Top => "trace panel",
        View::App => "app",
    }
}

fn egui_top_ui(ui: &mut eframe::egui::Ui, tracks: &[(String, Track)], seconds: f64, contact: bool, bounds: Option<trace_panel::Bounds>) {
    use eframe::egui;
    // The app's theme (the panel's colours assume it); the first pass already uses it.
    ui.ctx().set_theme(egui::Theme::Light);
    egui::CentralPanel::default().show(ui, |ui| {
        let n = tracks.len().max(1) as f32;
        let w = (ui.available_width() - 6.0 * (n - 1.0)) / n;
        let h = ui.available_height();
        ui.horizontal(|ui| {
            for (name, t) in tracks {
                let time = seconds / t.case().units.time_s;
                ui.allocate_ui(egui::vec2(w, h), |ui| {
                    trace_panel::trace_panel_ui(ui, &format!("path of A from above: {name}"), t, time, contact, bounds);
                });
            }
        });
    });
}

/// The 3D scene of one case, or of two side by side (each half its own view, one camera).
fn render_3d(gpu: &Gpu, cases: &[Case], seconds: f64, size: [u32; 2], args: &RenderArgs) -> Result<image::RgbaImage> {
    let r = cases[0].model.body.r as f32;
    let (camera, follow) = match &args.camera {
        Some(s) => (parse_camera(s, r)?, false),
        None => (OrbitCamera::default_for(r), true),
    };
    let mut renderer = SceneRenderer::new(&gpu.device, None);
    let n = cases.len() as u32;
    let gap = if n > 1 { 4 } else { 0 };
    let w = (size[0].saturating_sub(gap * (n - 1))) / n;
    let mut out = image::RgbaImage::from_pixel(size[0], size[1], image::Rgba([255, 255, 255, 255]));
    for (i, case) in cases.iter().enumerate() {
        let track = Track::compute(case.clone());
        let t = seconds / case.units.time_s;
        let mut cam = camera;
        if !follow {
            let path = track.samples_until(t);
            if let Some(first) = path.first() {
                let (mut lo, mut hi) = ([first.x_a, first.y_a], [first.x_a, first.y_a]);
                for s in path {
                    lo = [lo[0].min(s.x_a), lo[1].min(s.y_a)];
                    hi = [hi[0].max(s.x_a), hi[1].max(s.y_a)];
                }
                cam.target = [(0.5 * (lo[0] + hi[0])) as f32, (0.5 * (lo[1] + hi[1])) as f32, 0.0];
            }
        }
        let frame = scene::scene_frame(&track, t, &cam, follow, !args.no_contact, BODY_LINEAR[i % 2]);
        let img = gpu.render_scene(&mut renderer, &frame, [w.max(1), size[1]])?;
        image::imageops::replace(&mut out, &img, (i as u32 * (w + gap)) as i64, 0);
    }
    Ok(out)
}

fn save_png(img: &image::RgbaImage, path: &Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        if !dir.is_dir() {
            bail!("--out {}: the folder {} does not exist", path.display(), dir.display());
        }
    }
    img.save_with_format(path, image::ImageFormat::Png).with_context(|| format!("cannot write {}", path.display()))
}
