//! `ringlab render`: a picture or a video without a window, through the same renderer as the
//! app.

use super::case_args::CaseArgs;
use super::render_film::{FILM_SIZE, FilmFlags, FilmRequest, check_folder};
use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use ringlab::config::{Case, CaseFile, load_preset};
use ringlab::export::mp4::find_ffmpeg;
use ringlab::export::picture::save_png;
use ringlab::export::{Aim, ExportError, VideoFormat, VideoSpec, write_video};
use ringlab::recording::import::BodyMm;
use ringlab::render::{Gpu, OrbitCamera};
use ringlab::session::DiagnosedModel;
use ringlab::ui::diagnose_panel::DiagnoseAction;
use ringlab::ui::frames::FrameSource;
use ringlab::ui::recording_panel::RecordingAction;
use ringlab::ui::{Detail3d, Mode, RinglabApp, Settings, SideTab};
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
    /// A lab's film: straight down at a known scale, the marks as discs (--video, --truth)
    Film,
}

impl View {
    fn name(self) -> &'static str {
        match self {
            View::ThreeD => ringlab::export::View::ThreeD.name(),
            View::Top => ringlab::export::View::Top.name(),
            View::App => ringlab::export::View::App.name(),
            View::Film => "film",
        }
    }
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    #[command(flatten)]
    pub case: CaseArgs,
    /// The moment to show, in the case's time unit (as `simulate` counts it)
    #[arg(
        long,
        allow_negative_numbers = true,
        required_unless_present = "video",
        conflicts_with = "video"
    )]
    pub time: Option<f64>,
    /// Width in pixels [default: 1280 for a picture, 640 for a video or a film]
    #[arg(long)]
    pub width: Option<u32>,
    /// Height in pixels [default: 720 for a picture, 360 for a video, 512 for a film]
    #[arg(long)]
    pub height: Option<u32>,
    /// What to draw
    #[arg(long, value_enum, default_value = "3d")]
    pub view: View,
    /// A second preset side by side on the same clock (ring vs disk: --compare paper-disk-drag)
    #[arg(long, value_name = "PRESET")]
    pub compare: Option<String>,
    /// Fixed camera as YAW,PITCH,DISTANCE (radians, radians, outer radii) looking at the
    /// middle of the path so far (a video: of the path up to --to); default: the app's view,
    /// following the body
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
    #[arg(
        long,
        value_name = "FILE.png",
        required_unless_present = "video",
        conflicts_with = "video"
    )]
    pub out: Option<PathBuf>,
    /// Write a video of the run from --from to --to instead of a picture: a GIF (written by
    /// ringlab: a palette of 256 colours per frame, looping) or an MP4 (H.264, made by an
    /// ffmpeg that must be on PATH)
    #[arg(long, value_name = "OUT.gif|OUT.mp4", requires_all = ["from", "to"])]
    pub video: Option<PathBuf>,
    /// Video: the first frame's time, in the case's time unit (as --time)
    #[arg(long, allow_negative_numbers = true, requires = "video")]
    pub from: Option<f64>,
    /// Video: the last frame's time (at most), in the case's time unit
    #[arg(long, allow_negative_numbers = true, requires = "video")]
    pub to: Option<f64>,
    /// Video: frames per second [default: 25; a GIF at most 50; a film 300]
    #[arg(long, allow_negative_numbers = true, requires = "video")]
    pub fps: Option<f64>,
    /// Video: playback speed, a multiple of real time as the window's speed control: one second
    /// of video shows X seconds of the motion [default: 0.25]. In the paper's units (a time unit
    /// of 0.04595 s) that is X / 0.04595 time units per second of video; in mm and s, X seconds
    #[arg(long, allow_negative_numbers = true, requires = "video", value_name = "X")]
    pub speed: Option<f64>,
    #[command(flatten)]
    pub film: FilmFlags,
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
    Ok(OrbitCamera {
        target: [0.0; 3],
        yaw: v[0],
        pitch: v[1].clamp(0.05, 1.52),
        distance: v[2] * r,
    })
}

/// The picture's or video's size: the flags, or the defaults of each.
fn size(args: &RenderArgs, default: [u32; 2]) -> Result<[u32; 2]> {
    let size = [args.width.unwrap_or(default[0]), args.height.unwrap_or(default[1])];
    for (v, flag) in [(size[0], "--width"), (size[1], "--height")] {
        if !(16..=8192).contains(&v) {
            bail!("{flag} = {v}: must be between 16 and 8192 pixels");
        }
    }
    Ok(size)
}

pub fn run(args: &RenderArgs) -> Result<()> {
    if args.view == View::Film {
        return run_film(args);
    }
    if let Some(flag) = args.film.first_given() {
        bail!("{flag} is for a film (--view film)");
    }
    match (&args.video, args.time, &args.out) {
        (Some(video), _, _) => run_video(args, video),
        (None, Some(time), Some(out)) => run_picture(args, time, out),
        // clap asks for --time and --out where --video is missing.
        _ => bail!("give --time and --out for a picture, or --video with --from and --to"),
    }
}

/// Second preset (--compare), loaded and built.
fn second_case(args: &RenderArgs) -> Result<Option<(String, CaseFile, Case)>> {
    let Some(name) = &args.compare else { return Ok(None) };
    let f = load_preset(name)?;
    let c = f.build().map_err(anyhow::Error::msg).with_context(|| format!("preset '{name}'"))?;
    Ok(Some((name.clone(), f, c)))
}

/// What draws the frames of the asked view. `until`: a video's end (seconds), where a fixed
/// camera looks at the middle of the path up to it.
fn frame_source(gpu: &Gpu, args: &RenderArgs, until: Option<f64>) -> Result<FrameSource> {
    let file = args.case.case_file()?;
    let case = args.case.case()?;
    let second = second_case(args)?;
    Ok(match args.view {
        View::ThreeD => {
            let r = case.model.body.r as f32;
            let (camera, aim) = match &args.camera {
                Some(s) => (parse_camera(s, r)?, Aim::PathMiddle(until)),
                None => (OrbitCamera::default_for(r), Aim::Follow),
            };
            let mut cases = vec![case];
            cases.extend(second.map(|s| s.2));
            FrameSource::three_d(gpu, cases, camera, aim, !args.no_contact)
        }
        View::Top => {
            let mut runs = vec![(file.name.clone(), case)];
            runs.extend(second.map(|s| (s.0, s.2)));
            FrameSource::top(gpu, runs, !args.no_contact)
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
            let mut app = RinglabApp::new(settings, Mode::Fixed { seconds: 0.0 });
            // A film (or a tracker's file) says nothing of the body: the case's is taken.
            app.recording.import_options.body = BodyMm::of_case(&file).ok();
            if let Some(path) = &args.recording {
                open_recording(&mut app, path, args.fit)?;
                if args.diagnose {
                    diagnose_recording(&mut app)?;
                }
            }
            FrameSource::app(gpu, app)
        }
        View::Film => bail!("--view film draws a film (--video) and no picture"),
    })
}

fn run_picture(args: &RenderArgs, time: f64, out: &Path) -> Result<()> {
    // clap lets these through beside --time (it conflicts with --video, which they need).
    for (given, flag) in [
        (args.from.is_some(), "--from"),
        (args.to.is_some(), "--to"),
        (args.fps.is_some(), "--fps"),
        (args.speed.is_some(), "--speed"),
    ] {
        if given {
            bail!("{flag} is for a video (--video OUT.gif|OUT.mp4), not a picture (--time, --out)");
        }
    }
    if !(time.is_finite() && time >= 0.0) {
        bail!("--time = {time}: must be a time at or after the start (0)");
    }
    let size = size(args, [1280, 720])?;
    if out.extension().and_then(|e| e.to_str()).map(|e| e.eq_ignore_ascii_case("png")) != Some(true)
    {
        bail!("--out {}: only PNG pictures are written (name the file .png)", out.display());
    }
    check_folder("--out", out)?;
    let gpu = Gpu::new()?;
    let mut source = frame_source(&gpu, args, None)?;
    let image = source.frame(&gpu, time, size)?;
    save_png(&image, out).with_context(|| format!("--out {}", out.display()))?;
    println!(
        "wrote {} ({}x{}, {} at t = {}, {})",
        out.display(),
        size[0],
        size[1],
        args.view.name(),
        time,
        gpu.adapter.name
    );
    Ok(())
}

fn run_video(args: &RenderArgs, path: &Path) -> Result<()> {
    let format = VideoFormat::of(path)
        .with_context(|| format!("--video {}: name the file .gif or .mp4", path.display()))?;
    let spec = VideoSpec {
        from: args.from.context("--video needs --from")?,
        to: args.to.context("--video needs --to")?,
        fps: args.fps.unwrap_or(25.0),
        speed: args.speed.unwrap_or(0.25),
    };
    spec.check(format).map_err(anyhow::Error::msg)?;
    let size = size(args, [640, 360])?;
    check_folder("--video", path)?;
    if format == VideoFormat::Mp4 && find_ffmpeg().is_none() {
        bail!("--video {}: {}", path.display(), ExportError::NoFfmpeg);
    }
    let gpu = Gpu::new()?;
    let case = args.case.case()?;
    let mut source = frame_source(&gpu, args, Some(spec.to * case.units.time_s))?;
    let frames = spec.frame_times(source.time_unit_s()).map_err(anyhow::Error::msg)?.len();
    let bar = super::progress::LateBar::new(super::progress::COUNT_TEMPLATE);
    let report = write_video(&gpu, &mut source, &spec, size, path, &mut |done, _| {
        bar.update(done as u64, frames as u64, "frames".into());
        true
    })
    .with_context(|| format!("--video {}", path.display()))?;
    bar.finish();
    let seconds = report.seconds;
    println!(
        "wrote {} ({} frames of {}x{}, {} to {} at {} frames/s and {}x real time: {:.1} s of video; {} at {:.1} kB; {:.1} s, {:.0} ms a frame, {})",
        path.display(),
        report.frames,
        size[0],
        size[1],
        spec.from,
        spec.to,
        spec.fps,
        spec.speed,
        report.frames as f64 / spec.fps,
        args.view.name(),
        report.bytes as f64 / 1000.0,
        seconds,
        1000.0 * seconds / report.frames.max(1) as f64,
        gpu.adapter.name
    );
    Ok(())
}

/// `--view film`: the flags of the other views are refused, then `render_film` runs.
fn run_film(args: &RenderArgs) -> Result<()> {
    for (given, flag) in [
        (args.speed.is_some(), "--speed"),
        (args.compare.is_some(), "--compare"),
        (args.camera.is_some(), "--camera"),
        (args.no_contact, "--no-contact"),
        (args.why, "--why"),
        (args.recording.is_some(), "--recording"),
    ] {
        if given {
            bail!("{flag} is not for a film (--view film): its camera and speed are a lab's");
        }
    }
    let Some(video) = &args.video else {
        bail!(
            "--view film needs --video FILM.mp4 (or a folder for PNG frames) with --from and --to"
        );
    };
    super::render_film::run(&FilmRequest {
        case: &args.case,
        video,
        from: args.from.context("--view film needs --from")?,
        to: args.to.context("--view film needs --to")?,
        fps: args.fps,
        size: size(args, FILM_SIZE)?,
        flags: &args.film,
    })
}

/// Opens `path` in the app (and fits it), as the window's menu and Fit button do.
fn open_recording(app: &mut RinglabApp, path: &Path, fit: bool) -> Result<()> {
    app.open_recording(path.to_path_buf());
    app.finish_recording_jobs();
    if let Some(e) = app.recording.error.take() {
        bail!("{e}");
    }
    if let Some(p) = app.recording.pending_import() {
        bail!("{}", p.error);
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
