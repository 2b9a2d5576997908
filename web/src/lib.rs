//! ringlab in a web page: the desktop's app (`ringlab::ui`) started by eframe's web runner on
//! the page's canvas. wgpu draws through WebGPU where the browser has it, WebGL2 otherwise. The
//! page has one thread: the integrator runs in slices between frames (`ringlab::sim`), and the
//! fit and the diagnosis in a web worker (`worker.js`, `fit_in_worker`).

#[cfg(target_arch = "wasm32")]
mod page;
#[cfg(target_arch = "wasm32")]
mod status;
#[cfg(target_arch = "wasm32")]
pub use page::*;
