//! What the app shows, as JSON for the page's script and the browser test: numbers only, in
//! the units the window shows them.

use ringlab::ui::RinglabApp;
use serde_json::{Value, json};

pub fn status_json(app: &RinglabApp) -> String {
    let runs: Vec<Value> = app
        .tracks()
        .iter()
        .map(|t| {
            json!({
                "case": t.case().name,
                "samples": t.samples().len(),
                "last_t": t.last_time(),
                "finished": t.is_finished(),
                "t_end": t.end().map(|e| e.t_end),
            })
        })
        .collect();
    let recording = app
        .recording
        .loaded()
        .map(|l| json!({ "name": l.name(), "frames": l.frames().len(), "fps": l.fps() }));
    let fit = app.recording.fitted().map(|f| {
        json!({ "c": f.result.c, "c_sigma": f.result.c_sigma, "rms_px": f.result.rms_px,
                "compute_seconds": f.result.compute_seconds })
    });
    let diagnosis = app.recording.diagnosed().map(|d| {
        let r = &d.result;
        json!({ "finding": r.finding.name(),
                "named": r.finding.named().iter().map(|k| k.name()).collect::<Vec<_>>(),
                "before_px": r.before.rms_px, "after_px": r.after.rms_px, "noise_px": r.noise_px,
                "compute_seconds": r.compute_seconds })
    });
    json!({
        "running": true,
        "seconds": app.player.seconds(),
        "t": app.tracks().first().map(|t| app.player.seconds() / t.case().units.time_s),
        "playing": app.player.is_playing(),
        "drag": app.settings.case.drag.c,
        "compare": app.settings.compare,
        "runs": runs,
        "recording": recording,
        "fitting": app.recording.fit_progress().map(|p| json!({"fraction": p.fraction, "text": p.text})),
        "fit": fit,
        "diagnosing": app.recording.diagnose_progress().map(|p| json!({"fraction": p.fraction, "text": p.text})),
        "diagnosis": diagnosis,
        "error": app.recording.error,
        "note": app.recording.note,
        "last_restart_ms": app.last_restart_latency.map(|d| d.as_secs_f64() * 1e3),
    })
    .to_string()
}

/// The paper's ring to its end, timed with the page's clock (`performance.now`).
pub fn bench_paper_ring() -> Result<String, String> {
    let case = ringlab::config::load_preset("paper-ring").map_err(|e| e.to_string())?.build()?;
    let clock = web_time::Instant::now();
    let sim = ringlab::physics::Simulation::new(case.model, &case.initial, case.opts)
        .map_err(|e| e.to_string())?;
    let mut samples = 0usize;
    let summary = sim.run(&mut |_| samples += 1);
    let ms = clock.elapsed().as_secs_f64() * 1e3;
    Ok(json!({ "t_end": summary.t_end, "samples": samples, "ms": ms }).to_string())
}
