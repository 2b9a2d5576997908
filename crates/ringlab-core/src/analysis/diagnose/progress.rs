//! The diagnosis's progress: each stage's share of the bar and its messages, in one place (the
//! stages call it; they do no progress arithmetic of their own).

use super::options::{DiagnoseProgress, DiagnoseStage};
use crate::analysis::fit::FitProgress;
use crate::physics::effects::EffectKind;
use std::sync::Mutex;

/// Where each stage ends on the bar: the baseline's multiple-shooting fit, its whole-run path,
/// the candidates (with the departure beside them), the plan's singles phase, its selection
/// (the pairs and larger models); then the words. Where the selection is needed it takes as
/// long as everything before it. Each pass of the plan has its weight's share of its phase.
const FIT_END: f64 = 0.08;
const BASELINE_END: f64 = 0.15;
const CANDIDATES_END: f64 = 0.50;
const SINGLES_END: f64 = 0.55;
const SELECTION_END: f64 = 0.95;
const EXPLAIN_AT: f64 = 0.97;
/// The share of the pairs' pass that their first round takes.
const FIRST_ROUND: f64 = 0.7;

/// Reports the diagnosis's progress to its caller; shared by the worker threads.
pub(super) struct Reporter<'a> {
    report: &'a (dyn Fn(&DiagnoseProgress) + Sync),
    /// The baseline path's share done.
    baseline: Mutex<f64>,
    /// Each candidate's share done (by `EffectKind::ALL` index), and how many are finished.
    candidates: Mutex<(Vec<f64>, usize)>,
    /// The pairs' round, fitted and planned.
    pairs: Mutex<PairRound>,
    /// The pass of the plan under way and its stretch of the bar.
    pass: Mutex<Option<PassSlot>>,
}

/// A pass of the plan on the bar: its name and where its stretch begins and ends.
#[derive(Clone, Copy)]
struct PassSlot {
    name: &'static str,
    from: f64,
    to: f64,
}

impl<'a> Reporter<'a> {
    pub(super) fn new(report: &'a (dyn Fn(&DiagnoseProgress) + Sync)) -> Reporter<'a> {
        Reporter {
            report,
            baseline: Mutex::new(0.0),
            candidates: Mutex::new((vec![0.0; EffectKind::ALL.len()], 0)),
            pairs: Mutex::new(PairRound { round: 0, done: 0, count: 0 }),
            pass: Mutex::new(None),
        }
    }

    fn send(&self, stage: DiagnoseStage, fraction: f64, message: String) {
        let pass = self.slot().map(|p| p.name);
        (self.report)(&DiagnoseProgress { stage, fraction, message, pass });
    }

    fn slot(&self) -> Option<PassSlot> {
        *self.pass.lock().unwrap_or_else(|e| e.into_inner())
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

    /// The plan's pass `name` of `phase` begins; it spans `from..to` of its phase (shares).
    pub(super) fn pass(&self, phase: Phase, name: &'static str, from: f64, to: f64) {
        let (start, end) = match phase {
            Phase::Singles => (CANDIDATES_END, SINGLES_END),
            Phase::Selection => (SINGLES_END, SELECTION_END),
        };
        let at = |share: f64| start + (end - start) * share.clamp(0.0, 1.0);
        let slot = PassSlot { name, from: at(from), to: at(to) };
        *self.pass.lock().unwrap_or_else(|e| e.into_inner()) = Some(slot);
        self.send(DiagnoseStage::Candidates, slot.from, name.to_string());
    }

    /// Stage 5: the pairs of round `round` (0: the first, 1: the second) are planned, `count`.
    pub(super) fn pairs_planned(&self, round: usize, count: usize) {
        let slot = self.slot();
        if let Ok(mut st) = self.pairs.lock() {
            *st = PairRound { round: round.min(1), done: 0, count };
            self.send(DiagnoseStage::Candidates, st.fraction(slot), st.message());
        }
    }

    /// Stage 5: the pair `a + b` is fitted over the whole run, to `rms_px`.
    pub(super) fn pair_fitted(&self, a: EffectKind, b: EffectKind, rms_px: f64) {
        let slot = self.slot();
        if let Ok(mut st) = self.pairs.lock() {
            st.done += 1;
            let message = format!("{} ({a} + {b}: {rms_px:.2} px)", st.message());
            self.send(DiagnoseStage::Candidates, st.fraction(slot), message);
        }
    }

    /// Stage 6: the residuals, the signature, the words.
    pub(super) fn explaining(&self) {
        *self.pass.lock().unwrap_or_else(|e| e.into_inner()) = None;
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
    /// Where it is on the bar, within the pass `slot` that fits it.
    fn fraction(&self, slot: Option<PassSlot>) -> f64 {
        let (from, to) = slot.map_or((SINGLES_END, SELECTION_END), |s| (s.from, s.to));
        let (a, b) = if self.round == 0 { (0.0, FIRST_ROUND) } else { (FIRST_ROUND, 1.0) };
        let share = (self.done as f64 / self.count.max(1) as f64).min(1.0);
        from + (to - from) * (a + (b - a) * share)
    }

    fn message(&self) -> String {
        let which = if self.round == 0 { "" } else { ", second round" };
        format!("pairs of effects{which}: {} of {} fitted", self.done, self.count)
    }
}

fn index(k: EffectKind) -> usize {
    EffectKind::ALL.iter().position(|&x| x == k).unwrap_or(0)
}

/// The two phases of the plan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Phase {
    Singles,
    Selection,
}
