//! The diagnosis's plan: its passes as data, each named, with when it runs and what it does,
//! run in order by one loop ([`run`]) with one test of "settled" ([`reached`]).
//!
//! Two phases share the list. The passes of the singles ([`Singles`], `again.rs`) fit the
//! single candidates again where their first walk may have ended in a side valley; then the
//! candidates are ranked and one is chosen (`select.rs::decide`), and the passes of the
//! selection ([`Choosing`], `select.rs`) fit larger models where the choice still misses.
//! Where a tracker's correlated noise is found late, the selection's passes run again against
//! the corrected noise, the singles' do not. A pass names no effect: what it needs to know of
//! one (a camera or physics, its cost, the header's camera it stands in for) is in the
//! effect's descriptor (`physics::effects::InPlan`). A new pass is one entry of [`PLAN`].

use super::again::{self, Singles};
use super::options::DiagnoseError;
use super::progress::{Phase, Reporter};
use super::rules::{Reach, reached};
use super::select::{self, Choosing};
use super::whole::WholeFit;

/// What a pass does, on the work of its phase.
pub(super) enum Step {
    Singles {
        when: fn(&Singles<'_>) -> bool,
        does: fn(&mut Singles<'_>) -> Result<(), DiagnoseError>,
    },
    Selection {
        when: fn(&Choosing<'_>) -> bool,
        does: fn(&mut Choosing<'_>) -> Result<(), DiagnoseError>,
    },
}

/// One pass of the plan.
pub(super) struct Pass {
    /// In the words the progress bar shows.
    pub(super) name: &'static str,
    /// The pass is skipped once a model its phase has fitted so far reaches this (`None`: it
    /// runs whatever was fitted before it).
    pub(super) until: Option<Reach>,
    /// Its share of its phase's stretch of the progress bar.
    pub(super) weight: f64,
    pub(super) step: Step,
}

/// The passes, in the order they run (docs/diagnosis.md has them as a table).
pub(super) const PLAN: &[Pass] = &[
    Pass {
        name: "fitting again: the camera candidates through the camera each found",
        until: Some(Reach::Settled),
        weight: 1.0,
        step: Step::Singles { when: again::always, does: again::cameras_second_pass },
    },
    Pass {
        name: "fitting again: every effect through the camera the segments see",
        until: Some(Reach::Settled),
        weight: 1.0,
        step: Step::Singles { when: again::camera_seen, does: again::through_seen_camera },
    },
    Pass {
        name: "fitting again: the best physical candidates walked again",
        until: Some(Reach::Settled),
        weight: 1.0,
        step: Step::Singles { when: again::always, does: again::walk_singles_again },
    },
    Pass {
        name: "every effect through the camera the segments see",
        until: None,
        weight: 2.0,
        step: Step::Selection { when: select::misses_with_seen, does: select::through_seen },
    },
    Pass {
        name: "pairs of the best candidates",
        until: Some(Reach::Settled),
        weight: 6.0,
        step: Step::Selection { when: select::misses, does: select::pairs },
    },
    Pass {
        name: "each other effect added to the best one's solution",
        until: Some(Reach::Settled),
        weight: 1.0,
        step: Step::Selection { when: select::misses, does: select::added_to_best },
    },
    Pass {
        name: "the chosen model through the camera the segments see",
        until: None,
        weight: 1.0,
        step: Step::Selection { when: select::seen_lacked, does: select::chosen_through_seen },
    },
    Pass {
        name: "the costly effects through the leading camera",
        until: Some(Reach::Settled),
        weight: 1.0,
        step: Step::Selection {
            when: select::camera_leads_without_costly,
            does: select::costly_through_lead,
        },
    },
    Pass {
        name: "the other effects through the leading camera",
        until: Some(Reach::Consistent),
        weight: 1.0,
        step: Step::Selection {
            when: select::camera_leads_missing,
            does: select::others_through_lead,
        },
    },
    Pass {
        name: "the best pair walked again",
        until: None,
        weight: 1.0,
        step: Step::Selection { when: select::best_pair_unwalked, does: select::walk_best_pair },
    },
    Pass {
        name: "the costly effect fitted again through the best pair's camera",
        until: None,
        weight: 1.0,
        step: Step::Selection {
            when: select::best_pair_costly_with_camera,
            does: select::costly_through_pair_camera,
        },
    },
];

/// When a pass runs and what it does, on the work `W` of its phase.
pub(super) type WhenDoes<W> = (fn(&W) -> bool, fn(&mut W) -> Result<(), DiagnoseError>);

/// What a phase's passes work on.
pub(super) trait Work: Sized {
    /// The phase, for the progress bar.
    const PHASE: Phase;
    /// The pass's step where it is of this phase.
    fn step(step: &Step) -> Option<WhenDoes<Self>>;
    /// Every model the phase has fitted so far.
    fn fitted(&self) -> Vec<&WholeFit>;
    fn noise_px(&self) -> f64;
    fn progress(&self) -> &Reporter<'_>;
}

/// The passes of `w`'s phase, in order: each that has not been made needless by a model
/// reaching its `until` and whose `when` holds, reported by name, then done.
pub(super) fn run<W: Work>(w: &mut W) -> Result<(), DiagnoseError> {
    let passes: Vec<(&Pass, _, _)> =
        PLAN.iter().filter_map(|p| W::step(&p.step).map(|(when, does)| (p, when, does))).collect();
    let total: f64 = passes.iter().map(|(p, _, _)| p.weight).sum();
    let mut done = 0.0;
    for (pass, when, does) in passes {
        let needless = pass.until.is_some_and(|r| reached(w.fitted(), r, w.noise_px()));
        if !needless && when(w) {
            w.progress().pass(W::PHASE, pass.name, done / total, (done + pass.weight) / total);
            does(w)?;
        }
        done += pass.weight;
    }
    Ok(())
}

impl Work for Singles<'_> {
    const PHASE: Phase = Phase::Singles;
    fn step(step: &Step) -> Option<WhenDoes<Self>> {
        match step {
            Step::Singles { when, does } => Some((*when, *does)),
            Step::Selection { .. } => None,
        }
    }
    fn fitted(&self) -> Vec<&WholeFit> {
        self.fits.iter().filter_map(|(_, r)| r.as_ref().ok()).chain(&self.through_seen).collect()
    }
    fn noise_px(&self) -> f64 {
        self.noise_px
    }
    fn progress(&self) -> &Reporter<'_> {
        self.progress
    }
}

impl Work for Choosing<'_> {
    const PHASE: Phase = Phase::Selection;
    fn step(step: &Step) -> Option<WhenDoes<Self>> {
        match step {
            Step::Selection { when, does } => Some((*when, *does)),
            Step::Singles { .. } => None,
        }
    }
    fn fitted(&self) -> Vec<&WholeFit> {
        self.pairs.fits.iter().filter_map(|(_, _, r)| r.as_ref().ok()).collect()
    }
    fn noise_px(&self) -> f64 {
        self.sel.noise_px
    }
    fn progress(&self) -> &Reporter<'_> {
        self.sel.progress
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_pass_has_its_own_name_and_the_singles_come_first() {
        let names: std::collections::BTreeSet<&str> = PLAN.iter().map(|p| p.name).collect();
        assert_eq!(names.len(), PLAN.len(), "two passes of one name");
        assert!(PLAN.iter().all(|p| p.weight > 0.0 && !p.name.is_empty()));
        let singles = |p: &Pass| matches!(p.step, Step::Singles { .. });
        let first_selection = PLAN.iter().position(|p| !singles(p)).unwrap_or(PLAN.len());
        assert!(PLAN[first_selection..].iter().all(|p| !singles(p)), "phases interleaved");
        // The bar's stretch of each phase is shared out whole.
        assert!(first_selection > 0 && first_selection < PLAN.len());
    }
}
