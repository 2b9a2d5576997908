//! Films tracked (`film::track`): 240 frames (150 of the flickering one) from the middle of each
//! shared film (`tests/data/video/*-mid.mp4`, cut at a key frame from the films of a renderer
//! written apart from ringlab) and the opening of one (`colours-none-short.mp4`), against their
//! marks' true centres; a folder of frames, the scale from the ring, and every way a film can
//! be bad.
//! Needs ffmpeg and ffprobe on PATH (the README's test command installs them).

mod common;

use common::test_data;
use ringlab_core::film::{CameraGiven, FilmErrorKind, MarkStyle, TrackOptions, TrackedFilm, track};
use ringlab_core::physics::Shape;
use ringlab_core::recording::import::BodyMm;
use ringlab_core::recording::{FrameMarks, read_recording};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

fn steel_ring() -> BodyMm {
    BodyMm { shape: Shape::Ring, outer_radius_mm: 20.66, width_mm: 18.0, thickness_mm: Some(1.0) }
}

fn aluminium_disk() -> BodyMm {
    BodyMm { shape: Shape::Disk, outer_radius_mm: 31.75, width_mm: 6.14, thickness_mm: None }
}

fn options(body: BodyMm) -> TrackOptions {
    TrackOptions::for_body(body)
}

fn run(path: &Path, opts: &TrackOptions) -> Result<TrackedFilm, ringlab_core::film::FilmError> {
    track(path, opts, &mut |_, _| {}, &AtomicBool::new(false))
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ringlab-film-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// Tracked against true marks as `compare_tracks.py` judges them: the numbering (start and
/// direction round the ring) that fits best, then the RMS distance, the share of the visible
/// marks found, and the marks more than 3 px off (a swap puts a mark tens of px off).
struct Comparison {
    rms: f64,
    found: f64,
    far: usize,
    /// Marks more than 20 px off: taken on a look-alike.
    gross: usize,
    extra: usize,
    /// Frames whose marks fit another numbering within 3 px but not the film's own.
    swaps: usize,
}

fn compare(tracked: &[FrameMarks], truth: &[FrameMarks]) -> Comparison {
    let n = tracked.len().min(truth.len());
    let labellings: Vec<[usize; 4]> = (0..4)
        .flat_map(|r| {
            [1i64, -1]
                .map(|d| std::array::from_fn(|i| (r as i64 + d * i as i64).rem_euclid(4) as usize))
        })
        .collect();
    let errors = |perm: &[usize; 4]| -> Vec<f64> {
        (0..n)
            .flat_map(|i| {
                (0..4).filter_map(move |j| {
                    let (t, m) = (truth[i][j]?, tracked[i][perm[j]]?);
                    Some((t[0] - m[0]).hypot(t[1] - m[1]))
                })
            })
            .collect()
    };
    let median = |mut e: Vec<f64>| {
        e.sort_by(|a, b| a.total_cmp(b));
        e.get(e.len() / 2).copied().unwrap_or(f64::INFINITY)
    };
    let best = labellings
        .iter()
        .min_by(|a, b| median(errors(a)).total_cmp(&median(errors(b))))
        .expect("labellings");
    let e = errors(best);
    let visible: usize = truth[..n].iter().map(|f| f.iter().flatten().count()).sum();
    let extra = (0..n)
        .map(|i| (0..4).filter(|&j| truth[i][j].is_none() && tracked[i][best[j]].is_some()).count())
        .sum();
    let within = |i: usize, perm: &[usize; 4]| {
        let e: Vec<f64> = (0..4)
            .filter_map(|j| {
                let (t, m) = (truth[i][j]?, tracked[i][perm[j]]?);
                Some((t[0] - m[0]).hypot(t[1] - m[1]))
            })
            .collect();
        !e.is_empty() && e.iter().all(|&x| x <= 3.0)
    };
    let swaps = (0..n)
        .filter(|&i| !within(i, best) && labellings.iter().any(|p| p != best && within(i, p)))
        .count();
    Comparison {
        swaps,
        rms: (e.iter().map(|x| x * x).sum::<f64>() / e.len() as f64).sqrt(),
        found: e.len() as f64 / visible as f64,
        far: e.iter().filter(|&&x| x > 3.0).count(),
        gross: e.iter().filter(|&&x| x > 20.0).count(),
        extra,
    }
}

/// Marks more than 3 px off allowed: none in a short stretch; a swap puts every later mark off.
fn max_far(_frames: usize) -> usize {
    0
}

fn check_film(name: &str, body: BodyMm, max_rms: f64) -> TrackedFilm {
    let t = run(&test_data(&format!("video/{name}.mp4")), &options(body)).expect("tracks");
    let truth = read_recording(&test_data(&format!("video/{name}.truth.csv"))).expect("truth");
    let c = compare(&t.recording.frames, &truth.frames);
    assert!(c.rms < max_rms, "{name}: rms {:.3} px", c.rms);
    assert!(c.found >= 0.98, "{name}: found {:.1}%", 100.0 * c.found);
    assert!(
        c.far <= max_far(t.recording.frames.len()),
        "{name}: {} marks more than 3 px off (a swap?)",
        c.far
    );
    assert_eq!(c.extra, 0, "{name}: marks reported where the rim hides them");
    assert_eq!(t.recording.frames.len(), truth.frames.len(), "{name}: every frame");
    t
}

#[test]
fn coloured_marks_are_tracked_within_the_goal_and_named_by_their_hue() {
    let t = check_film("colours-none-mid", steel_ring(), 0.7);
    assert_eq!(t.report.style, MarkStyle::Colours);
    assert_eq!(t.recording.header.fps, 300.0);
    assert_eq!(t.recording.header.image_width_px, Some(1280.0));
    let from =
        t.recording.header.extra.iter().find(|(k, _)| k == "tracked_from").map(|(_, v)| v.as_str());
    assert_eq!(from, Some("colours-none-mid.mp4"));
}

/// The first frames, where the ring spins fastest and stands nearly on edge, smear a mark
/// along the rim: the opening is looser than the film as a whole.
#[test]
fn the_opening_of_a_film_is_tracked_from_its_first_frame() {
    let t =
        run(&test_data("video/colours-none-short.mp4"), &options(steel_ring())).expect("tracks");
    let truth = read_recording(&test_data("video/colours-none-short.truth.csv")).expect("truth");
    let c = compare(&t.recording.frames, &truth.frames);
    assert_eq!(t.report.acquired_at, 0);
    assert!(
        c.rms < 1.0 && c.found >= 0.98 && c.extra == 0,
        "rms {:.3}, found {:.3}",
        c.rms,
        c.found
    );
    // Off by more than 3 px only in the first few frames, never after.
    let late: Vec<FrameMarks> = t.recording.frames[10..].to_vec();
    assert_eq!(compare(&late, &truth.frames[10..]).far, 0);
}

/// A phone's film: `colours-none` at 2 px per mm, 240 frames/s, crf 28 (`make-phone.sh`),
/// where a coloured mark is about one chroma sample. The goal is 1.4 px and 98% found: the
/// RMS is met; the share found (`docs/film.md`) is not, and is held where it stands. A
/// weak mark whose hue the codec loses is left behind on the table's grain for frames on end:
/// the ellipse of the frame before tells it (`phase`), without which this cut gives 1.35 px;
/// and a chroma centre the film showed to err more than the brightness's is left out where
/// the brightness centre cannot be had (1.222 px and 92.8% found with it kept).
#[test]
fn small_strongly_compressed_colours_are_placed_on_the_brightness() {
    let t =
        run(&test_data("video/colours-none-phone.mp4"), &options(steel_ring())).expect("tracks");
    let truth = read_recording(&test_data("video/colours-none-phone.truth.csv")).expect("truth");
    assert_eq!(t.report.style, MarkStyle::Colours);
    check_colours_phone(&t, &truth.frames);
}

/// The whole of `colours-none` as a phone films it (crf 28, 1813 frames), its opening too, where
/// the ring stands on edge and spins fast and a mark is a faint smear of chroma. A mark looked
/// for round the whole ring took look-alikes there (2.124 px, 12 marks more than 20 px off):
/// now it must have a close hue, lie off another mark's fringe and keep the figure within the
/// ring's size, frames whose marks are not of the ring's size are left out (`spread`), and so
/// are marks whose hue strays from the mark's over the film (`stray_hue`: the opening's
/// look-alikes and blurs, 1.559 px before), and frames of one or two marks where the ring is
/// mostly lost (`few`: spots of stale colour, 1.402 px before). The goal is 1.4 px (0.887 px
/// now, none more than 20 px off).
#[test]
fn a_whole_phone_film_keeps_look_alikes_out_of_its_opening() {
    let t = run(&test_data("video/colours-none-phone-whole.mp4"), &options(steel_ring()))
        .expect("tracks");
    let truth =
        read_recording(&test_data("video/colours-none-phone-whole.truth.csv")).expect("truth");
    let c = compare(&t.recording.frames, &truth.frames);
    assert!(c.rms <= 1.0, "rms {:.3} px", c.rms);
    assert!(c.gross <= 1, "{} marks more than 20 px off", c.gross);
    assert!(c.found >= 0.85, "found {:.1}%", 100.0 * c.found);
    assert_eq!((c.swaps, c.extra), (0, 0), "swaps, marks where the rim hides them");
    let r = &t.report;
    assert!(r.left_out_by("spread") > 0 && r.left_out_by("stray_hue") > 0);
    assert!(r.left_out_by("few") > 0);
    assert!(r.notes.iter().any(|n| n.contains("wider or narrower than the ring")));
    assert!(r.notes.iter().any(|n| n.contains("hue strayed")));
    assert!(r.notes.iter().any(|n| n.contains("where the ring was mostly lost")));
}

/// The colour phone cut's goal, held where it stands: within 1.15 px, 87% found, no swap
/// (1.127 px, 89.1% found; 87.5% upright: its rows and columns fall otherwise on the codec's
/// blocks).
fn check_colours_phone(t: &TrackedFilm, truth: &[FrameMarks]) {
    let c = compare(&t.recording.frames, truth);
    assert!(c.rms <= 1.15, "rms {:.3} px", c.rms);
    assert!(c.found >= 0.87, "found {:.1}%", 100.0 * c.found);
    assert_eq!((c.swaps, c.extra), (0, 0), "swaps, marks where the rim hides them");
}

/// A phone held upright stores its frames on their side with a rotation to show them by,
/// which ffmpeg applies as it decodes (`make-phone.sh --test-cut`: the cut above, tagged a
/// quarter turn). The film is tracked as it is shown: its frames 608 wide and 760 high, a
/// mark at (x, y) of the stored frame at (y, 759 - x). It was read as 760x608 before, every
/// frame garbled (10% of the marks found, all of them off).
#[test]
fn a_film_from_a_phone_held_upright_is_tracked_as_it_is_shown() {
    let t = run(&test_data("video/colours-none-phone-upright.mp4"), &options(steel_ring()))
        .expect("tracks");
    assert_eq!((t.report.width_px, t.report.height_px), (608, 760));
    assert_eq!(t.recording.header.image_width_px, Some(608.0));
    let mut truth =
        read_recording(&test_data("video/colours-none-phone.truth.csv")).expect("truth");
    for p in truth.frames.iter_mut().flatten().flatten() {
        *p = [p[1], 759.0 - p[0]];
    }
    check_colours_phone(&t, &truth.frames);
}

/// A film whose frame rate varies (`make-phone.sh --test-cut`: the disk's cut with frames
/// 100-119 never taken, their time left in its timestamps): the frames are placed at their
/// times at the nominal 240 frames/s, the untaken ones empty rows, and the report says so.
/// Read as a steady film of 516 frames at 231 frames/s, every frame after the gap was 20
/// frames early.
#[test]
fn a_film_whose_frame_rate_varies_keeps_each_frame_at_its_time() {
    let t = run(&test_data("video/disk-dark-none-phone-vfr.mp4"), &options(aluminium_disk()))
        .expect("tracks");
    let truth = read_recording(&test_data("video/disk-dark-none-phone.truth.csv")).expect("truth");
    assert_eq!(t.recording.frames.len(), truth.frames.len());
    assert_eq!(t.recording.header.fps, 240.0);
    assert!(
        t.report.notes.iter().any(|n| n.contains("leave 20 of its frames")),
        "{:?}",
        t.report.notes
    );
    assert!(t.recording.frames[100..120].iter().flatten().all(Option::is_none));
    let mut visible = truth.frames.clone();
    visible[100..120].fill([None; 4]);
    let c = compare(&t.recording.frames, &visible);
    assert!(c.rms <= 1.4, "rms {:.3} px", c.rms);
    assert_eq!((c.far, c.swaps, c.extra), (0, 0, 0), "far, swaps, marks where none was taken");
    let after = compare(&t.recording.frames[120..], &visible[120..]);
    assert!(after.found >= 0.98, "found after the gap {:.1}%", 100.0 * after.found);
}

/// A disk's dots at 2 px per mm and crf 28 (`make-phone.sh --test-cut`): with no scale given,
/// four specks of noise sit as marks do in its first frames; the ring must still be acquired
/// and its scale measured from the marks.
#[test]
fn small_strongly_compressed_dots_give_their_scale_from_the_ring() {
    let t = run(&test_data("video/disk-dark-none-phone.mp4"), &options(aluminium_disk()))
        .expect("tracks with no scale given");
    let truth = read_recording(&test_data("video/disk-dark-none-phone.truth.csv")).expect("truth");
    let c = compare(&t.recording.frames, &truth.frames);
    assert!(c.rms <= 1.4, "rms {:.3} px", c.rms);
    assert!(c.found >= 0.98, "found {:.1}%", 100.0 * c.found);
    assert_eq!((c.swaps, c.extra), (0, 0), "swaps, marks where the rim hides them");
    let s = t.report.ring_scale.as_ref().expect("a scale");
    let k = truth.header.px_per_mm;
    assert!((s.px_per_mm / k - 1.0).abs() < 0.02, "{} against {k}", s.px_per_mm);
    assert!((s.px_per_mm - k).abs() < 3.0 * s.sigma, "{} +- {} against {k}", s.px_per_mm, s.sigma);
}

/// A hand before the lens for a quarter of a second (`make-phone.sh --test-cut`: the near
/// camera's dots at 2 px per mm, crf 28, frames 300-359 grey): the ring turns 1.4 rad
/// meanwhile, and four alike dots found again could be numbered four ways. The ring's turning
/// across the loss numbers them as before (`join`); without it they were left unfound.
#[test]
fn dots_found_again_after_the_ring_was_hidden_are_numbered_as_before() {
    let name = "dark-perspective-phone-covered";
    let t = run(&test_data(&format!("video/{name}.mp4")), &options(steel_ring())).expect("tracks");
    let truth = read_recording(&test_data(&format!("video/{name}.truth.csv"))).expect("truth");
    let c = compare(&t.recording.frames, &truth.frames);
    assert!(c.rms <= 1.4, "rms {:.3} px", c.rms);
    assert!(c.found >= 0.98, "found {:.1}%", 100.0 * c.found);
    assert_eq!((c.far, c.swaps, c.extra), (0, 0, 0), "far, swaps, marks where none is seen");
    let join = t.report.stage("join").expect("the join stage ran");
    assert_eq!((join.renumbered, join.left_out), (1, 0));
    // The same numbering after the loss as before it, to the frame.
    let after: Vec<FrameMarks> = t.recording.frames[360..].to_vec();
    assert_eq!(compare(&after, &truth.frames[360..]).far, 0);
}

/// Phones' films at 2 px per mm and crf 28 (`make-phone.sh --test-cut`). Far away, the marks'
/// errors, shared by frames on end, can make their scale grow with their height as a near
/// camera's does; the camera that growth implies does not close the marks' figure better than
/// a far one, so the camera is far and the scale the marks' own (it was written 9-19% low).
/// Through the near camera at the same quality the figure closes, and the camera stays near.
/// (`colours-none-phone-long` faked the growth too until its weak marks' chroma centres alone
/// were left out; it is checked for its scale only.)
#[test]
fn a_far_phones_compressed_film_is_not_taken_for_a_near_camera() {
    let far =
        run(&test_data("video/colours-reynolds-flicker-phone-long.mp4"), &options(steel_ring()))
            .expect("tracks");
    let truth = read_recording(&test_data("video/colours-reynolds-flicker-phone-long.truth.csv"))
        .expect("truth");
    let s = far.report.ring_scale.as_ref().expect("a scale");
    assert!(s.grows_with_height(), "the growth this film fakes: {s:?}");
    let (near_px, far_px) = s.figure_px.expect("the figure checked");
    assert!(near_px > 0.8 * far_px, "{near_px} px near, {far_px} px far");
    assert!(!s.camera_is_near() && s.table.is_none(), "{s:?}");
    let k = truth.header.px_per_mm;
    assert!((far.report.px_per_mm / k - 1.0).abs() < 0.01, "{} against {k}", far.report.px_per_mm);
    assert!(far.report.notes.iter().any(|n| n.contains("taken as far")), "{:?}", far.report.notes);

    let other = run(&test_data("video/colours-none-phone-long.mp4"), &options(steel_ring()))
        .expect("tracks");
    let truth =
        read_recording(&test_data("video/colours-none-phone-long.truth.csv")).expect("truth");
    let s = other.report.ring_scale.as_ref().expect("a scale");
    assert!(!s.camera_is_near() && s.table.is_none(), "{s:?}");
    let (got, k) = (other.report.px_per_mm, truth.header.px_per_mm);
    assert!((got / k - 1.0).abs() < 0.01, "{got} against {k}");

    let near = run(&test_data("video/dark-perspective-phone.mp4"), &options(steel_ring()))
        .expect("tracks");
    let s = near.report.ring_scale.as_ref().expect("a scale");
    let (near_px, far_px) = s.figure_px.expect("the figure checked");
    assert!(near_px < 0.6 * far_px, "{near_px} px near, {far_px} px far");
    assert!(s.camera_is_near() && s.table.is_some(), "{s:?}");
}

#[test]
fn dark_dots_seen_by_a_near_tilted_camera_are_tracked_within_the_goal() {
    let t = check_film("dark-perspective-mid", steel_ring(), 0.7);
    assert_eq!(t.report.style, MarkStyle::Dark);
}

#[test]
fn blurred_flickering_colours_are_tracked_within_the_goal() {
    check_film("colours-reynolds-flicker-mid", steel_ring(), 0.7);
}

#[test]
fn dots_on_a_disk_are_tracked_within_the_goal() {
    check_film("disk-dark-none-mid", aluminium_disk(), 0.7);
}

/// Films made by ringlab's own renderer (`ringlab render --view film`, the commands in
/// docs/film.md): 119 frames of 640x512, coloured marks and dark dots, with their exact truth.
#[test]
fn films_of_ringlabs_own_renderer_are_tracked_within_the_goal_with_their_scale() {
    // Bright dots on the bright rim: the dark finder finds a four in each frame (the rim's
    // shade) and the colour finder one in a frame; the style is still told (`style`).
    for (name, style) in [
        ("rendered-colours", MarkStyle::Colours),
        ("rendered-dark", MarkStyle::Dark),
        ("rendered-bright", MarkStyle::Bright),
    ] {
        let t = check_film(name, steel_ring(), 0.7);
        assert_eq!(t.report.style, style, "{name}");
        let truth = read_recording(&test_data(&format!("video/{name}.truth.csv"))).expect("truth");
        let s = t.report.ring_scale.as_ref().expect("a scale");
        let k = truth.header.px_per_mm;
        assert!((s.px_per_mm / k - 1.0).abs() < 0.01, "{name}: {} against {k}", s.px_per_mm);
        assert!(s.table.is_none(), "{name}: a far camera");
    }
}

#[test]
fn the_scale_from_the_ring_is_within_a_percent_for_a_far_camera() {
    for (name, body, truth) in [
        ("colours-none-mid", steel_ring(), 3.364764),
        ("disk-dark-none-mid", aluminium_disk(), 5.0),
    ] {
        let t = run(&test_data(&format!("video/{name}.mp4")), &options(body)).expect("tracks");
        let s = t.report.ring_scale.as_ref().expect("a scale");
        assert!(
            (s.px_per_mm / truth - 1.0).abs() < 0.01,
            "{name}: {} against {truth}",
            s.px_per_mm
        );
        assert!(s.table.is_none(), "{name}: a far camera");
        assert_eq!(t.recording.header.px_per_mm, s.px_per_mm);
        let sigma = t.report.tracker_sigma_px.expect("the marks' parallelogram checks the error");
        assert!(sigma > 0.05 && sigma < 0.5, "{name}: {sigma}");
    }
}

#[test]
fn a_near_camera_is_told_and_its_table_scale_fitted_with_its_distance() {
    let t =
        run(&test_data("video/dark-perspective-mid.mp4"), &options(steel_ring())).expect("tracks");
    let s = t.report.ring_scale.as_ref().expect("a scale");
    assert!(s.camera_is_near(), "{s:?}");
    // The marks ride 18-27 mm above the table, 400 mm below the camera: 5-7% magnified.
    assert!(s.px_per_mm / 3.364764 > 1.04, "{s:?}");
    let table = s.table.expect("the table's scale fitted");
    assert!(
        (table.px_per_mm / 3.364764 - 1.0).abs() < 3.0 * table.sigma / 3.364764 + 0.01,
        "{table:?}"
    );
    assert_eq!(t.recording.header.px_per_mm, table.px_per_mm);
    // 240 frames place the pinhole too loosely (the table's scale +-7%) for the marks'
    // figure to check the centres' error: none is claimed.
    assert!(table.sigma > 0.02 * table.px_per_mm, "{table:?}");
    assert_eq!(t.report.tracker_sigma_px, None);
}

/// The film's first two seconds place the pinhole within a percent: each frame's pose of the
/// marks' circle through it reads the centres' error, which the truth confirms.
#[test]
fn a_near_camera_placed_well_checks_the_centres_error_through_its_pinhole() {
    let t = run(&test_data("video/dark-perspective-start.mp4"), &options(steel_ring()))
        .expect("tracks");
    let truth =
        read_recording(&test_data("video/dark-perspective-start.truth.csv")).expect("truth");
    let c = compare(&t.recording.frames, &truth.frames);
    assert!(c.rms < 0.7 && c.found >= 0.98 && c.extra == 0, "{:.3} px, {:.3}", c.rms, c.found);
    // As every opening, looser in its first frames (the ring on edge, spinning fastest).
    assert_eq!(compare(&t.recording.frames[10..], &truth.frames[10..]).far, 0);
    let table = t.report.ring_scale.as_ref().and_then(|s| s.table).expect("a near camera");
    assert!((table.px_per_mm / 3.364764 - 1.0).abs() < 0.02, "{table:?}");
    let per_coordinate = c.rms / 2f64.sqrt();
    let sigma = t.report.tracker_sigma_px.expect("the pose through the pinhole checks the error");
    assert!(
        (sigma / per_coordinate - 1.0).abs() < 0.2,
        "{sigma} px said against {per_coordinate} px"
    );
}

#[test]
fn a_given_scale_is_written_and_checked_against_the_ring() {
    let mut o = options(steel_ring());
    o.px_per_mm = Some(3.0);
    let t = run(&test_data("video/colours-none-short.mp4"), &o).expect("tracks");
    assert_eq!(t.recording.header.px_per_mm, 3.0);
    assert!(
        t.report.notes.iter().any(|n| n.contains("from the --px-per-mm given")),
        "{:?}",
        t.report.notes
    );
}

fn ffmpeg(args: &[&str]) {
    let ok = std::process::Command::new("ffmpeg")
        .args(["-v", "error", "-y"])
        .args(args)
        .status()
        .expect("ffmpeg runs")
        .success();
    assert!(ok, "ffmpeg {args:?}");
}

#[test]
fn a_folder_of_frames_tracks_as_the_video_does() {
    let d = temp_dir("folder");
    let film = test_data("video/colours-none-mid.mp4");
    let pattern = d.join("frame_%d.png");
    ffmpeg(&[
        "-i",
        film.to_str().expect("utf-8"),
        "-frames:v",
        "40",
        pattern.to_str().expect("utf-8"),
    ]);
    // Without a frame rate a folder says nothing of time.
    let e = run(&d, &options(steel_ring())).expect_err("no fps");
    assert!(matches!(e.kind, FilmErrorKind::NeedsFps), "{e}");
    let mut o = options(steel_ring());
    o.fps = Some(300.0);
    o.px_per_mm = Some(3.364764);
    let t = run(&d, &o).expect("tracks");
    assert_eq!(t.recording.frames.len(), 40, "frame_10 after frame_9");
    let truth = read_recording(&test_data("video/colours-none-mid.truth.csv")).expect("truth");
    let c = compare(&t.recording.frames, &truth.frames[..40]);
    // Frames as RGB give each chroma sample from its 2x2 block again, as the encoder did.
    assert!(c.rms < 0.7 && c.found >= 0.98 && c.far == 0, "rms {:.3}, found {:.3}", c.rms, c.found);
}

#[test]
fn frames_from_to_and_a_region_of_interest_are_kept_to() {
    let mut o = options(steel_ring());
    o.from_frame = 100;
    o.to_frame = Some(159);
    let t = run(&test_data("video/colours-none-short.mp4"), &o).expect("tracks");
    assert_eq!(t.recording.first_frame, 100);
    assert_eq!(t.recording.frames.len(), 60);
    // A region far from the ring: nothing to find there.
    let mut o = options(steel_ring());
    o.roi = Some(ringlab_core::film::Roi { x: 1000.0, y: 800.0, width: 200.0, height: 200.0 });
    let e = run(&test_data("video/colours-none-short.mp4"), &o).expect_err("no marks there");
    assert!(matches!(e.kind, FilmErrorKind::NoMarks { .. }), "{e}");
}

#[test]
fn bad_films_are_errors_that_name_the_file_and_what_is_wrong() {
    let d = temp_dir("bad");
    // Not a video.
    let text = d.join("notes.mp4");
    std::fs::write(&text, "these are not frames").expect("writes");
    let e = run(&text, &options(steel_ring())).expect_err("not a video");
    assert!(matches!(e.kind, FilmErrorKind::NotAVideo(_)), "{e}");
    assert!(e.to_string().contains("notes.mp4"), "{e}");
    // A folder without frames.
    let empty = d.join("empty");
    std::fs::create_dir_all(&empty).expect("dir");
    std::fs::write(empty.join("readme.txt"), "no frames").expect("writes");
    let e = run(&empty, &options(steel_ring())).expect_err("no frames");
    assert!(matches!(e.kind, FilmErrorKind::NoFrames), "{e}");
    // A film cut off mid-stream: its header announces more frames than it holds.
    let whole = std::fs::read(test_data("video/colours-none-short.mp4")).expect("reads");
    let cut = d.join("cut.mp4");
    std::fs::write(&cut, &whole[..whole.len() * 2 / 3]).expect("writes");
    let e = run(&cut, &options(steel_ring())).expect_err("cut off");
    assert!(matches!(e.kind, FilmErrorKind::CutOff { .. } | FilmErrorKind::NotAVideo(_)), "{e}");
    assert!(e.to_string().contains("cut.mp4"), "{e}");
    // No marks in the first frames: a plain grey film.
    let grey = d.join("grey.mp4");
    ffmpeg(&[
        "-f",
        "lavfi",
        "-i",
        "color=c=gray:s=320x240:r=30:d=3",
        "-pix_fmt",
        "yuv420p",
        grey.to_str().expect("utf-8"),
    ]);
    let e = run(&grey, &options(steel_ring())).expect_err("no marks");
    assert!(matches!(e.kind, FilmErrorKind::NoMarks { .. }), "{e}");
    // Fewer than two usable frames.
    let mut o = options(steel_ring());
    o.to_frame = Some(0);
    let e = run(&test_data("video/colours-none-short.mp4"), &o).expect_err("one frame");
    assert!(matches!(e.kind, FilmErrorKind::TooFewUsable { usable: 1 }), "{e}");
    // A start beyond the end.
    let mut o = options(steel_ring());
    o.from_frame = 5000;
    let e = run(&test_data("video/colours-none-short.mp4"), &o).expect_err("beyond");
    assert!(matches!(e.kind, FilmErrorKind::StartBeyondEnd { .. }), "{e}");
}

#[test]
fn a_cancel_ends_the_tracking_with_nothing() {
    let e = track(
        &test_data("video/colours-none-short.mp4"),
        &options(steel_ring()),
        &mut |_, _| {},
        &AtomicBool::new(true),
    )
    .expect_err("cancelled");
    assert!(matches!(e.kind, FilmErrorKind::Cancelled), "{e}");
}

/// The rule that numbers dots again after a loss (`join`), tried on the test films' true
/// marks with 0.3 px of noise: losses of 3 to 80 frames anywhere in each, the marks after a
/// loss numbered from each of the four. A shift it settles must be the true one; it must
/// settle most of them.
#[test]
fn the_turning_numbers_dots_across_losses_and_never_wrongly() {
    use ringlab_core::film::stages::join::{phase, settle};
    use ringlab_core::film::tuning::JoinTuning;
    let mut seed = 12345u64;
    let mut noise = move || {
        // A sum of four uniforms: near normal, 0.3 px standard deviation.
        (0..4)
            .map(|_| {
                seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            })
            .sum::<f64>()
            * 0.3
            * 3f64.sqrt()
    };
    let (mut tried, mut settled) = (0, 0);
    for name in [
        "colours-none-mid",
        "dark-perspective-start",
        "disk-dark-none-mid",
        "dark-perspective-phone",
    ] {
        let truth = read_recording(&test_data(&format!("video/{name}.truth.csv"))).expect("truth");
        let n = truth.frames.len();
        let phases = |from: usize, to: usize, rotate: usize, noise: &mut dyn FnMut() -> f64| {
            let mut out: Vec<(f64, f64)> = Vec::new();
            for i in from..to {
                let mut m = truth.frames[i];
                for p in m.iter_mut().flatten() {
                    *p = [p[0] + noise(), p[1] + noise()];
                }
                m.rotate_left(rotate);
                if let Some(a) = phase(&m) {
                    let a = out.last().map_or(a, |&(_, b)| {
                        b + (a - b + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                            - std::f64::consts::PI
                    });
                    out.push((i as f64, a));
                }
            }
            out
        };
        for gap in [3, 5, 10, 20, 40, 80] {
            for t0 in (16..n.saturating_sub(gap + 16)).step_by(23) {
                let rotate = (t0 / 23) % 4;
                let before = phases(t0 - 16, t0, 0, &mut noise);
                let after = phases(t0 + gap, t0 + gap + 16, rotate, &mut noise);
                tried += 1;
                if let Some(k) = settle(&before, &after, &JoinTuning::default()) {
                    settled += 1;
                    // Numbered from mark `rotate + 1`, the phase is `rotate` quarters ahead.
                    assert_eq!(
                        k.rem_euclid(4) as usize,
                        (4 - rotate) % 4,
                        "{name}: loss of {gap} frames after frame {t0}, numbered from mark {}",
                        rotate + 1
                    );
                }
            }
        }
    }
    assert!(settled * 2 > tried, "settled {settled} of {tried}");
}

/// A camera on a tripod beside the table (`colours-tripod-30-mid`: 600 frames of the shared
/// film, a pinhole 550 mm from the table tilted 30 degrees towards the image's bottom edge):
/// its distance, its tilt and the table's scale are measured from the ring and written in the
/// header, and the marks tracked within the goal.
#[test]
fn a_tripods_camera_is_measured_from_the_ring_and_written_in_the_header() {
    let t = check_film("colours-tripod-30-mid", steel_ring(), 0.7);
    let c = t.report.camera.expect("a camera fitted");
    assert!(c.is_tripod(), "{c:?}");
    // The tracked centres' own bias (a third of a pixel that turns with the ring) pulls the
    // camera away and up (docs/film.md): its true centres fix it within a few mm and a tenth
    // of a degree (below), the tracked ones within 20% and 3.5 degrees.
    let d = c.distance_mm.expect("a near camera");
    assert!((d / 550.0 - 1.0).abs() < 0.2 && c.distance_sigma_mm < 40.0, "{c:?}");
    assert!((c.tilt_deg - 30.0).abs() < 3.5 && c.tilt_sigma_deg < 1.5, "{c:?}");
    let h = &t.recording.header;
    assert!((h.px_per_mm / 3.364764 - 1.0).abs() < 0.01, "{}", h.px_per_mm);
    assert_eq!(h.camera_distance_mm, Some(d));
    assert_eq!(h.camera_tilt_deg, Some(c.tilt_deg));
    let from = h.extra.iter().find(|(k, _)| k == "px_per_mm_from").expect("px_per_mm_from");
    assert!(from.1.starts_with("ring through a near camera fitted from it"), "{from:?}");
    // Through the camera the marks' figure closes to the centres' error; looked at straight
    // down it cannot.
    assert!(c.figure_px < 0.5 * c.far_figure_px, "{c:?}");
    let sigma = t.report.tracker_sigma_px.expect("the error checked through the camera");
    assert!(sigma > 0.05 && sigma < 0.6, "{sigma}");
}

/// The camera given by flags is held, and the table's scale measured through it.
#[test]
fn a_camera_given_is_held_and_the_scale_measured_through_it() {
    let opts = TrackOptions {
        camera: CameraGiven { distance_mm: Some(550.0), tilt_deg: Some(30.0) },
        ..options(steel_ring())
    };
    let t = run(&test_data("video/colours-tripod-30-mid.mp4"), &opts).expect("tracks");
    let c = t.report.camera.expect("a camera");
    assert_eq!((c.distance_mm, c.tilt_deg), (Some(550.0), 30.0));
    let h = &t.recording.header;
    assert!((h.px_per_mm / 3.364764 - 1.0).abs() < 0.01, "{}", h.px_per_mm);
    assert_eq!((h.camera_distance_mm, h.camera_tilt_deg), (Some(550.0), Some(30.0)));
    let from = h.extra.iter().find(|(k, _)| k == "px_per_mm_from").expect("px_per_mm_from");
    assert!(from.1.starts_with("ring through the camera given"), "{from:?}");
    // A camera that cannot be is refused before the film is read.
    for (distance_mm, tilt_deg, said) in [
        (Some(-5.0), None, "--camera-distance-mm -5"),
        (Some(40.0), None, "more than the ring's"),
        (None, Some(80.0), "--camera-tilt-deg 80"),
        (None, Some(f64::NAN), "within (-80, 80)"),
    ] {
        let opts =
            TrackOptions { camera: CameraGiven { distance_mm, tilt_deg }, ..options(steel_ring()) };
        let e = run(&test_data("video/colours-tripod-30-mid.mp4"), &opts).expect_err("refused");
        assert!(matches!(e.kind, FilmErrorKind::Options(_)), "{e}");
        assert!(e.to_string().contains(said), "{e}");
    }
}

/// Far cameras looking straight down are not taken for a tripod: nothing is written of the
/// camera and the scale is the ring's as before.
#[test]
fn a_far_camera_looking_down_writes_no_camera() {
    for (name, body) in
        [("colours-none-mid", steel_ring()), ("disk-dark-none-mid", aluminium_disk())]
    {
        let t = run(&test_data(&format!("video/{name}.mp4")), &options(body)).expect("tracks");
        assert!(t.report.camera.is_none_or(|c| !c.is_tripod()), "{name}: {:?}", t.report.camera);
        let h = &t.recording.header;
        assert_eq!((h.camera_distance_mm, h.camera_tilt_deg), (None, None), "{name}");
    }
}

/// The true centres of the tripod's cut fix the camera they were made with: 550 mm from the
/// table along its axis, tilted 30 degrees, the table's scale 3.364764 px/mm under the image
/// centre.
#[test]
fn the_true_centres_of_a_tripods_film_fix_its_camera() {
    let truth = read_recording(&test_data("video/colours-tripod-30-mid.truth.csv")).expect("truth");
    let body = steel_ring();
    let geometry = ringlab_core::recording::marks::MarkGeometry {
        radius: body.outer_radius_mm - 0.5,
        r_outer: body.outer_radius_mm,
        h: body.width_mm,
        order: ringlab_core::recording::marks::MarkOrder::Forward,
    };
    let c = ringlab_core::film::camera_fit::fit_camera(
        &truth.frames,
        geometry,
        [1280.0, 1024.0],
        3.7,
        CameraGiven::default(),
        None,
    )
    .expect("a camera");
    let d = c.distance_mm.expect("near");
    assert!((d - 550.0).abs() < 3.0, "{c:?}");
    assert!((c.tilt_deg - 30.0).abs() < 0.1, "{c:?}");
    assert!((c.px_per_mm / 3.364764 - 1.0).abs() < 0.002, "{c:?}");
    assert!(c.figure_px < 0.02 && c.far_figure_px > 1.0, "{c:?}");
    assert!(c.is_tripod(), "{c:?}");
}
