//! The last run of each segment a fit evaluated, kept for the Jacobian made at that point.
//!
//! Why: Levenberg-Marquardt evaluates a trial point, and where it accepts it, linearizes
//! there next; the linearization's first act was to run the model at that same point again,
//! to keep its step ends for the columns (`physics::run`'s `steps.rs`). The evaluation now
//! keeps its step ends and samples, and the linearization takes them where the point is the
//! same to the bit: the same run, not made twice. What a run is (`shooting::Prediction`) is
//! the caller's: this file knows only the numbers a run was made at.

use std::ops::Range;
use std::sync::Mutex;

/// The last run `R` per segment index, with the numbers it ran at. A clone starts empty: a
/// clone of a problem may change what a run depends on besides those numbers (the effects
/// free, the slip start).
#[derive(Debug)]
pub struct LastRuns<R>(Mutex<Vec<Option<Kept<R>>>>);

#[derive(Debug)]
struct Kept<R> {
    key: Vec<u64>,
    run: R,
}

impl<R> Default for LastRuns<R> {
    fn default() -> Self {
        LastRuns(Mutex::new(Vec::new()))
    }
}

impl<R> Clone for LastRuns<R> {
    fn clone(&self) -> Self {
        LastRuns::default()
    }
}

/// The numbers a segment's run depends on, to the bit.
fn key(range: &Range<usize>, global: &[f64], local: &[f64]) -> Vec<u64> {
    [range.start as u64, range.end as u64]
        .into_iter()
        .chain(global.iter().chain(local).map(|v| v.to_bits()))
        .collect()
}

impl<R> LastRuns<R> {
    /// Keeps `run`, made for segment `s` (frames `range`) at `global` and `local`.
    pub fn keep(&self, s: usize, range: &Range<usize>, global: &[f64], local: &[f64], run: R) {
        let mut runs = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if runs.len() <= s {
            runs.resize_with(s + 1, || None);
        }
        runs[s] = Some(Kept { key: key(range, global, local), run });
    }

    /// The run kept for segment `s` where it was made at these numbers (taken out).
    pub fn take(&self, s: usize, range: &Range<usize>, global: &[f64], local: &[f64]) -> Option<R> {
        let mut runs = self.0.lock().unwrap_or_else(|e| e.into_inner());
        let slot = runs.get_mut(s)?;
        if slot.as_ref().is_some_and(|k| k.key == key(range, global, local)) {
            slot.take().map(|k| k.run)
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gives_a_run_back_only_at_the_same_numbers_and_once() {
        // A run here is its number of steps.
        let runs = LastRuns::<u64>::default();
        runs.keep(2, &(0..10), &[1.0, 2.0], &[3.0], 7);
        assert!(runs.take(2, &(0..10), &[1.0, 2.0 + 1e-15], &[3.0]).is_none());
        assert!(runs.take(2, &(0..11), &[1.0, 2.0], &[3.0]).is_none());
        assert!(runs.take(1, &(0..10), &[1.0, 2.0], &[3.0]).is_none());
        assert_eq!(runs.take(2, &(0..10), &[1.0, 2.0], &[3.0]), Some(7));
        assert!(runs.take(2, &(0..10), &[1.0, 2.0], &[3.0]).is_none());
        // A clone starts empty.
        runs.keep(0, &(0..10), &[1.0], &[], 1);
        assert!(runs.clone().take(0, &(0..10), &[1.0], &[]).is_none());
    }
}
