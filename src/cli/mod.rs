//! The command-line commands (the binary's side: anyhow errors, printing, files).

pub mod bench;
pub mod bench_recording;
pub mod bench_scipy;
pub mod bench_track;
pub mod bench_view;
pub mod case_args;
pub mod diagnose;
pub mod diagnose_args;
pub mod diagnose_batch;
pub mod diagnose_bench;
pub mod diagnose_report;
pub mod effect_args;
pub mod film_args;
pub mod fit;
pub mod import;
pub mod import_args;
pub mod progress;
pub mod recover;
pub mod render;
pub mod render_film;
pub mod shard;
pub mod simulate;
pub mod sweep;
pub mod synth;
pub mod track;
pub mod windows_console;
