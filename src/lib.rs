//! ringlab: rolling rings and disks on a table, after Jalali, Sarebangholi & Alam,
//! "Terminal retrograde turn of rolling rings".
//!
//! Layout: `physics` is the model and its integrator (pure math); `analysis` sweeps, fits and
//! diagnoses; `config` reads case files; `report` turns runs into JSON and CSV; `plot` draws
//! the report figures; `sim` runs the model on a thread for the live view; `render` draws the
//! scene (wgpu); `ui` is the window (egui); `export` makes videos, pictures and CSV files of
//! runs through render and ui. physics never uses sim, render or ui.

pub mod analysis;
pub mod config;
pub mod export;
pub mod physics;
pub mod plot;
pub mod recording;
pub mod render;
pub mod report;
pub mod sim;
pub mod ui;
