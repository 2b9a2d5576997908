//! What the integrator thread sends the UI over the channel ([`super::worker`]), and what the
//! UI's [`super::track::Track`] keeps of it.

use crate::physics::{EndReason, Interval, Sample, TurningPoint};

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub struct RunEnd {
    pub reason: EndReason,
    pub t_end: f64,
    /// Exact intervals where the model is invalid (from this run's start).
    pub lift_off: Vec<Interval>,
    pub slip: Vec<Interval>,
}

/// What the worker sends. States of one run arrive in time order, one per output time
/// `t0 + k dt`, none missing; a turning point arrives before the first state after it.
#[derive(Clone, Debug, PartialEq)]
pub enum Event {
    Started { run: u64, start: Sample },
    State { run: u64, sample: Sample },
    Turn { run: u64, point: TurningPoint },
    Ended { run: u64, end: RunEnd },
    Failed { run: u64, message: String },
}

impl Event {
    pub fn run(&self) -> u64 {
        match self {
            Event::Started { run, .. }
            | Event::State { run, .. }
            | Event::Turn { run, .. }
            | Event::Ended { run, .. }
            | Event::Failed { run, .. } => *run,
        }
    }
}
