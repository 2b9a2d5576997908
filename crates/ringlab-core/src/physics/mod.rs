//! The paper's pure-rolling model of a ring or disk on a table (eqs. 3-5), its integrator,
//! and the analysis of a run. Pure math: nalgebra and std only, no GPU, UI or threads.

pub mod body;
mod contact;
pub mod effects;
pub mod frame;
pub mod integrator;
pub mod losses;
pub mod model;
pub mod motion;
pub mod painleve;
pub mod paper;
pub mod run;
pub mod sample;
pub mod slip;
pub mod speed;
pub mod trig;
pub mod units;

pub use body::{Body, ParamError, Shape};
pub use effects::EffectKind;
pub use model::{Effects, Initial, Model, ReynoldsDrag, STATE_LEN, SlipStart, StateVec};
pub use run::{
    EndReason, Interval, RunOptions, RunSummary, Sample, Simulation, TurnKind, TurningPoint,
    simulate,
};
pub use units::{Conversion, Units};
