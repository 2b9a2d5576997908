//! One recording diagnosed with the default options, without the app: its finding, misfits,
//! candidates and the seconds of each stage. A driver for profiling the diagnosis
//! (`docs/speed.md`): `cargo run --release -p ringlab-core --example diagnose_one -- FILE.csv`.
//! `RINGLAB_CANDIDATES=slip,reynolds_drag` offers only the effects named (to time one alone).
//! `RINGLAB_PASSES=1` prints each stage and pass of the plan as it begins, with the wall and
//! CPU seconds since the diagnosis began (the CPU time read from `/proc/self/stat`, Linux only).
//! `RINGLAB_RUNNABLE=1` samples, every 5 ms, how many of the process's threads are runnable
//! (`/proc/self/task/*/stat`, state R: running or waiting for a core) and prints the share of
//! samples with one and with two or more, and from them the wall seconds the same work would
//! take on two cores of its own: on a shared machine the wall time says how busy the others
//! were, the runnable threads say how much of the work could run side by side.

use ringlab_core::analysis::diagnose::{
    DiagnoseError, DiagnoseOptions, DiagnoseProgress, Diagnosis, Finding, diagnose,
};
use ringlab_core::physics::effects::EffectKind;
use ringlab_core::recording::Recording;
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

/// Counts, until `stop`, how often one and how often two or more of this process's threads
/// (the sampler aside) are runnable.
fn sample_runnable(stop: &AtomicBool) -> [u64; 3] {
    let mut counts = [0u64; 3];
    let me = std::fs::read_link("/proc/thread-self").ok();
    while !stop.load(std::sync::atomic::Ordering::Relaxed) {
        let mut running = 0usize;
        if let Ok(dir) = std::fs::read_dir("/proc/self/task") {
            for t in dir.flatten() {
                if me.as_ref().is_some_and(|m| m.ends_with(t.file_name())) {
                    continue;
                }
                let stat = std::fs::read_to_string(t.path().join("stat")).unwrap_or_default();
                let state = stat.rsplit_once(')').and_then(|(_, r)| r.split_whitespace().next());
                running += usize::from(state == Some("R"));
            }
        }
        counts[running.min(2)] += 1;
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    counts
}

/// The wall seconds `cpu` seconds of work would take on two idle cores, where a share `one` of
/// the samples had one thread runnable and `two` two or more: with the cores shared fairly per
/// thread, work goes on at a rate in proportion to the threads runnable (capped at two), so the
/// work of each kind of stretch is in proportion to its share times its threads.
fn two_core_wall(cpu: f64, one: f64, two: f64) -> f64 {
    if one + two <= 0.0 { cpu } else { cpu * (one + two) / (one + 2.0 * two) }
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

/// The diagnosis, its stages and passes printed where `RINGLAB_PASSES` asks.
fn diagnose_with(
    rec: &Recording,
    opts: &DiagnoseOptions,
    cancel: &AtomicBool,
    cpu0: f64,
) -> Result<Diagnosis, DiagnoseError> {
    if std::env::var_os("RINGLAB_PASSES").is_some() {
        diagnose(rec, opts, &pass_printer(Instant::now(), cpu0), cancel)
    } else {
        diagnose(rec, opts, &|_| {}, cancel)
    }
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
        let stop = AtomicBool::new(false);
        let sampler = std::env::var_os("RINGLAB_RUNNABLE").is_some();
        let (d, counts) = std::thread::scope(|scope| {
            let counts = sampler.then(|| scope.spawn(|| sample_runnable(&stop)));
            let d = diagnose_with(&rec, &opts, &cancel, cpu0);
            stop.store(true, std::sync::atomic::Ordering::Relaxed);
            (d, counts.and_then(|c| c.join().ok()))
        });
        let d = d?;
        let cpu = cpu_seconds().map_or(f64::NAN, |c| c - cpu0);
        if let Some([idle, one, two]) = counts {
            let n = (idle + one + two).max(1) as f64;
            let (one, two) = (one as f64 / n, two as f64 / n);
            println!(
                "runnable threads: none {:.0}%, one {:.0}%, two or more {:.0}%: on two idle cores about {:.2} s",
                100.0 * idle as f64 / n,
                100.0 * one,
                100.0 * two,
                two_core_wall(cpu, one, two)
            );
        }
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
