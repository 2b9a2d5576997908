// ringlab's web worker: a fit or a diagnosis off the page's thread, so that the window keeps
// drawing. The page (session/page_worker.rs) posts {fit: RECORDING_V1_TEXT} or {diagnose: ...};
// this answers with progress messages {progress: TEXT, fraction}, then {result: RON} or
// {error: MESSAGE}. The page ends the worker to cancel.
import init, { work } from "./ringlab_web.js";

const ready = init();
self.onmessage = async (e) => {
  try {
    await ready;
    const kind = "fit" in e.data ? "fit" : "diagnose";
    const result = work(kind, e.data[kind], (fraction, text) => self.postMessage({ progress: text, fraction }));
    self.postMessage({ result });
  } catch (err) {
    self.postMessage({ error: String(err) });
  }
};
