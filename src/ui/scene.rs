//! From tracks to what the 3D view draws: bodies where they are at the display time, the path
//! of A coloured by phase, the contact point's path, the start and the inflection.

use super::palette::{CONTACT_RGB, DATA_BODY_LINEAR, DATA_RGB, phase_linear, srgb_to_linear};
use crate::physics::Body;
use crate::render::{
    BodyDraw, BodyGeometry, BodyPose, CameraView, OrbitCamera, SceneFrame, TraceSegment, nice_step,
};
use crate::sim::Track;
use glam::{Vec2, Vec3};

/// States of one path at most (before the extra points where it turns fast); longer tracks
/// are thinned (every k-th state).
const MAX_STATES: usize = 3000;
/// The contact point's path is drawn for the last few precession periods only: over a whole
/// run it is a tangle of circles the size of the ring (the trace panel can show all of it).
const CONTACT_TRAIL_PERIODS: f64 = 4.0;

/// Longest run of points one simplified segment may replace (bounds the work on straight
/// stretches).
const MAX_RUN: usize = 64;

fn dist_to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let u = if len2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - u * dx).hypot(p[1] - a[1] - u * dy)
}

/// The indices of the points of a polyline worth drawing: no dropped point lies farther than
/// `tol` from the line through the kept ones, and `must(i)` keeps point `i` (where the colour
/// changes). Every point drawn is triangles for the (software) rasteriser; a smooth arc needs
/// far fewer of them than the integrator's output spacing gives.
pub fn simplify(pts: &[[f64; 2]], tol: f64, must: impl Fn(usize) -> bool) -> Vec<usize> {
    let n = pts.len();
    if n <= 2 {
        return (0..n).collect();
    }
    let mut keep = vec![0];
    let mut anchor = 0;
    let mut i = 1;
    while i < n {
        let fits = i == anchor + 1
            || (i - anchor <= MAX_RUN
                && (anchor + 1..i).all(|k| dist_to_segment(pts[k], pts[anchor], pts[i]) <= tol));
        if !fits {
            keep.push(i - 1);
            anchor = i - 1;
            continue;
        }
        if i == n - 1 || must(i) {
            keep.push(i);
            anchor = i;
        }
        i += 1;
    }
    keep
}

pub fn body_geometry(b: &Body) -> BodyGeometry {
    BodyGeometry { r: b.r as f32, h: b.h as f32, w: b.w.min(b.r) as f32 }
}

/// The mean position of the centre of mass over the last precession period before `t` (the
/// camera follows this, not the wobbling body).
pub fn follow_point(track: &Track, t: f64) -> Option<Vec2> {
    let start = track.start()?;
    let period = std::f64::consts::TAU / start.phi_dot().abs().max(1e-9);
    let recent = track.samples_until(t);
    let from = recent.partition_point(|s| s.t < t - period);
    let window = &recent[from..];
    if window.is_empty() {
        return recent
            .last()
            .or(track.samples().first())
            .map(|s| Vec2::new(s.x_c() as f32, s.y_c() as f32));
    }
    let n = window.len() as f64;
    let (x, y) = window.iter().fold((0.0, 0.0), |(x, y), s| (x + s.x_c(), y + s.y_c()));
    Some(Vec2::new((x / n) as f32, (y / n) as f32))
}

fn circle(out: &mut Vec<TraceSegment>, c: Vec2, r: f32, color: [f32; 4], half_width: f32) {
    let n = 28;
    for k in 0..n {
        let a0 = k as f32 / n as f32 * std::f32::consts::TAU;
        let a1 = (k + 1) as f32 / n as f32 * std::f32::consts::TAU;
        out.push(TraceSegment::new(
            c + r * Vec2::new(a0.cos(), a0.sin()),
            c + r * Vec2::new(a1.cos(), a1.sin()),
            color,
            half_width,
            0.8,
        ));
    }
}

/// The traces of one track up to `t`: the contact path (optional, thin and faint) under the
/// path of A coloured by phase, a ring at the start and one at the inflection.
pub fn trace_segments(track: &Track, t: f64, show_contact: bool) -> Vec<TraceSegment> {
    let r = track.case().model.body.r as f32;
    let path = track.path_until(t, MAX_STATES);
    let mut out = Vec::with_capacity(2 * path.len() + 60);
    let Some(first) = path.first() else { return out };
    let v = |p: [f64; 2]| Vec2::new(p[0] as f32, p[1] as f32);
    if show_contact {
        let c = CONTACT_RGB.map(|x| srgb_to_linear(x as f32 / 255.0));
        let period = track
            .start()
            .map_or(f64::INFINITY, |s| std::f64::consts::TAU / s.phi_dot().abs().max(1e-9));
        let trail = &path[path.partition_point(|q| q.t < t - CONTACT_TRAIL_PERIODS * period)..];
        let p: Vec<[f64; 2]> = trail.iter().map(|q| q.p).collect();
        let kept = simplify(&p, 0.002 * r as f64, |_| false);
        for w in kept.windows(2) {
            // Fading out towards the start of the trail.
            let age =
                ((t - trail[w[0]].t) / (CONTACT_TRAIL_PERIODS * period)).clamp(0.0, 1.0) as f32;
            out.push(TraceSegment::new(
                v(p[w[0]]),
                v(p[w[1]]),
                [c[0], c[1], c[2], 0.6 * (1.0 - age)],
                0.012 * r,
                0.6,
            ));
        }
    }
    let hw = 0.028 * r;
    let a: Vec<[f64; 2]> = path.iter().map(|q| q.a).collect();
    let phases: Vec<_> = path.iter().map(|q| track.phase_at(q.t)).collect();
    let kept = simplify(&a, 0.002 * r as f64, |i| phases[i] != phases[i - 1]);
    for w in kept.windows(2) {
        let color = phase_linear(phases[w[0]], 1.0);
        out.push(TraceSegment::new(v(a[w[0]]), v(a[w[1]]), color, hw, 1.1));
    }
    let dark = [0.02, 0.02, 0.03, 0.9];
    circle(&mut out, v(first.a), 0.12 * r, dark, 0.015 * r);
    if let Some(ti) = track.inflection_time().filter(|&ti| ti <= t)
        && let Some(s) = track.state_at(ti)
    {
        let p = Vec2::new(s.sample.x_a as f32, s.sample.y_a as f32);
        circle(&mut out, p, 0.22 * r, dark, 0.02 * r);
        circle(&mut out, p, 0.06 * r, dark, 0.03 * r);
    }
    out
}

/// The body of `track` at time `t`, painted `color` (linear RGB).
pub fn body_draw(track: &Track, t: f64, color: [f32; 3]) -> Option<BodyDraw> {
    let s = track.state_at(t)?.sample;
    let body = &track.case().model.body;
    let pose = BodyPose::new(&s, body);
    Some(BodyDraw {
        geometry: body_geometry(body),
        world_from_ring: pose.world_from_ring,
        color,
        contact: pose.contact,
        yields: false,
        discs: None,
    })
}

/// One view's frame: `track` at `t` seen by `camera`, its target moved to the followed point
/// when `follow`.
pub fn scene_frame(
    track: &Track,
    t: f64,
    camera: &OrbitCamera,
    follow: bool,
    show_contact: bool,
    color: [f32; 3],
) -> SceneFrame {
    let r = track.case().model.body.r as f32;
    let mut cam = *camera;
    if follow && let Some(p) = follow_point(track, t) {
        cam.target = [p.x, p.y, 0.0];
    }
    let view: CameraView = cam.view();
    SceneFrame {
        camera: view,
        bodies: body_draw(track, t, color).into_iter().collect(),
        traces: trace_segments(track, t, show_contact),
        scale: r,
        grid_spacing: nice_step(track.case().model.body.r) as f32,
        focus: Vec3::from(cam.target).truncate(),
    }
}

/// A recording added to a view's frame: the path of its point A so far (table, the view's
/// units) over the model's traces, and its ring where the recording has it now.
pub fn add_recording(frame: &mut SceneFrame, path: &[[f64; 2]], ring: Option<(&Body, BodyPose)>) {
    let r = frame.scale;
    let [cr, cg, cb] = DATA_RGB.map(|x| srgb_to_linear(x as f32 / 255.0));
    let v = |p: [f64; 2]| Vec2::new(p[0] as f32, p[1] as f32);
    // Narrower than the model's path, so that where they agree both show.
    for w in simplify(path, 0.002 * r as f64, |_| false).windows(2) {
        frame.traces.push(TraceSegment::new(
            v(path[w[0]]),
            v(path[w[1]]),
            [cr, cg, cb, 0.95],
            0.014 * r,
            0.7,
        ));
    }
    if let Some((body, pose)) = ring {
        frame.bodies.push(BodyDraw {
            geometry: body_geometry(body),
            world_from_ring: pose.world_from_ring,
            color: DATA_BODY_LINEAR,
            contact: pose.contact,
            yields: true,
            discs: None,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::simplify;

    #[test]
    fn simplify_drops_points_on_straight_stretches_and_keeps_corners_and_forced_ones() {
        let mut pts: Vec<[f64; 2]> = (0..50).map(|k| [k as f64, 0.0]).collect();
        pts.extend((1..50).map(|k| [49.0, k as f64]));
        let kept = simplify(&pts, 0.01, |i| i == 10);
        assert_eq!(kept, vec![0, 10, 49, 98]);
        let circle: Vec<[f64; 2]> = (0..=360)
            .map(|d| {
                let a = (d as f64).to_radians();
                [a.cos(), a.sin()]
            })
            .collect();
        let kept = simplify(&circle, 1e-3, |_| false);
        assert!(kept.len() > 10 && kept.len() < 100, "{} points kept", kept.len());
        for w in kept.windows(2) {
            for k in w[0]..w[1] {
                assert!(super::dist_to_segment(circle[k], circle[w[0]], circle[w[1]]) <= 1e-3);
            }
        }
    }
}
