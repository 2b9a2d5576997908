// The page's figures for docs/web.md: the frame time over 30 s of a run playing (median and
// p90 of requestAnimationFrame's intervals), and the paper's ring run to its end in the page
// against the same run natively (`ringlab simulate --preset paper-ring --json`).
// Usage: node web/test/measure.mjs [SECONDS] (after web/build.sh and cargo build --release).
import { execFileSync } from "node:child_process";
import path from "node:path";
import { chromium } from "playwright-core";
import { serveSite, launchChromium, openPage, waitFor } from "./browser.mjs";

const root = path.resolve(import.meta.dirname, "../..");
const site = process.env.RINGLAB_SITE ?? path.join(root, "target/site");
const cli = process.env.RINGLAB_CLI ?? path.join(root, "target/release/ringlab");
const seconds = Number(process.argv[2] ?? 30);

const quantile = (xs, q) => {
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.min(s.length - 1, Math.floor(q * s.length))];
};

const server = await serveSite(site);
const browser = await launchChromium(chromium);
try {
  const url = `http://127.0.0.1:${server.address().port}/?preset=paper-ring&t=0&play=1`;
  const opened = Date.now();
  const page = await openPage(browser, url, { width: 1480, height: 920 });
  // From the request of the page to the app running (the .wasm fetched, compiled, started).
  const startMs = Date.now() - opened;
  await waitFor(page, (s) => s.playing, 30_000);
  const intervals = await page.evaluate((ms) => new Promise((resolve) => {
    const out = [];
    let last = performance.now();
    const end = last + ms;
    const frame = (now) => {
      out.push(now - last);
      last = now;
      if (now < end) requestAnimationFrame(frame); else resolve(out);
    };
    requestAnimationFrame(frame);
  }), seconds * 1000);
  const status = await page.evaluate(() => JSON.parse(window.ringlab.status()));
  const runs = [];
  for (let i = 0; i < 5; i++) runs.push(JSON.parse(await page.evaluate(() => window.ringlab.bench_paper_ring())));
  const native = [];
  for (let i = 0; i < 5; i++) {
    native.push(JSON.parse(execFileSync(cli, ["simulate", "--preset", "paper-ring", "--json"]).toString()));
  }
  const pageMs = Math.min(...runs.map((r) => r.ms));
  const nativeMs = Math.min(...native.map((r) => r.compute_seconds * 1e3));
  console.log(JSON.stringify({
    start_ms: startMs,
    frames: intervals.length,
    frame_ms: { median: +quantile(intervals, 0.5).toFixed(2), p90: +quantile(intervals, 0.9).toFixed(2), max: +Math.max(...intervals).toFixed(2) },
    played_to_seconds: status.seconds,
    paper_ring: {
      page: { t_end: runs[0].t_end, ms: +pageMs.toFixed(2) },
      native: { t_end: native[0].t_end, ms: +nativeMs.toFixed(2) },
      page_over_native: +(pageMs / nativeMs).toFixed(2),
    },
  }, null, 2));
  await page.close();
} finally {
  await browser.close();
  server.close();
}
