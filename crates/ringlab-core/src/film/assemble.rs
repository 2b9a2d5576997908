//! The recording assembled from a film's pass: the scale (given, from the ring, or from a
//! tripod's camera fitted from it), the centres' error (the marks' parallelogram, or their
//! figure through a near camera's pinhole), the header, and the report with its notes.

use super::pass::{Job, Tracked};
use super::{
    FilmError, FilmErrorKind, FilmInfo, NEAR_RING_SCALE, RingCamera, RingScale, TRACKER_SIGMA_KEY,
    TrackReport, TrackedFilm, camera_fit, camera_motion, error, lost, mark_radius_mm, pose_error,
    scale,
};
use crate::physics::Shape;
use crate::recording::{Camera, FrameMarks, Header, Recording, is_usable};

/// The film's size and frame rate.
pub struct FilmFacts<'a> {
    pub info: &'a FilmInfo,
    pub fps: f64,
}

/// The recording and report of a film's pass; an error where it found no ring, too little of
/// it, or no scale.
pub fn assemble(job: &Job, film: FilmFacts, tracked: Tracked) -> Result<TrackedFilm, FilmError> {
    let acquired_at = usable_start(job, &tracked)?;
    let Tracked { style, track, seen, ambiguous, reacquired, motion, stages, .. } = tracked;
    let (frames, sigma) = (track.frames, track.sigma);
    let mut scaled = scaled(job, film.info, &frames).map_err(|k| job.err(k))?;
    let centre_sigma_px = median_per_mark(&sigma);
    let (tracker_sigma_px, sigma) = centres_error(job, film.info, &frames, sigma, &mut scaled);
    let mut notes = std::mem::take(&mut scaled.notes);
    if film.info.missing > 0 {
        notes.push(format!(
            "the film's frame rate varies: its timestamps leave {} of its frames at {} frames/s untaken; they are empty rows at their times",
            film.info.missing, film.fps
        ));
    }
    notes.extend(lost::lost_note(&frames, job.opts.from_frame));
    notes.extend(camera_motion::camera_note(&motion));
    notes.extend(stages.iter().filter_map(|s| s.note.clone()));
    let name = job.path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let mut extra = vec![
        ("tracked_from".to_string(), name),
        ("tracked_marks".to_string(), style.name().to_string()),
    ];
    if let Some(s) = tracker_sigma_px {
        extra.push((TRACKER_SIGMA_KEY.to_string(), format!("{s:.3}")));
    }
    if let Some(from) = scale_from(job, &scaled) {
        extra.push(("px_per_mm_from".to_string(), from));
    }
    let header = header(job, &film, &scaled, extra);
    let marks_found = frames.iter().map(|f| f.iter().flatten().count()).sum();
    let report = TrackReport {
        style,
        frames: frames.len(),
        width_px: film.info.width,
        height_px: film.info.height,
        fps: film.fps,
        acquired_at,
        marks_found,
        left_out_ambiguous: ambiguous,
        reacquired,
        stages,
        centre_sigma_px,
        tracker_sigma_px,
        ring_scale: scaled.ring_scale,
        camera: scaled.camera,
        px_per_mm: scaled.px_per_mm,
        camera_motion: motion,
        notes,
    };
    let recording = Recording { header, first_frame: job.opts.from_frame, frames };
    Ok(TrackedFilm { recording, sigma, report, seen })
}

/// The frame the ring was acquired in; an error where it never was or fewer than two frames
/// hold an opposite pair and a third.
fn usable_start(job: &Job, tracked: &Tracked) -> Result<u64, FilmError> {
    let frames = &tracked.track.frames;
    let Some(acquired_at) = tracked.acquired_at else {
        let from = job.opts.from_frame;
        return Err(job.err(FilmErrorKind::NoMarks {
            first: from,
            last: from + frames.len().saturating_sub(1) as u64,
            style: job.opts.style.name(),
        }));
    };
    let usable = frames.iter().filter(|f| is_usable(f)).count();
    if usable < 2 {
        return Err(job.err(FilmErrorKind::TooFewUsable { usable }));
    }
    Ok(acquired_at)
}

/// The scale written and what it was had from, with the notes on it.
struct Scaled {
    /// The scale from the ring.
    ring_scale: Option<RingScale>,
    /// The camera fitted from the ring, and the same where it is a tripod's.
    camera: Option<RingCamera>,
    tripod: Option<RingCamera>,
    px_per_mm: f64,
    notes: Vec<String>,
}

/// The scale: given, a tripod's fitted from the ring, or the ring's (at the table where a
/// near camera's distance was fitted with it).
fn scaled(job: &Job, info: &FilmInfo, frames: &[FrameMarks]) -> Result<Scaled, FilmErrorKind> {
    let (opts, body) = (job.opts, &job.opts.body);
    let centre = [info.width as f64 / 2.0, info.height as f64 / 2.0];
    let radius = mark_radius_mm(body);
    let mut ring_scale =
        scale::ring_scale(frames, radius, body.outer_radius_mm, body.width_mm, centre);
    let mut notes = Vec::new();
    if let Some(rs) = ring_scale.as_mut() {
        let size = [info.width as f64, info.height as f64];
        notes.extend(pose_error::check_near_camera(rs, frames, size, radius));
    }
    let camera = super::ring_camera(opts, info, frames, ring_scale.as_ref())?;
    let tripod = camera.filter(RingCamera::is_tripod);
    if let Some(c) = &tripod {
        // The tripod's camera answers what the straight-down view's scale could not.
        notes.clear();
        notes.push(super::camera_note(c));
    }
    let from_tripod = tripod.filter(|_| opts.px_per_mm.is_none()).map(|c| c.px_per_mm);
    let px_per_mm = match (opts.px_per_mm.or(from_tripod), &ring_scale) {
        (Some(s), Some(rs)) => {
            let off = rs.px_per_mm / s - 1.0;
            if off.abs() > job.tuning.scale_check && tripod.is_none() {
                notes.push(format!(
                    "the ring measures {:.4} px/mm, {:+.1}% from the --px-per-mm given: check the body's size",
                    rs.px_per_mm,
                    100.0 * off
                ));
            }
            s
        }
        (Some(s), None) => s,
        (None, Some(rs)) => rs.table.map_or(rs.px_per_mm, |t| t.px_per_mm),
        (None, None) => return Err(FilmErrorKind::NoScale),
    };
    if let Some(rs) = &ring_scale
        && rs.camera_is_near()
        && tripod.is_none()
    {
        notes.push(near_camera_note(rs));
    }
    Ok(Scaled { ring_scale, camera, tripod, px_per_mm, notes })
}

/// The note of a near camera, with its distance where it was fitted.
fn near_camera_note(rs: &RingScale) -> String {
    match rs.table {
        Some(t) => format!(
            "a near camera (the marks' scale grows with their height): about {:.0} mm away; the table's scale under the image centre, {:.4} +- {:.4} px/mm, fitted with it (the marks' own, {:.4} px/mm, holds {:.1} mm above the table)",
            t.camera_distance_mm, t.px_per_mm, t.sigma, rs.px_per_mm, rs.height_mm
        ),
        None => format!(
            "a near camera (the scale grows {:.2}% per mm of the marks' height) whose distance could not be fitted: {:.4} px/mm holds {:.1} mm above the table, not at it (give --px-per-mm for the table's)",
            100.0 * rs.growth_per_mm,
            rs.px_per_mm,
            rs.height_mm
        ),
    }
}

/// Each mark's median centre error over the frames; `None` for a mark never found.
fn median_per_mark(sigma: &[[Option<f64>; 4]]) -> [Option<f64>; 4] {
    let mut per_mark: [Vec<f64>; 4] = Default::default();
    for s in sigma {
        for k in 0..4 {
            if let Some(v) = s[k] {
                per_mark[k].push(v);
            }
        }
    }
    per_mark.map(|mut v| {
        (!v.is_empty()).then(|| {
            v.sort_by(|a, b| a.total_cmp(b));
            v[v.len() / 2]
        })
    })
}

/// The error of one centre per coordinate from the marks' figure (a tripod's camera, the
/// parallelogram, or a near camera's poses), with each centre's error widened by the share
/// of it beyond the pixels' noise and the ring's scale error bounded by it.
fn centres_error(
    job: &Job,
    info: &FilmInfo,
    frames: &[FrameMarks],
    mut sigma: Vec<[Option<f64>; 4]>,
    scaled: &mut Scaled,
) -> (Option<f64>, Vec<[Option<f64>; 4]>) {
    let radius = mark_radius_mm(&job.opts.body);
    let tripod = scaled.tripod;
    let near =
        tripod.is_none() && scaled.ring_scale.as_ref().is_some_and(RingScale::camera_is_near);
    // Through a near camera, the marks' circle posed in each frame through the pinhole fitted
    // with the scale checks the centres instead of the parallelogram, where that pinhole is
    // known well enough: a wrong distance leaves a residual of its own in every pose.
    let near_camera = scaled
        .ring_scale
        .as_ref()
        .and_then(|rs| rs.table)
        .filter(|t| t.sigma < job.tuning.pose_scale_sigma * t.px_per_mm)
        .map(|t| Camera {
            distance_mm: Some(t.camera_distance_mm),
            ..Camera::centred(scaled.px_per_mm, info.width as f64, info.height as f64)
        });
    let tracker_sigma_px = match (near, near_camera) {
        _ if tripod.is_some() => tripod.map(|c| c.figure_px),
        (false, _) => error::closure_sigma(frames),
        (true, Some(cam)) => pose_error::pinhole_closure_sigma(frames, &cam, radius),
        (true, None) => None,
    };
    // The scale's own spread over the frames misses a bias the four centres share (each
    // pulled out or in from A by its neighbourhood alike): one centre's error over the
    // marks' radius bounds it.
    if let (Some(rs), Some(e)) = (scaled.ring_scale.as_mut(), tracker_sigma_px) {
        rs.sigma = rs.sigma.hypot(e / radius);
    }
    // Each centre's error: its own noise and the share of the closure beyond the noise.
    if let Some(total) = tracker_sigma_px {
        let noise: Vec<f64> = sigma.iter().flatten().flatten().copied().collect();
        let mean_var = noise.iter().map(|s| s * s).sum::<f64>() / noise.len().max(1) as f64;
        let beyond = (total * total - mean_var).max(0.0);
        for s in sigma.iter_mut().flatten().flatten() {
            *s = (*s * *s + beyond).sqrt();
        }
    } else if near {
        scaled.notes.push(
            "a near camera whose distance is not known well enough (the table's scale within 2%) for the marks' figure to check the centres' error: the error said is the pixels' noise alone".into(),
        );
    }
    (tracker_sigma_px, sigma)
}

/// The header's `px_per_mm_from` where the scale was not given.
fn scale_from(job: &Job, scaled: &Scaled) -> Option<String> {
    if job.opts.px_per_mm.is_some() {
        return None;
    }
    if let Some(c) = &scaled.tripod {
        return Some(camera_fit::scale_from(c));
    }
    let rs = scaled.ring_scale.as_ref()?;
    Some(match rs.table {
        Some(t) => {
            format!(
                "{NEAR_RING_SCALE}, +-{:.4}, about {:.0} mm away",
                t.sigma, t.camera_distance_mm
            )
        }
        None => format!("ring, +-{:.4}, at {:.1} mm", rs.sigma, rs.height_mm),
    })
}

/// The recording's header: the body, the film, the scale and a tripod's camera.
fn header(job: &Job, film: &FilmFacts, scaled: &Scaled, extra: Vec<(String, String)>) -> Header {
    let (body, camera, tripod) = (&job.opts.body, &job.opts.camera, scaled.tripod);
    Header {
        fps: film.fps,
        px_per_mm: scaled.px_per_mm,
        shape: body.shape,
        outer_radius_mm: body.outer_radius_mm,
        width_mm: body.width_mm,
        thickness_mm: if body.shape == Shape::Ring {
            body.thickness_mm
        } else {
            body.thickness_mm.or(Some(body.outer_radius_mm))
        },
        image_width_px: Some(film.info.width as f64),
        image_height_px: Some(film.info.height as f64),
        camera_distance_mm: tripod.and_then(|c| c.distance_mm).or(camera.distance_mm),
        camera_tilt_deg: tripod.map(|c| c.tilt_deg).or(camera.tilt_deg),
        extra,
    }
}
