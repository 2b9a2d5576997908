//! ringlab's core: rolling rings and disks on a table, after Jalali, Sarebangholi & Alam,
//! "Terminal retrograde turn of rolling rings", without a window or a GPU.
//!
//! Layers, lowest first: `physics` (the model and its integrator, pure math); `recording`
//! (recordings read, written, imported from trackers, synthesized, their motion recovered);
//! `analysis` (sweeps, the fit, the diagnosis); `config` (case files), `report` (runs as JSON
//! and CSV) and `plot` (figures as PNG). The app crate `ringlab` adds the live run, the
//! renderer, the window and the command line.

pub mod analysis;
pub mod config;
pub mod film;
pub mod physics;
pub mod plot;
pub mod recording;
pub mod report;
