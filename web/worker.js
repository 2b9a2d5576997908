// ringlab's web worker: a fit off the page's thread, so that the window keeps drawing. The
// page (session/page_worker.rs) posts {fit: RECORDING_V1_TEXT}; this answers with progress
// messages {progress: TEXT, fraction}, then {result: FIT_RON} or {error: MESSAGE}.
import init, { fit_recording } from "./ringlab_web.js";

const ready = init();
self.onmessage = async (e) => {
  try {
    await ready;
    const result = fit_recording(e.data.fit, (fraction, text) => self.postMessage({ progress: text, fraction }));
    self.postMessage({ result });
  } catch (err) {
    self.postMessage({ error: String(err) });
  }
};
