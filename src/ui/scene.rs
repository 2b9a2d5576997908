//! From tracks to what the 3D view draws: bodies where they are at the display time, the path
//! of A coloured by phase, the contact point's path, the start and the inflection.

use super::palette::{CONTACT_RGB, phase_linear, srgb_to_linear};
use crate::physics::Body;
use crate::render::{BodyDraw, BodyGeometry, BodyPose, CameraView, OrbitCamera, SceneFrame, TraceSegment, nice_step};
use crate::sim::Track;
use glam::{Vec2, Vec3};

/// States of one path at most (before the extra points where it turns fast); longer tracks
/// are thinned (every k-th state).
const MAX_STATES: usize = 8000;

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
        return recent.last().or(track.samples().first()).map(|s| Vec2::new(s.x_c() as f32, s.y_c() as f32));
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
        let color = [c[0], c[1], c[2], 0.35];
        for w in path.windows(2) {
            out.push(TraceSegment::new(v(w[0].p), v(w[1].p), color, 0.01 * r, 0.5));
        }
    }
    let hw = 0.028 * r;
    for w in path.windows(2) {
        let color = phase_linear(track.phase_at(w[0].t), 1.0);
        out.push(TraceSegment::new(v(w[0].a), v(w[1].a), color, hw, 1.1));
    }
    let dark = [0.02, 0.02, 0.03, 0.9];
    circle(&mut out, v(first.a), 0.12 * r, dark, 0.015 * r);
    if let Some(ti) = track.inflection_time().filter(|&ti| ti <= t) {
        if let Some(s) = track.state_at(ti) {
            let p = Vec2::new(s.sample.x_a as f32, s.sample.y_a as f32);
            circle(&mut out, p, 0.22 * r, dark, 0.02 * r);
            circle(&mut out, p, 0.06 * r, dark, 0.03 * r);
        }
    }
    out
}

/// The body of `track` at time `t`, painted `color` (linear RGB).
pub fn body_draw(track: &Track, t: f64, color: [f32; 3]) -> Option<BodyDraw> {
    let s = track.state_at(t)?.sample;
    let body = &track.case().model.body;
    let pose = BodyPose::new(&s, body);
    Some(BodyDraw { geometry: body_geometry(body), world_from_ring: pose.world_from_ring, color, contact: pose.contact })
}

/// One view's frame: `track` at `t` seen by `camera`, its target moved to the followed point
/// when `follow`.
pub fn scene_frame(track: &Track, t: f64, camera: &OrbitCamera, follow: bool, show_contact: bool, color: [f32; 3]) -> SceneFrame {
    let r = track.case().model.body.r as f32;
    let mut cam = *camera;
    if follow {
        if let Some(p) = follow_point(track, t) {
            cam.target = [p.x, p.y, 0.0];
        }
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
