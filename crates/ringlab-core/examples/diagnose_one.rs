//! One recording diagnosed with the default options, without the app: its finding, misfits,
//! candidates and the seconds of each stage. A driver for profiling the diagnosis
//! (`docs/speed.md`): `cargo run --release -p ringlab-core --example diagnose_one -- FILE.csv`.
//! `RINGLAB_CANDIDATES=slip,reynolds_drag` offers only the effects named (to time one alone).
//! `RINGLAB_PASSES=1` prints each stage and pass of the plan as it begins, with the wall and
//! CPU seconds since the diagnosis began (the CPU time read from `/proc/self/stat`, Linux only).

use ringlab_core::analysis::diagnose::{DiagnoseOptions, DiagnoseProgress, Finding, diagnose};
use ringlab_core::physics::effects::EffectKind;
use ringlab_core::recording::import::{ImportOptions, import};
use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// The CPU seconds (user and system) this process has used, where `/proc` tells them.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The fields after the command's name in parentheses (which may hold spaces).
    let rest = stat.rsplit_once(')')?.1;
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| fields.get(i).and_then(|v| v.parse::<f64>().ok());
    // utime and stime, fields 14 and 15 of proc(5), in clock ticks of 1/100 s.
    Some((ticks(11)? + ticks(12)?) / 100.0)
}

/// Prints each stage and pass as it begins (once), with the seconds since `start`.
fn pass_printer(start: Instant, cpu0: f64) -> impl Fn(&DiagnoseProgress) + Sync {
    let last = Mutex::new(String::new());
    move |p: &DiagnoseProgress| {
        let what = match p.pass {
            Some(name) => format!("pass: {name}"),
            None => format!("stage: {}", p.stage.describe()),
        };
        let mut last = last.lock().unwrap_or_else(|e| e.into_inner());
        if *last != what {
            let cpu = cpu_seconds().map_or(f64::NAN, |c| c - cpu0);
            let wall = start.elapsed().as_secs_f64();
            println!("  [{wall:7.2} s wall {cpu:7.2} s cpu] {what}");
            *last = what;
        }
    }
}

/// The effect named `name`, as `ringlab diagnose --candidates` spells it.
fn effect(name: &str) -> Result<EffectKind, String> {
    EffectKind::ALL.into_iter().find(|k| k.name() == name).ok_or_else(|| {
        let names: Vec<&str> = EffectKind::ALL.iter().map(|k| k.name()).collect();
        format!("RINGLAB_CANDIDATES: no effect '{name}' (one of {})", names.join(", "))
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let files: Vec<PathBuf> = std::env::args().skip(1).map(PathBuf::from).collect();
    if files.is_empty() {
        return Err("usage: diagnose_one FILE.csv [FILE.csv ...]".into());
    }
    for file in &files {
        let rec = import(std::slice::from_ref(file), None, &ImportOptions::default())?.recording;
        let cancel = AtomicBool::new(false);
        let mut opts = DiagnoseOptions::default();
        if let Ok(list) = std::env::var("RINGLAB_CANDIDATES") {
            opts.candidates = list.split(',').map(effect).collect::<Result<_, _>>()?;
        }
        let cpu0 = cpu_seconds().unwrap_or(0.0);
        let d = if std::env::var_os("RINGLAB_PASSES").is_some() {
            diagnose(&rec, &opts, &pass_printer(Instant::now(), cpu0), &cancel)?
        } else {
            diagnose(&rec, &opts, &|_| {}, &cancel)?
        };
        let cpu = cpu_seconds().map_or(f64::NAN, |c| c - cpu0);
        let named = match &d.finding {
            Finding::Named(k) => k.iter().map(|k| k.name()).collect::<Vec<_>>().join(" + "),
            f => f.name().to_string(),
        };
        println!(
            "{}: {} frames; {named}; misfit {:.4} -> {:.4} px; noise {:.4} px; {:.2} s ({cpu:.2} s of CPU)",
            file.display(),
            d.frames,
            d.before.rms_px,
            d.after.rms_px,
            d.noise_px,
            d.compute_seconds
        );
        for c in &d.candidates {
            println!(
                "  {:<20} {:>9.4} px  {:>+10.1}  ({:.2} s)",
                c.effect.name(),
                c.rms_px,
                c.delta_score,
                c.seconds
            );
        }
        for p in &d.pairs {
            println!("  pair {} + {}: {:.4} px ({:.2} s)", p.first, p.second, p.rms_px, p.seconds);
        }
        for (stage, s) in &d.stage_seconds {
            println!("  stage {stage}: {s:.2} s");
        }
    }
    Ok(())
}
