//! The camera's own motion, for a camera held in the hand: every frame's table (which stands
//! still) registered against the first frame's (`register`), the ring and its shadow masked
//! out by a disc round where the marks are; the follower carried along with each frame's
//! motion so that it follows the ring and not the camera; and, where the motion is clearly
//! above the registration's noise, the marks written in the first frame's camera (the
//! table's frame).

use super::follow::Follower;
use super::frame::Frame;
use super::register::{CameraPose, Disc, Pyramid, Reference, Registration};
use crate::recording::FrameMarks;

/// The disc masked round the ring: this many times the marks' semi-major axis (the band's
/// side and its shadow reach beyond the mark circle)...
const RING_MASK: f64 = 2.2;
/// ...plus this many px (the blur, a frame's motion)...
const MASK_MARGIN_PX: f64 = 16.0;
/// ...and this many times more where the ring's place is from another frame.
const ELSEWHERE: f64 = 1.5;
/// A film is taken as hand-held where the camera moves a point of the image by more than this
/// (px) in at least `MOVING_SHARE` of the frames...
const MIN_MOTION_PX: f64 = 3.0;
const MOVING_SHARE: f64 = 0.05;
/// ...and by more than this many times the registration's own error.
const NOISE_FACTOR: f64 = 10.0;

/// How far the camera moved over the film, for the report.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CameraMotionReport {
    /// Whether the marks were moved into the first frame's camera (the motion clearly above
    /// the registration's noise).
    pub hand_held: bool,
    /// The largest shift of the image's centre from the first frame (px).
    pub largest_shift_px: f64,
    /// The largest turn of the image from the first frame (degrees).
    pub largest_turn_deg: f64,
    /// The motion's 95th percentile at the image's corners (px).
    pub motion_px: f64,
    /// The median standard error of a frame's registration at the image's corners (px).
    pub registration_sigma_px: f64,
    /// Frames registered, and frames with marks whose registration failed.
    pub frames_registered: usize,
    pub frames_unregistered: usize,
    /// Marks left out of a hand-held film for a frame whose camera could not be found.
    pub left_out_unregistered: usize,
}

/// The registration's state along the film.
#[derive(Default)]
pub struct CameraMotion {
    /// The first frame's levels, until the ring's place in it is known.
    first: Option<Pyramid>,
    reference: Option<Reference>,
    /// Each frame's pose, by slot (`None`: not registered).
    poses: Vec<Option<Registration>>,
    /// The pose of the image the follower holds now: the first frame's until the camera is
    /// first seen moving more than `MIN_MOTION_PX`, so that a still camera's registration
    /// noise never reaches the follower.
    held: CameraPose,
    /// The last pose found: where the next frame's search starts.
    last: CameraPose,
    /// The marks' semi-major axis (px), the largest seen.
    ring_px: f64,
}

impl CameraMotion {
    /// Keeps the film's first frame tracked: the table's frame.
    pub fn first_frame(&mut self, frame: &Frame) {
        self.first = Pyramid::of(frame);
    }

    /// Registers the frame at `slot` and carries `follower` into it. `ring`: the marks where
    /// the ring is in this frame or near it; `own`: whether they are this frame's.
    pub fn register(
        &mut self,
        slot: usize,
        frame: &Frame,
        ring: &FrameMarks,
        own: bool,
        follower: Option<&mut Follower>,
    ) {
        let disc = self.disc(ring, own);
        if self.reference.is_none() {
            let Some(first) = self.first.take() else { return };
            // The ring's place in the first frame is known only where that frame is this one.
            let at_first = disc.map(|d| Disc { radius: d.radius * ELSEWHERE, ..d });
            let reference_disc = if slot == 0 && own { disc } else { at_first };
            self.reference =
                Some(Reference::new(&first, reference_disc, frame.width, frame.height));
            self.set(0, Registration { pose: CameraPose::default(), sigma_px: 0.0 });
        }
        let (Some(reference), Some(levels)) = (&self.reference, Pyramid::of(frame)) else {
            return;
        };
        let Some(found) = reference.register(&levels, disc, self.last) else { return };
        self.last = found.pose;
        let centre = reference.centre();
        let moving = self.held != CameraPose::default()
            || found.pose.displacement(reference.reach()) > MIN_MOTION_PX;
        if let Some(f) = follower.filter(|_| moving) {
            let (from, to) = (self.held, found.pose);
            f.follow_camera(
                &|p| to.to_image(from.to_table(p, centre), centre),
                to.turn_rad - from.turn_rad,
            );
        }
        if moving {
            self.held = found.pose;
        }
        self.set(slot, found);
    }

    fn set(&mut self, slot: usize, r: Registration) {
        if self.poses.len() <= slot {
            self.poses.resize(slot + 1, None);
        }
        self.poses[slot] = Some(r);
    }

    /// The disc masked round the ring where `marks` put it; `None` where no mark is known.
    fn disc(&mut self, marks: &FrameMarks, own: bool) -> Option<Disc> {
        let seen: Vec<[f64; 2]> = marks.iter().flatten().copied().collect();
        for (i, p) in seen.iter().enumerate() {
            for q in &seen[i + 1..] {
                self.ring_px = self.ring_px.max((p[0] - q[0]).hypot(p[1] - q[1]) / 2.0);
            }
        }
        if seen.is_empty() {
            return None;
        }
        let n = seen.len() as f64;
        let centre = [
            seen.iter().map(|p| p[0]).sum::<f64>() / n,
            seen.iter().map(|p| p[1]).sum::<f64>() / n,
        ];
        let radius = RING_MASK * self.ring_px + MASK_MARGIN_PX;
        Some(Disc { centre, radius: if own { radius } else { radius * ELSEWHERE } })
    }

    /// The poses found, for `frames` frames.
    pub fn finish(mut self, frames: usize) -> CameraTrack {
        self.poses.resize(frames, None);
        let (centre, reach) =
            self.reference.as_ref().map_or(([0.0; 2], 0.0), |r| (r.centre(), r.reach()));
        CameraTrack { poses: self.poses, centre, reach }
    }
}

/// The camera's pose in each frame, and what follows from it.
pub struct CameraTrack {
    pub poses: Vec<Option<Registration>>,
    centre: [f64; 2],
    reach: f64,
}

impl CameraTrack {
    /// The motion over the film, and whether it is clearly above the registration's noise;
    /// `frames` the marks as found (in the image).
    pub fn report(&self, frames: &[FrameMarks]) -> CameraMotionReport {
        let found: Vec<&Registration> = self.poses.iter().flatten().collect();
        let mut moved: Vec<f64> = found.iter().map(|r| r.pose.displacement(self.reach)).collect();
        moved.sort_by(f64::total_cmp);
        let mut sigma: Vec<f64> = found.iter().map(|r| r.sigma_px).filter(|s| *s > 0.0).collect();
        sigma.sort_by(f64::total_cmp);
        let quantile = |v: &[f64], q: f64| {
            v.get(((v.len() as f64 - 1.0) * q).round() as usize).copied().unwrap_or(0.0)
        };
        let motion_px = quantile(&moved, 0.95);
        let registration_sigma_px = quantile(&sigma, 0.5);
        let moving = moved.iter().filter(|&&d| d > MIN_MOTION_PX).count();
        let hand_held = moving as f64 >= MOVING_SHARE * moved.len().max(1) as f64
            && motion_px > MIN_MOTION_PX
            && motion_px > NOISE_FACTOR * registration_sigma_px;
        let unregistered = self.unregistered(frames);
        CameraMotionReport {
            hand_held,
            largest_shift_px: found
                .iter()
                .map(|r| r.pose.shift_px[0].hypot(r.pose.shift_px[1]))
                .fold(0.0, f64::max),
            largest_turn_deg: found
                .iter()
                .map(|r| r.pose.turn_rad.abs())
                .fold(0.0, f64::max)
                .to_degrees(),
            motion_px,
            registration_sigma_px,
            frames_registered: found.len(),
            frames_unregistered: unregistered.len(),
            left_out_unregistered: 0,
        }
    }

    /// The frames with marks whose camera was not found.
    fn unregistered(&self, frames: &[FrameMarks]) -> Vec<usize> {
        (0..frames.len())
            .filter(|&i| {
                frames[i].iter().any(Option::is_some)
                    && self.poses.get(i).is_none_or(Option::is_none)
            })
            .collect()
    }

    /// The marks moved into the first frame's camera; those of a frame whose camera was not
    /// found left out (with their errors), counted in the report.
    pub fn to_table(
        &self,
        frames: &mut [FrameMarks],
        sigma: &mut [[Option<f64>; 4]],
        report: &mut CameraMotionReport,
    ) {
        for (i, (f, s)) in frames.iter_mut().zip(sigma.iter_mut()).enumerate() {
            match self.poses.get(i).copied().flatten() {
                Some(r) => {
                    for m in f.iter_mut().flatten() {
                        *m = r.pose.to_table(*m, self.centre);
                    }
                }
                None => {
                    report.left_out_unregistered += f.iter().flatten().count();
                    *f = [None; 4];
                    *s = [None; 4];
                }
            }
        }
    }

    /// The marks of the table's frame where they were seen in each frame's image.
    pub fn to_image(&self, frames: &[FrameMarks]) -> Vec<FrameMarks> {
        frames
            .iter()
            .enumerate()
            .map(|(i, f)| match self.poses.get(i).copied().flatten() {
                Some(r) => f.map(|m| m.map(|p| r.pose.to_image(p, self.centre))),
                None => *f,
            })
            .collect()
    }
}

/// The report's note on a camera that moved: hand-held (the marks moved into the first
/// frame's camera) or not, where it moved at all.
pub fn camera_note(m: &CameraMotionReport) -> Option<String> {
    if m.hand_held {
        let mut note = format!(
            "a camera held in the hand: it moved up to {:.1} px and turned up to {:.2} degrees from the first frame (registered on the table to {:.3} px); the marks are written in the first frame's camera",
            m.largest_shift_px, m.largest_turn_deg, m.registration_sigma_px
        );
        if m.left_out_unregistered > 0 {
            note.push_str(&format!(
                "; {} marks left out in {} frames whose camera could not be found",
                m.left_out_unregistered, m.frames_unregistered
            ));
        }
        Some(note)
    } else if m.frames_registered > 0 && m.motion_px > MIN_MOTION_PX {
        Some(format!(
            "the camera seemed to move up to {:.1} px, not clearly above the registration's error ({:.3} px): the marks are written as seen",
            m.motion_px, m.registration_sigma_px
        ))
    } else {
        None
    }
}
