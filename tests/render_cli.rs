//! `ringlab render`: a PNG of the asked size through the software adapter, and clear errors
//! (never a panic) for bad flags.

use std::process::{Command, Output};

fn ringlab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ringlab")).args(args).output().expect("runs the binary")
}

fn out_dir() -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("ringlab-render-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

#[test]
fn renders_each_view_at_the_asked_size() {
    let dir = out_dir();
    for (view, extra) in
        [("3d", vec![]), ("top", vec!["--compare", "paper-disk-drag"]), ("app", vec![])]
    {
        let path = dir.join(format!("{view}.png"));
        let mut args = vec![
            "render",
            "--time",
            "30",
            "--width",
            "400",
            "--height",
            "300",
            "--view",
            view,
            "--out",
            path.to_str().unwrap(),
        ];
        args.extend(extra);
        let out = ringlab(&args);
        assert!(out.status.success(), "{view}: {}", String::from_utf8_lossy(&out.stderr));
        let img = image::open(&path).expect("a PNG").to_rgba8();
        assert_eq!(img.dimensions(), (400, 300));
        // Not a blank picture: many distinct colours.
        let mut colours: Vec<[u8; 4]> = img.pixels().map(|p| p.0).collect();
        colours.sort_unstable();
        colours.dedup();
        assert!(colours.len() > 50, "{view}: only {} colours", colours.len());
    }
}

#[test]
fn bad_flags_are_named() {
    let dir = out_dir();
    let png = dir.join("x.png");
    let png = png.to_str().unwrap();
    for (args, needle) in [
        (vec!["render", "--time", "-1", "--out", png], "--time"),
        (vec!["render", "--time", "1", "--out", "x.jpg"], "PNG"),
        (vec!["render", "--time", "1", "--width", "5", "--out", png], "--width"),
        (vec!["render", "--time", "1", "--camera", "1,2", "--out", png], "--camera"),
        (vec!["render", "--time", "1", "--compare", "nosuch", "--out", png], "nosuch"),
        (vec!["render", "--time", "1", "--out", "/nonexistent-dir/x.png"], "does not exist"),
        (vec!["render", "--time", "1", "--view", "app", "--diagnose", "--out", png], "--recording"),
    ] {
        let out = ringlab(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
        assert!(err.contains(needle), "{args:?}: error does not mention '{needle}':\n{err}");
    }
}

#[test]
fn no_vulkan_driver_is_a_clear_error() {
    let dir = out_dir();
    let png = dir.join("none.png");
    let out = Command::new(env!("CARGO_BIN_EXE_ringlab"))
        .args(["render", "--time", "1", "--out", png.to_str().unwrap()])
        .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
        .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
        .output()
        .expect("runs the binary");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains("no Vulkan graphics adapter"), "{err}");
}

/// A film given as the app view's recording is tracked with the case's body (the film says
/// nothing of it) and drawn; before, the import dialog's question stopped it silently.
#[test]
fn a_film_is_drawn_with_the_cases_body() {
    if ringlab::film::source::find_program("ffmpeg").is_none() {
        assert!(std::env::var("CI").is_err(), "ffmpeg is not on PATH in CI");
        return;
    }
    let film = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/video/colours-none-mid.mp4");
    let path = out_dir().join("film.png");
    let out = ringlab(&[
        "render",
        "--view",
        "app",
        "--preset",
        "steel-ring",
        "--recording",
        film,
        "--time",
        "0.2",
        "--width",
        "800",
        "--height",
        "500",
        "--out",
        path.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(image::open(&path).expect("a PNG").to_rgba8().dimensions(), (800, 500));
}
