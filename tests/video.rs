//! `ringlab render --video`: a GIF with the frames the span, the frame rate and the speed ask
//! for, frames that change as the ring moves and end where a picture at that time is; an MP4
//! through ffmpeg where it is installed (CI installs it); clear errors for bad flags and for a
//! missing ffmpeg.

mod common;

use common::{assert_fails_with, gif_frames, ringlab};
use std::path::PathBuf;
use std::process::Command;

fn out_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ringlab-video-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn time_unit_s() -> f64 {
    ringlab::config::load_preset("paper-ring").unwrap().build().unwrap().units.time_s
}

/// Pixels whose colour differs by more than `tol` in a channel.
fn differing(a: &image::RgbaImage, b: &image::RgbaImage, tol: u8) -> usize {
    a.pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0.iter()).any(|(x, y)| x.abs_diff(*y) > tol))
        .count()
}

#[test]
fn a_gif_has_the_frames_asked_for_and_they_change() {
    let dir = out_dir("gif");
    let gif = dir.join("run.gif");
    let (from, to, fps, speed) = (10.0, 30.0, 10.0, 0.25);
    let out = ringlab(&[
        "render",
        "--video",
        gif.to_str().unwrap(),
        "--from",
        "10",
        "--to",
        "30",
        "--fps",
        "10",
        "--speed",
        "0.25",
        "--width",
        "160",
        "--height",
        "90",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // One frame every speed / fps seconds of motion, from `from` up to `to`.
    let step = speed / fps / time_unit_s();
    let expected = ((to - from) / step + 1e-9).floor() as usize + 1;
    let frames = gif_frames(&gif);
    assert_eq!(frames.len(), expected);
    assert!(frames.iter().all(|f| f.dimensions() == (160, 90)));
    // The ring moves (and the camera follows it): every frame differs from the one before.
    for (k, w) in frames.windows(2).enumerate() {
        let d = differing(&w[0], &w[1], 8);
        assert!(d > 50, "frames {k} and {} differ in {d} pixels only", k + 1);
    }
    assert!(differing(&frames[0], &frames[frames.len() - 1], 8) > 160 * 90 / 4);
    // Each frame shows its time: the last one is the picture at that time, to the GIF's
    // 256 colours.
    let last_t = from + (expected - 1) as f64 * step;
    let png = dir.join("last.png");
    let out = ringlab(&[
        "render",
        "--time",
        &format!("{last_t}"),
        "--width",
        "160",
        "--height",
        "90",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let still = image::open(&png).unwrap().to_rgba8();
    let last = &frames[frames.len() - 1];
    let off = differing(last, &still, 24);
    assert!(off < 160 * 90 / 50, "the last frame is the picture at t = {last_t}: {off} pixels off");
    // 25 frames/s: a delay of 4 hundredths of a second each.
    let gif25 = dir.join("d.gif");
    let out = ringlab(&[
        "render",
        "--video",
        gif25.to_str().unwrap(),
        "--from",
        "0",
        "--to",
        "2",
        "--width",
        "32",
        "--height",
        "18",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let mut d = gif::DecodeOptions::new().read_info(std::fs::File::open(&gif25).unwrap()).unwrap();
    while let Some(f) = d.read_next_frame().unwrap() {
        assert_eq!(f.delay, 4);
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_top_and_app_views_make_gifs_too() {
    let dir = out_dir("views");
    for view in ["top", "app"] {
        let gif = dir.join(format!("{view}.gif"));
        let out = ringlab(&[
            "render",
            "--video",
            gif.to_str().unwrap(),
            "--view",
            view,
            "--from",
            "20",
            "--to",
            "24",
            "--fps",
            "10",
            "--speed",
            "0.25",
            "--width",
            "480",
            "--height",
            "300",
        ]);
        assert!(out.status.success(), "{view}: {}", String::from_utf8_lossy(&out.stderr));
        let frames = gif_frames(&gif);
        assert!(frames.len() > 5, "{view}: {} frames", frames.len());
        assert!(
            differing(&frames[0], &frames[frames.len() - 1], 8) > 100,
            "{view}: the path grows"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn an_mp4_through_ffmpeg() {
    if ringlab::export::mp4::find_ffmpeg().is_none() {
        // CI installs ffmpeg (.ci/run): there the MP4 must be made.
        assert!(std::env::var("CI").is_err(), "ffmpeg is not on PATH in CI");
        eprintln!("ffmpeg is not installed here: the MP4 is not tested");
        return;
    }
    let dir = out_dir("mp4");
    let mp4 = dir.join("run.mp4");
    // An odd size: padded by a pixel for H.264's colour format.
    let out = ringlab(&[
        "render",
        "--video",
        mp4.to_str().unwrap(),
        "--from",
        "0",
        "--to",
        "10",
        "--fps",
        "20",
        "--speed",
        "0.5",
        "--width",
        "161",
        "--height",
        "90",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let bytes = std::fs::read(&mp4).unwrap();
    assert_eq!(&bytes[4..8], b"ftyp", "an MP4 file");
    let expected = (10.0 * time_unit_s() * 20.0 / 0.5 + 1e-9).floor() as usize + 1;
    let probe = Command::new("ffprobe")
        .args([
            "-v",
            "error",
            "-count_frames",
            "-select_streams",
            "v:0",
            "-show_entries",
            "stream=nb_read_frames,width,height,codec_name",
            "-of",
            "csv=p=0",
        ])
        .arg(&mp4)
        .output()
        .expect("ffprobe comes with ffmpeg");
    assert!(probe.status.success(), "{}", String::from_utf8_lossy(&probe.stderr));
    let said = String::from_utf8_lossy(&probe.stdout).trim().to_string();
    assert_eq!(said, format!("h264,162,90,{expected}"), "codec, size, frames");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn no_ffmpeg_is_a_clear_error_and_a_gif_still_works() {
    let dir = out_dir("no-ffmpeg");
    let empty = dir.join("bin");
    std::fs::create_dir_all(&empty).unwrap();
    let run = |name: &str| {
        Command::new(env!("CARGO_BIN_EXE_ringlab"))
            .args([
                "render",
                "--video",
                dir.join(name).to_str().unwrap(),
                "--from",
                "0",
                "--to",
                "2",
                "--width",
                "32",
                "--height",
                "18",
            ])
            .env("PATH", &empty)
            .output()
            .unwrap()
    };
    let out = run("x.mp4");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(err.contains("ffmpeg was not found on PATH") && !err.contains("panicked"), "{err}");
    assert!(!dir.join("x.mp4").exists());
    let out = run("x.gif");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_video_flags_are_named() {
    let dir = out_dir("bad");
    let gif = dir.join("x.gif");
    let gif = gif.to_str().unwrap();
    assert_fails_with(
        &["render", "--video", "x.avi", "--from", "0", "--to", "1"],
        &["x.avi", ".gif or .mp4"],
    );
    assert_fails_with(&["render", "--video", gif, "--from", "5", "--to", "1"], &["--to"]);
    assert_fails_with(&["render", "--video", gif, "--from", "-1", "--to", "1"], &["--from"]);
    assert_fails_with(
        &["render", "--video", gif, "--from", "0", "--to", "1", "--fps", "0"],
        &["--fps"],
    );
    assert_fails_with(
        &["render", "--video", gif, "--from", "0", "--to", "1", "--fps", "60"],
        &["--fps", "GIF"],
    );
    assert_fails_with(
        &["render", "--video", gif, "--from", "0", "--to", "1", "--speed", "-2"],
        &["--speed"],
    );
    assert_fails_with(
        &["render", "--video", gif, "--from", "0", "--to", "1e9", "--speed", "0.05"],
        &["frames"],
    );
    assert_fails_with(&["render", "--video", gif, "--from", "0"], &["--to"]);
    assert_fails_with(
        &["render", "--video", "/nonexistent-dir/x.gif", "--from", "0", "--to", "1"],
        &["does not exist"],
    );
    assert_fails_with(
        &["render", "--time", "1", "--out", dir.join("x.png").to_str().unwrap(), "--fps", "10"],
        &["--fps", "video"],
    );
    assert_fails_with(
        &["render", "--video", gif, "--time", "1", "--from", "0", "--to", "1"],
        &["--time"],
    );
    std::fs::remove_dir_all(&dir).ok();
}
