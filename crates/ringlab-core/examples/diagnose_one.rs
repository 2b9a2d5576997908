//! One recording diagnosed with the default options, without the app: its finding, misfits,
//! candidates and the seconds of each stage. A driver for profiling the diagnosis
//! (`docs/speed.md`): `cargo run --release -p ringlab-core --example diagnose_one -- FILE.csv`.
//! `RINGLAB_CANDIDATES=slip,reynolds_drag` offers only the effects named (to time one alone).

use ringlab_core::analysis::diagnose::{DiagnoseOptions, Finding, diagnose};
use ringlab_core::physics::effects::EffectKind;
use ringlab_core::recording::import::{ImportOptions, import};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

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
        let d = diagnose(&rec, &opts, &|_| {}, &cancel)?;
        let named = match &d.finding {
            Finding::Named(k) => k.iter().map(|k| k.name()).collect::<Vec<_>>().join(" + "),
            f => f.name().to_string(),
        };
        println!(
            "{}: {} frames; {named}; misfit {:.4} -> {:.4} px; noise {:.4} px; {:.2} s",
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
