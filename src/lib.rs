//! ringlab: rolling rings and disks on a table, after Jalali, Sarebangholi & Alam,
//! "Terminal retrograde turn of rolling rings".
//!
//! Layout: `physics` is the model and its integrator (pure math); `analysis` sweeps, fits and
//! diagnoses; `config` reads case files; `report` turns runs into JSON and CSV; `plot` draws
//! the report figures.

pub mod analysis;
pub mod config;
pub mod physics;
pub mod plot;
pub mod recording;
pub mod report;
