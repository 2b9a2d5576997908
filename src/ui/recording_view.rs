//! A loaded recording as one frame of the window shows it, in the model's units and frame and
//! on the display's clock: the path of A so far, where A is now, the ring's pose, and the
//! series for the plots.

use super::palette::{DATA_COLOR, MISMATCH_COLOR};
use super::plots::DataLine;
use super::trace_panel::{Bounds, Overlay};
use crate::physics::{Body, Conversion, Units};
use crate::render::BodyPose;
use crate::session::RecordingSession;

pub struct DataView {
    pub name: String,
    /// Path of A up to now (model units).
    pub path: Vec<[f64; 2]>,
    pub now: Option<[f64; 2]>,
    /// Around the whole path, so that the view does not grow as it replays.
    pub bounds: Option<Bounds>,
    /// The recording's ring (its own body, model units) where it is now.
    pub ring: Option<(Body, BodyPose)>,
    /// `v_p` and `theta` against the plots' time.
    pub v_p: Vec<[f64; 2]>,
    pub theta: Vec<[f64; 2]>,
    /// A diagnosis's mismatch window: the path of A inside it so far (model units), and the
    /// window on the plots' time axis.
    pub mismatch_path: Vec<[f64; 2]>,
    pub mismatch_plot: Option<[f64; 2]>,
    /// Point A at the frames so far where a diagnosis left out a tracker's glitch.
    pub glitches: Vec<[f64; 2]>,
}

impl DataView {
    /// The recording at display time `seconds` in `units` (the first run's), times on the plots
    /// in units of `plot_time_s` seconds. None without a recording.
    pub fn at(
        session: &RecordingSession,
        units: &Units,
        seconds: f64,
        plot_time_s: f64,
    ) -> Option<DataView> {
        let l = session.loaded()?;
        let k = Conversion::between(Units::MM_S, *units);
        let len = |p: [f64; 2]| [p[0] * k.length, p[1] * k.length];
        let frames = session.frames_until(seconds);
        let path: Vec<[f64; 2]> = frames.iter().filter_map(|f| f.a_mm.map(len)).collect();
        let all: Vec<[f64; 2]> = l.frames().iter().filter_map(|f| f.a_mm.map(len)).collect();
        let ring = match (session.pose_at(seconds), l.motion.body_mm.scaled(k.length)) {
            (Some((angles, a)), Ok(body)) => {
                let pose = BodyPose::on_table(angles.phi, angles.theta, angles.psi, len(a), &body);
                Some((body, pose))
            }
            _ => None,
        };
        let t_of = |i: usize| session.frame_seconds(i).unwrap_or(0.0) / plot_time_s;
        let window = session.mismatch_display_s();
        let inside = |i: usize| {
            window.is_some_and(|(a, b)| session.frame_seconds(i).is_some_and(|s| s >= a && s <= b))
        };
        let mismatch_path: Vec<[f64; 2]> = frames
            .iter()
            .enumerate()
            .filter(|(i, _)| inside(*i))
            .filter_map(|(_, f)| f.a_mm.map(len))
            .collect();
        let mut glitch_frames: Vec<usize> = session
            .diagnosed()
            .map_or_else(Vec::new, |d| d.result.glitches.iter().map(|g| g.frame).collect());
        glitch_frames.dedup();
        let glitches: Vec<[f64; 2]> =
            glitch_frames.iter().filter_map(|&i| frames.get(i)?.a_mm.map(len)).collect();
        let mut v_p = Vec::with_capacity(frames.len());
        let mut theta = Vec::with_capacity(frames.len());
        for (i, f) in frames.iter().enumerate() {
            if let Some(v) = f.v_p_mm_s {
                v_p.push([t_of(i), v * k.speed()]);
            }
            if let Some(a) = f.angles {
                theta.push([t_of(i), a.theta]);
            }
        }
        Some(DataView {
            name: format!("recording: {}", l.name()),
            now: frames.last().and_then(|f| f.a_mm).map(len),
            path,
            bounds: Bounds::of_points(&all),
            ring,
            v_p,
            theta,
            mismatch_path,
            mismatch_plot: window.map(|(a, b)| [a / plot_time_s, b / plot_time_s]),
            glitches,
        })
    }

    /// The path of A, over it the stretch where a diagnosis found the mismatch, and crosses
    /// where it left out a tracker's glitch.
    pub fn overlays(&self) -> Vec<Overlay<'_>> {
        let mut v = vec![Overlay {
            points: &self.path,
            color: DATA_COLOR,
            now: self.now,
            width: 1.2,
            crosses: &[],
        }];
        if self.mismatch_path.len() > 1 || !self.glitches.is_empty() {
            v.push(Overlay {
                points: &self.mismatch_path,
                color: MISMATCH_COLOR,
                now: None,
                width: 2.4,
                crosses: &self.glitches,
            });
        }
        v
    }

    pub fn plot_lines(&self) -> Vec<DataLine<'_>> {
        vec![
            DataLine {
                quantity: "v_p",
                name: &self.name,
                points: self.v_p.clone(),
                color: DATA_COLOR,
            },
            DataLine {
                quantity: "theta",
                name: &self.name,
                points: self.theta.clone(),
                color: DATA_COLOR,
            },
        ]
    }
}
