//! The command-line commands (the binary's side: anyhow errors, printing, files).

pub mod bench;
pub mod bench_view;
pub mod case_args;
pub mod render;
pub mod simulate;
pub mod sweep;
