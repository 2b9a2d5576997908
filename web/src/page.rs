//! The page's entry points, called from `index.html`'s script: the app started on a canvas,
//! and a handle that the page (and the browser test) drives it through: a preset, the drag, the
//! clock, a recording's bytes, a fit, and what the app shows now as JSON.

use ringlab::ui::RinglabApp;
use ringlab::ui::controls::Change;
use std::sync::Arc;
use wasm_bindgen::prelude::*;

/// The running app, for the page's script.
#[wasm_bindgen]
pub struct WebHandle {
    runner: eframe::WebRunner,
}

#[wasm_bindgen]
impl WebHandle {
    #[wasm_bindgen(constructor)]
    pub fn new() -> WebHandle {
        WebHandle { runner: eframe::WebRunner::new() }
    }

    /// Starts the app on the canvas with this id; settles once it runs (or with the reason
    /// it could not: no WebGPU nor WebGL2, no such canvas). `backend`: "webgpu" or "webgl"
    /// alone (anything else: WebGPU where the browser has it, WebGL2 otherwise).
    pub async fn start(&self, canvas_id: &str, backend: Option<String>) -> Result<(), JsValue> {
        let document = web_sys::window()
            .and_then(|w| w.document())
            .ok_or_else(|| JsValue::from_str("no document: ringlab must run in a page"))?;
        let canvas = document
            .get_element_by_id(canvas_id)
            .ok_or_else(|| JsValue::from_str(&format!("no element #{canvas_id} in the page")))?
            .dyn_into::<web_sys::HtmlCanvasElement>()
            .map_err(|_| JsValue::from_str(&format!("#{canvas_id} is not a canvas")))?;
        let mut options = eframe::WebOptions::default();
        let backends = match backend.as_deref() {
            Some("webgl") => Some(eframe::wgpu::Backends::GL),
            Some("webgpu") => Some(eframe::wgpu::Backends::BROWSER_WEBGPU),
            _ => None,
        };
        if let Some(backends) = backends {
            let mut setup = eframe::egui_wgpu::WgpuSetupCreateNew::without_display_handle();
            setup.instance_descriptor.backends = backends;
            options.wgpu_options.wgpu_setup = eframe::egui_wgpu::WgpuSetup::CreateNew(setup);
        }
        self.runner
            .start(canvas, options, Box::new(|cc| Ok(Box::new(ringlab::ui::create_app(cc, None)))))
            .await
    }

    /// Loads a preset (`presets` lists them) into the run; false where there is none so named.
    pub fn load_preset(&self, name: &str) -> bool {
        let known = ringlab::config::preset_names().contains(&name);
        self.with_app(|app| {
            if known {
                app.load_preset(name, false);
            }
        });
        known
    }

    /// The paper's ring and its disk-like drag side by side.
    pub fn ring_vs_disk(&self) {
        self.with_app(RinglabApp::ring_vs_disk);
    }

    /// Sets the drag coefficients as the sliders do (the run restarts, or goes on from now
    /// where "continue on change" is set).
    pub fn set_drag(&self, c1: f64, c2: f64, c3: f64) {
        self.with_app(|app| {
            app.settings.case.drag.c = [c1, c2, c3];
            app.apply_change(Change::Drag);
        });
    }

    /// Moves the clock to model time `t` of the first run (as `ringlab render --time`),
    /// playing from there or paused.
    pub fn seek(&self, t: f64, playing: bool) {
        self.with_app(|app| {
            app.seek_model_time(t);
            if playing { app.player.play() } else { app.player.pause() }
        });
    }

    /// The paper's ring run to its end here, in the page (the same run as `ringlab simulate
    /// --preset paper-ring`): its end time and the milliseconds it took, as JSON.
    pub fn bench_paper_ring(&self) -> Result<String, JsValue> {
        crate::status::bench_paper_ring().map_err(|e| JsValue::from_str(&e))
    }

    /// Opens a recording (format v1 or a lab tracker's file) from its bytes, as a file dropped
    /// on the page is.
    pub fn open_file(&self, name: &str, bytes: Vec<u8>) {
        let bytes: Arc<[u8]> = bytes.into();
        self.with_app(|app| app.open_recording_bytes(name, bytes));
    }

    /// Starts a fit of the open recording (the Recording tab's Fit).
    pub fn fit(&self) {
        self.with_app(|app| app.recording.start_fit());
    }

    /// Starts a diagnosis of the open recording (the Diagnose tab's Diagnose).
    pub fn diagnose(&self) {
        self.with_app(|app| app.recording.start_diagnose());
    }

    /// What the app shows now, as JSON: the clock, the runs, the drag, the recording and its
    /// fit (the browser test reads it; so may a page that embeds ringlab).
    pub fn status(&self) -> String {
        self.runner.app_mut::<RinglabApp>().map_or_else(
            || r#"{"running":false}"#.to_string(),
            |app| crate::status::status_json(&app),
        )
    }

    /// The app's panic, if it had one (the page shows it instead of a frozen canvas).
    pub fn panic_message(&self) -> Option<String> {
        self.runner.panic_summary().map(|p| p.message())
    }

    fn with_app(&self, f: impl FnOnce(&mut RinglabApp)) {
        if let Some(mut app) = self.runner.app_mut::<RinglabApp>() {
            f(&mut app);
        }
    }
}

impl Default for WebHandle {
    fn default() -> Self {
        WebHandle::new()
    }
}

/// The worker's side (`worker.js`): `work` is "fit" or "diagnose", the recording format v1
/// text, progress to `progress(fraction, text)`; the result as `session::page_worker` reads it.
#[wasm_bindgen]
pub fn work(work: &str, recording: &str, progress: &js_sys::Function) -> Result<String, JsValue> {
    use ringlab::analysis::diagnose::{DiagnoseOptions, DiagnoseProgress, diagnose};
    use ringlab::analysis::fit::{FitOptions, FitProgress, fit};
    use ringlab::session::{describe_fit_progress, page_worker};
    let js = |e: String| JsValue::from_str(&e);
    let rec = ringlab::recording::read::parse_recording(
        recording.as_bytes(),
        std::path::Path::new("recording"),
    )
    .map_err(|e| js(e.to_string()))?;
    let tell = |fraction: f32, text: String| {
        let _ = progress.call2(&JsValue::NULL, &fraction.into(), &text.into());
    };
    // The page ends the worker to cancel: nothing here is ever asked to stop.
    let never = std::sync::atomic::AtomicBool::new(false);
    match work {
        "fit" => {
            let report = |p: &FitProgress| {
                let p = describe_fit_progress(p);
                tell(p.fraction, p.text);
            };
            let r = fit(&rec, &FitOptions::default(), &report, &never)
                .map_err(|e| js(e.to_string()))?;
            page_worker::result_text(&r).map_err(js)
        }
        "diagnose" => {
            let report = |p: &DiagnoseProgress| tell(p.fraction as f32, p.message.clone());
            let d = diagnose(&rec, &DiagnoseOptions::default(), &report, &never)
                .map_err(|e| js(e.to_string()))?;
            page_worker::result_text(&d).map_err(js)
        }
        other => Err(js(format!("no work named {other:?} (fit or diagnose)"))),
    }
}
