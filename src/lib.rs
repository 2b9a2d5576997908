//! ringlab, the app: the live run of the model on a thread (`sim`), what the window does with
//! a recording (`session`), the renderer (`render`, wgpu) and the window (`ui`, egui); the
//! command line is the binary's (`src/cli`). The physics, recordings, fit and diagnosis are the
//! `ringlab-core` crate's, re-exported here under their own names.
//!
//! Layers, lowest first: core < sim, session < render < ui < export < cli (`export` makes
//! videos, pictures and CSV files of runs through render and ui). `render` knows nothing of
//! `ui`; `sim` and `session` know nothing of egui. `ARCHITECTURE.md` maps the crates, the
//! threads and the data flow.

pub use ringlab_core::{analysis, config, film, physics, plot, recording, report};

pub mod export;
pub mod render;
pub mod session;
pub mod sim;
pub mod ui;
