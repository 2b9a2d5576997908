//! A run's step ends kept, and followed by another run of nearby parameters.
//!
//! Why: a forward difference of two adaptive runs carries the tolerance's jitter (each run
//! picks its own steps), divided by the difference's step. Taken at the same step ends, the
//! two runs differ smoothly in the parameters, so the derivative is that of one fixed
//! discretization and holds at a looser tolerance (internal numerical differentiation, Bock).

use std::sync::Arc;

/// A followed step is accepted up to this error ratio (the kept run's steps had at most 1; a
/// nearby run's differ little). Beyond, the run takes an adaptive step there instead.
pub(super) const FOLLOW_MAX_ERR: f64 = 10.0;

/// How a run chooses its steps.
#[derive(Clone, Debug, Default)]
pub(super) enum Steps {
    #[default]
    Adaptive,
    /// Adaptive, keeping where each step ends.
    Keep(Vec<f64>),
    /// To the ends another run kept, in order; `next` is the first not yet reached.
    Follow { ends: Arc<[f64]>, next: usize },
}

impl Steps {
    /// The end of the next step to take, when following: the first kept end beyond `t`
    /// (a run whose contact switched at another time than the kept run's resumes there).
    pub(super) fn target(&mut self, t: f64) -> Option<f64> {
        let Steps::Follow { ends, next } = self else { return None };
        let gap = 1e-12 * t.abs().max(1.0);
        while *next < ends.len() && ends[*next] <= t + gap {
            *next += 1;
        }
        let end = ends.get(*next).copied()?;
        *next += 1;
        Some(end)
    }

    /// Notes a step taken (kept when keeping).
    pub(super) fn taken(&mut self, t: f64) {
        if let Steps::Keep(ends) = self {
            ends.push(t);
        }
    }

    pub(super) fn into_kept(self) -> Vec<f64> {
        match self {
            Steps::Keep(ends) => ends,
            _ => Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn follows_the_kept_ends_beyond_the_current_time() {
        // The kept run's step to 0.3 met a switch at 0.25; restarted there, it stepped to 0.28.
        let ends: Arc<[f64]> = Arc::from(vec![0.1, 0.3, 0.28, 0.5]);
        let mut s = Steps::Follow { ends: ends.clone(), next: 0 };
        assert_eq!(s.target(0.0), Some(0.1));
        assert_eq!(s.target(0.1), Some(0.3));
        // This run switched a little later, at 0.26: on to 0.28 as the kept run.
        assert_eq!(s.target(0.26), Some(0.28));
        assert_eq!(s.target(0.28), Some(0.5));
        assert_eq!(s.target(0.5), None);
        // Switched at 0.29, past the kept run's 0.28: it resumes at the first end beyond.
        let mut s = Steps::Follow { ends, next: 0 };
        s.target(0.0);
        s.target(0.1);
        assert_eq!(s.target(0.29), Some(0.5));
        let mut k = Steps::Keep(Vec::new());
        assert_eq!(k.target(0.0), None);
        k.taken(0.1);
        assert_eq!(k.into_kept(), vec![0.1]);
    }
}
