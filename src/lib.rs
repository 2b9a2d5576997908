//! ringlab: rolling rings and disks on a table, after Jalali, Sarebangholi & Alam,
//! "Terminal retrograde turn of rolling rings".
//!
//! Layout: `physics` is the model and its integrator (pure math); `recording` reads, writes,
//! recovers and synthesizes recordings; `analysis` sweeps, fits and diagnoses; `config` reads
//! case files; `report` turns runs into JSON and CSV; `plot` draws the report figures; `sim`
//! runs the model on a thread for the live view and the window's other work off its thread;
//! `render` draws the scene (wgpu); `ui` is the window (egui). physics never uses sim, render
//! or ui. `ARCHITECTURE.md` maps the layers, the threads and the data flow.

pub mod analysis;
pub mod config;
pub mod physics;
pub mod plot;
pub mod recording;
pub mod render;
pub mod report;
pub mod sim;
pub mod ui;
