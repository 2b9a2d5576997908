//! The ring acquired: four dots found in one frame stand only where the next frame finds four
//! of the same size in the same place. The mark circle's semi-major axis is the same in every
//! pose (a camera far away), while four specks of noise that happen to sit as marks do, which
//! a strongly compressed film shows when no scale narrows the search, change from frame to
//! frame. Four colours need no second frame: noise seldom has four distinct hues.

use super::MarkStyle;
use super::find::{Found, ellipse_axes};
use super::frame::Frame;

/// Frames in a row that must agree for marks of this style.
fn agreeing(style: MarkStyle) -> usize {
    if style == MarkStyle::Colours { 1 } else { 2 }
}

/// Frames in a row that agree: the first with its four, the others after it.
pub struct Run {
    pub first: (u64, Frame, Found),
    pub rest: Vec<(u64, Frame)>,
}

/// Frames waiting for the ring to be confirmed, oldest first.
#[derive(Default)]
pub struct Acquirer {
    pending: Vec<(u64, Frame, Found)>,
}

impl Acquirer {
    /// Offers a frame and the four found in it (`None`: none). Returns the run that agrees
    /// once enough frames in a row do.
    pub fn offer(
        &mut self,
        index: u64,
        frame: &Frame,
        found: Option<(MarkStyle, Found)>,
    ) -> Option<Run> {
        let Some((style, found)) = found else {
            self.pending.clear();
            return None;
        };
        if self.pending.last().is_some_and(|(_, _, last)| !agree(last, &found)) {
            self.pending.clear();
        }
        self.pending.push((index, frame.clone(), found));
        if self.pending.len() < agreeing(style) {
            return None;
        }
        let mut run = std::mem::take(&mut self.pending).into_iter();
        let first = run.next()?;
        Some(Run { first, rest: run.map(|(i, f, _)| (i, f)).collect() })
    }
}

/// The marks' centre and semi-major axis (px).
fn figure(f: &Found) -> ([f64; 2], f64) {
    let m = &f.marks;
    let a = [(m[0].x + m[1].x + m[2].x + m[3].x) / 4.0, (m[0].y + m[1].y + m[2].y + m[3].y) / 4.0];
    let d1 = [(m[0].x - m[2].x) / 2.0, (m[0].y - m[2].y) / 2.0];
    let d2 = [(m[1].x - m[3].x) / 2.0, (m[1].y - m[3].y) / 2.0];
    (a, ellipse_axes(d1, d2).0)
}

/// Two frames' fours are one ring: sizes within the centres' error and a little more (a near
/// camera's size changes slowly), centres within a quarter of the size (the ring's motion).
pub fn agree(a: &Found, b: &Found) -> bool {
    let ((ca, sa), (cb, sb)) = (figure(a), figure(b));
    let size = sa.max(sb);
    (sa - sb).abs() <= 0.05 * size + 0.5 && (ca[0] - cb[0]).hypot(ca[1] - cb[1]) <= 0.25 * size
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::find::Candidate;

    fn four(cx: f64, a: f64) -> Found {
        let c = |x: f64, y: f64| Candidate { x, y, strength: 1.0, chroma: [0.0; 2] };
        Found {
            marks: [c(cx + a, 50.0), c(cx, 50.0 + a), c(cx - a, 50.0), c(cx, 50.0 - a)],
            dot_radius: 2.0,
        }
    }

    #[test]
    fn noise_of_changing_size_is_not_acquired_and_a_steady_ring_is() {
        let frame = Frame::default();
        let mut acq = Acquirer::default();
        let dots = |cx, a| Some((MarkStyle::Dark, four(cx, a)));
        assert!(acq.offer(0, &frame, dots(50.0, 13.0)).is_none());
        assert!(acq.offer(1, &frame, dots(51.0, 15.5)).is_none());
        assert!(acq.offer(2, &frame, dots(52.0, 19.5)).is_none());
        assert!(acq.offer(3, &frame, dots(60.0, 63.5)).is_none());
        let run = acq.offer(4, &frame, dots(61.0, 64.0)).expect("two agree");
        assert_eq!(run.first.0, 3);
        assert_eq!(run.rest.iter().map(|r| r.0).collect::<Vec<_>>(), vec![4]);
        let colours = Some((MarkStyle::Colours, four(50.0, 13.0)));
        assert!(acq.offer(5, &frame, colours).is_some_and(|r| r.rest.is_empty()));
    }
}
