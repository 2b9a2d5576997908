//! `ringlab render --view film` checked end to end: a short film rendered now (lavapipe) whose
//! discs sit where its truth says, tracked by ringlab's tracker against that truth; and the
//! command's files and its bad flags.

mod common;

use common::{assert_fails_with, ringlab};
use ringlab::export::{FilmMarks, FilmSpec, plan_film, write_film};
use ringlab::film::{MarkStyle, TrackOptions, track};
use ringlab::recording::import::BodyMm;
use ringlab::recording::read_recording;
use ringlab::render::{Gpu, SceneRenderer};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

fn out_dir(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("ringlab-film-render-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn steel_ring() -> ringlab::config::Case {
    ringlab::config::load_preset("steel-ring").unwrap().build().unwrap()
}

/// 40 frames of 320x256 from 1.5 s: quick to draw in software.
fn spec(marks: FilmMarks) -> FilmSpec {
    FilmSpec {
        from: 1.5,
        to: 1.63,
        fps: 300.0,
        size: [320, 256],
        px_per_mm: Some(3.0),
        marks,
        mark_diameter_mm: 2.5,
        supersample: 3,
    }
}

/// The centroid of how far each pixel's `k`-th hue stands out, in a window round `at`.
fn hue_centroid(img: &image::RgbaImage, k: usize, at: [f64; 2]) -> [f64; 2] {
    let (mut sw, mut sx, mut sy) = (0.0, 0.0, 0.0);
    let (x0, y0) = (at[0].round() as i64, at[1].round() as i64);
    for y in y0 - 8..=y0 + 8 {
        for x in x0 - 8..=x0 + 8 {
            let p = img.get_pixel(x as u32, y as u32).0.map(f64::from);
            let (r, g, b) = (p[0], p[1], p[2]);
            let stand_out = match k {
                0 => r - g.max(b),
                1 => g - r.max(b),
                2 => b - r.max(g),
                _ => r.min(g) - b,
            };
            let w = (stand_out - 40.0).max(0.0);
            (sw, sx, sy) = (sw + w, sx + w * x as f64, sy + w * y as f64);
        }
    }
    [sx / sw, sy / sw]
}

#[test]
fn the_discs_are_drawn_where_the_truth_puts_them() {
    let gpu = Gpu::new().expect("a Vulkan adapter (lavapipe)");
    let plan = plan_film(&steel_ring(), &spec(FilmMarks::Colours)).expect("plan");
    let mut renderer = SceneRenderer::new(&gpu.device, None);
    let mut worst: f64 = 0.0;
    for n in [0, 13, 27, 39] {
        let img =
            ringlab::export::film_frames::film_frame(&gpu, &mut renderer, &plan, n).expect("frame");
        for (k, m) in plan.truth.frames[n].iter().enumerate() {
            let t = m.expect("every mark in the picture");
            let c = hue_centroid(&img, k, t);
            worst = worst.max((c[0] - t[0]).hypot(c[1] - t[1]));
        }
    }
    assert!(worst < 0.2, "a disc's centroid {worst:.3} px from its truth");
}

#[test]
fn a_film_rendered_now_is_tracked_against_its_truth() {
    let gpu = Gpu::new().expect("a Vulkan adapter (lavapipe)");
    let case = steel_ring();
    for (marks, style) in
        [(FilmMarks::Colours, MarkStyle::Colours), (FilmMarks::Dark, MarkStyle::Dark)]
    {
        let plan = plan_film(&case, &spec(marks)).expect("plan");
        let dir = out_dir(marks.name()).join("frames");
        write_film(&gpu, &plan, &dir, &mut |_, _| true).expect("film");
        let body = BodyMm {
            shape: ringlab::physics::Shape::Ring,
            outer_radius_mm: 20.66,
            width_mm: 18.0,
            thickness_mm: Some(1.0),
        };
        let opts = TrackOptions { fps: Some(300.0), ..TrackOptions::for_body(body) };
        let t = track(&dir, &opts, &mut |_, _| {}, &AtomicBool::new(false)).expect("tracks");
        assert_eq!(t.report.style, style);
        let (tracked, truth) = (&t.recording.frames, &plan.truth.frames);
        assert_eq!(tracked.len(), truth.len());
        // The best of the eight numberings (dots are numbered from any one).
        let (mut best_sq, mut best_found) = (f64::INFINITY, 0usize);
        for start in 0..4 {
            for dir in [1i64, -1] {
                let perm = |j: usize| (start as i64 + dir * j as i64).rem_euclid(4) as usize;
                let (mut sq, mut found) = (0.0, 0);
                for (f, g) in tracked.iter().zip(truth) {
                    for j in 0..4 {
                        if let (Some(a), Some(b)) = (f[perm(j)], g[j]) {
                            sq += (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
                            found += 1;
                        }
                    }
                }
                if found > 0 && sq / (found as f64) < best_sq {
                    (best_sq, best_found) = (sq / found as f64, found);
                }
            }
        }
        let rms = best_sq.sqrt();
        let visible = plan.truth.mark_count();
        assert!(rms < 0.7, "{}: rms {rms:.3} px", marks.name());
        assert!(
            best_found as f64 >= 0.98 * visible as f64,
            "{}: {best_found}/{visible}",
            marks.name()
        );
        let k = t.report.ring_scale.as_ref().expect("a scale").px_per_mm;
        assert!((k / 3.0 - 1.0).abs() < 0.01, "{}: scale {k}", marks.name());
    }
}

#[test]
fn the_command_writes_the_film_and_its_truth_and_refuses_bad_flags() {
    let dir = out_dir("cli");
    let (video, truth) = (dir.join("f"), dir.join("f.truth.csv"));
    let (v, t) = (video.to_str().expect("utf-8"), truth.to_str().expect("utf-8"));
    let out = ringlab(&[
        "render",
        "--view",
        "film",
        "--preset",
        "steel-ring",
        "--from",
        "1.5",
        "--to",
        "1.52",
        "--width",
        "160",
        "--height",
        "128",
        "--supersample",
        "1",
        "--video",
        v,
        "--truth",
        t,
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rec = read_recording(&truth).expect("the truth reads back");
    assert_eq!(rec.frames.len(), 7);
    assert_eq!(rec.first_frame, 450);
    assert_eq!(rec.header.fps, 300.0);
    assert_eq!(rec.header.image_width_px, Some(160.0));
    assert!(video.join("frame_000006.png").is_file());
    let g = dir.join("g");
    let g = g.to_str().expect("utf-8");
    let film = ["render", "--view", "film", "--preset", "steel-ring", "--from", "1.5", "--to"];
    for (extra, needle) in [
        (["--speed", "2"], "--speed is not for a film"),
        (["--mark-mm", "0"], "--mark-mm"),
        (["--px-per-mm", "0"], "--px-per-mm"),
        (["--supersample", "12"], "--supersample"),
    ] {
        let args: Vec<&str> =
            film.iter().copied().chain(["1.52", "--video", g]).chain(extra).collect();
        assert_fails_with(&args, &[needle]);
    }
    let p = dir.join("p.png");
    let p = p.to_str().expect("utf-8");
    assert_fails_with(
        &["render", "--time", "1", "--out", p, "--truth", t],
        &["--truth is for a film"],
    );
    let avi = dir.join("f.avi");
    let avi = avi.to_str().expect("utf-8");
    assert_fails_with(
        &["render", "--view", "film", "--from", "0", "--to", "1", "--video", avi],
        &["a film is an .mp4 file or a folder"],
    );
    assert!(!dir.join("g").exists(), "nothing written for a bad flag");
}
