//! The diagnosis's progress: each stage's share of the bar and its messages, in one place (the
//! stages call it; they do no progress arithmetic of their own).

use super::options::{DiagnoseProgress, DiagnoseStage};
use crate::analysis::fit::FitProgress;
use crate::physics::effects::EffectKind;
use std::sync::Mutex;

/// Where each stage ends on the bar: the baseline's multiple-shooting fit, its whole-run path,
/// the candidates (with the departure beside them), their second passes, the pairs; then the
/// words. Where the pairs are needed they take as long as everything before them.
const FIT_END: f64 = 0.08;
const BASELINE_END: f64 = 0.15;
const CANDIDATES_END: f64 = 0.50;
const AGAIN_END: f64 = 0.55;
/// Where the pairs' first and second rounds end, and where the best pair's passes again start.
const ROUND_END: [f64; 2] = [0.75, 0.85];
const PAIR_AGAIN: [f64; 2] = [0.87, 0.92];
const EXPLAIN_AT: f64 = 0.97;

/// Reports the diagnosis's progress to its caller; shared by the worker threads.
pub(super) struct Reporter<'a> {
    report: &'a (dyn Fn(&DiagnoseProgress) + Sync),
    /// The baseline path's share done.
    baseline: Mutex<f64>,
    /// Each candidate's share done (by `EffectKind::ALL` index), and how many are finished.
    candidates: Mutex<(Vec<f64>, usize)>,
    /// The pairs' round, fitted and planned.
    pairs: Mutex<PairRound>,
}

impl<'a> Reporter<'a> {
    pub(super) fn new(report: &'a (dyn Fn(&DiagnoseProgress) + Sync)) -> Reporter<'a> {
        Reporter {
            report,
            baseline: Mutex::new(0.0),
            candidates: Mutex::new((vec![0.0; EffectKind::ALL.len()], 0)),
            pairs: Mutex::new(PairRound { round: 0, done: 0, count: 0 }),
        }
    }

    fn send(&self, stage: DiagnoseStage, fraction: f64, message: String) {
        (self.report)(&DiagnoseProgress { stage, fraction, message });
    }

    /// Stage 1: the fit's own five stages.
    pub(super) fn baseline_fit(&self, p: &FitProgress) {
        let within = if p.total > 0 { (p.done as f64 / p.total as f64).min(1.0) } else { 0.0 };
        let fraction = FIT_END * (p.stage as usize as f64 + within) / 5.0;
        self.send(
            DiagnoseStage::BaselineFit(p.stage),
            fraction,
            format!("baseline fit: {}", p.stage.describe()),
        );
    }

    /// Stage 1, after the fit: its segments refitted with the camera free
    /// ([`super::seen_camera`]).
    pub(super) fn seeing_camera(&self) {
        let message = "baseline fit: the camera its segments see".to_string();
        self.send(
            DiagnoseStage::BaselineFit(crate::analysis::fit::FitStage::Refine),
            FIT_END,
            message,
        );
    }

    /// Stage 2: the baseline's path has reached `segments` of the fit's `fit_segments`
    /// (the segments halve, level by level, to one).
    pub(super) fn baseline_path(&self, fit_segments: usize, segments: usize, rms_px: f64) {
        let levels = (fit_segments.max(1) as f64).log2().ceil() + 1.0;
        let done = (levels - (segments.max(1) as f64).log2().ceil() - 1.0) / levels;
        if let Ok(mut d) = self.baseline.lock() {
            *d = d.max(done);
            let fraction = FIT_END + (BASELINE_END - FIT_END) * *d;
            let message =
                format!("baseline over the whole run: {segments} segments, {rms_px:.2} px");
            self.send(DiagnoseStage::Candidates, fraction, message);
        }
    }

    fn candidates_fraction(&self, shares: &[f64], count: usize) -> f64 {
        let sum: f64 = shares.iter().sum();
        BASELINE_END + (CANDIDATES_END - BASELINE_END) * (sum / count.max(1) as f64).min(1.0)
    }

    /// Stage 3: candidate `k`'s path (three levels: four segments, two, one) has reached
    /// `segments`; `count` candidates in all.
    pub(super) fn candidate_level(
        &self,
        k: EffectKind,
        segments: usize,
        rms_px: f64,
        count: usize,
    ) {
        if let Ok(mut st) = self.candidates.lock() {
            let slot = &mut st.0[index(k)];
            *slot = slot.max(match segments {
                0..=1 => 0.67,
                2 => 0.33,
                _ => 0.0,
            });
            let plural = if segments == 1 { "" } else { "s" };
            let fraction = self.candidates_fraction(&st.0, count);
            self.send(
                DiagnoseStage::Candidates,
                fraction,
                format!("{k}: {segments} segment{plural}, {rms_px:.2} px"),
            );
        }
    }

    /// Stage 3: candidate `k` is fitted over the whole run.
    pub(super) fn candidate_done(&self, k: EffectKind, count: usize) {
        if let Ok(mut st) = self.candidates.lock() {
            st.0[index(k)] = 1.0;
            st.1 += 1;
            let message = format!("{} of {count} candidates fitted over the whole run", st.1);
            let fraction = self.candidates_fraction(&st.0, count);
            self.send(DiagnoseStage::Candidates, fraction, message);
        }
    }

    /// Stage 3, after every candidate: `what` is fitted again (a camera candidate through the
    /// camera it found, the best candidates' paths walked again).
    pub(super) fn fitting_again(&self, what: &str) {
        self.send(DiagnoseStage::Candidates, CANDIDATES_END, format!("fitting again: {what}"));
    }

    /// Stage 5: the pairs of round `round` (0: the first, 1: the second) are planned, `count`.
    pub(super) fn pairs_planned(&self, round: usize, count: usize) {
        if let Ok(mut st) = self.pairs.lock() {
            *st = PairRound { round: round.min(1), done: 0, count };
            self.send(DiagnoseStage::Candidates, st.fraction(), st.message());
        }
    }

    /// Stage 5: the pair `a + b` is fitted over the whole run, to `rms_px`.
    pub(super) fn pair_fitted(&self, a: EffectKind, b: EffectKind, rms_px: f64) {
        if let Ok(mut st) = self.pairs.lock() {
            st.done += 1;
            let message = format!("{} ({a} + {b}: {rms_px:.2} px)", st.message());
            self.send(DiagnoseStage::Candidates, st.fraction(), message);
        }
    }

    /// Stage 5, after the pairs: `what` is fitted again (the best pair; `late`: its last pass).
    pub(super) fn pair_again(&self, what: &str, late: bool) {
        let fraction = if late { PAIR_AGAIN[1] } else { PAIR_AGAIN[0] };
        self.send(DiagnoseStage::Candidates, fraction, format!("pairs of effects: {what}"));
    }

    /// Stage 6: the residuals, the signature, the words.
    pub(super) fn explaining(&self) {
        self.send(DiagnoseStage::Explain, EXPLAIN_AT, "explaining".into());
    }
}

/// A round of pairs: which, how many of its pairs are fitted, and how many it has.
#[derive(Clone, Copy)]
struct PairRound {
    round: usize,
    done: usize,
    count: usize,
}

impl PairRound {
    fn fraction(&self) -> f64 {
        let start = if self.round == 0 { AGAIN_END } else { ROUND_END[0] };
        let share = (self.done as f64 / self.count.max(1) as f64).min(1.0);
        start + (ROUND_END[self.round] - start) * share
    }

    fn message(&self) -> String {
        let which = if self.round == 0 { "" } else { ", second round" };
        format!("pairs of effects{which}: {} of {} fitted", self.done, self.count)
    }
}

fn index(k: EffectKind) -> usize {
    EffectKind::ALL.iter().position(|&x| x == k).unwrap_or(0)
}
