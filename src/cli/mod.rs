//! The command-line commands (the binary's side: anyhow errors, printing, files).

pub mod bench;
pub mod case_args;
pub mod render;
pub mod simulate;
pub mod sweep;
