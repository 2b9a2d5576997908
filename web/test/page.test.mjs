// ringlab's page in a real browser: Debian's Chromium, headless, driven by playwright-core,
// opens the built site (web/build.sh) served on localhost and checks what a class would see:
// the app drawn (against the desktop's picture of the same case and time), a drag change that
// changes the run, the sample recording fitted to the desktop's C, a bad file's clear error.
//
// RINGLAB_SITE (default target/site) and RINGLAB_CLI (default target/release/ringlab, for the
// desktop's answers) say where the two builds are; RINGLAB_SHOTS keeps the screenshots.
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { chromium } from "playwright-core";
import { PNG } from "pngjs";
import { serveSite, launchChromium, openPage, waitFor } from "./browser.mjs";
import { compareImages } from "./images.mjs";

const root = path.resolve(import.meta.dirname, "../..");
const site = process.env.RINGLAB_SITE ?? path.join(root, "target/site");
const cli = process.env.RINGLAB_CLI ?? path.join(root, "target/release/ringlab");
const shots = process.env.RINGLAB_SHOTS ?? fs.mkdtempSync(path.join(os.tmpdir(), "ringlab-page-"));
const VIEW = { width: 1480, height: 920 };

let server;
let browser;

before(async () => {
  for (const f of ["index.html", "ringlab_web.js", "ringlab_web_bg.wasm"]) {
    assert.ok(fs.existsSync(path.join(site, f)), `${site}/${f} is missing: run web/build.sh first`);
  }
  assert.ok(fs.existsSync(cli), `${cli} is missing: cargo build --release first`);
  server = await serveSite(site);
  browser = await launchChromium(chromium);
});

after(async () => {
  await browser?.close();
  server?.close();
  console.log(`screenshots in ${shots}`);
});

const url = (query) => `http://127.0.0.1:${server.address().port}/${query}`;

/** The page at model time `t` of the first run, once the runs have reached it. */
async function pageAt(query, t) {
  const page = await openPage(browser, url(query), VIEW);
  await waitFor(page, (s) => s.runs.length > 0 && s.runs.every((r) => r.last_t >= t || r.finished), 60_000);
  // The states are in; two more frames draw them.
  await page.waitForTimeout(1500);
  return page;
}

// `ringlab diagnose --json`'s finding and improved misfit, as the window shows them.
const desktopFinding = (d) => d.left_out;
const desktopAfter = (d) => d.after.rms_px;

function desktopPicture(args, out) {
  execFileSync(cli, ["render", ...args, "--view", "app", "--width", String(VIEW.width),
    "--height", String(VIEW.height), "--out", out], { stdio: "pipe" });
  return PNG.sync.read(fs.readFileSync(out));
}

for (const backend of ["webgpu", "webgl"]) {
  test(`the page draws the app as the desktop draws it (${backend}, paper ring, t = 60)`, async () => {
    const page = await pageAt(`?backend=${backend}&preset=paper-ring&t=60`, 60);
    const shot = path.join(shots, `page-${backend}-paper-ring-t60.png`);
    await page.screenshot({ path: shot });
    const status = await page.evaluate(() => JSON.parse(window.ringlab.status()));
    assert.equal(status.runs[0].case, "paper-ring");
    assert.ok(Math.abs(status.t - 60) < 1e-9, `the clock at t = ${status.t}, not 60`);
    const desktop = desktopPicture(["--preset", "paper-ring", "--time", "60"], path.join(shots, "desktop-paper-ring-t60.png"));
    const result = compareImages(PNG.sync.read(fs.readFileSync(shot)), desktop, { tiles: [8, 6] });
    console.log(`page (${backend}) against desktop: ${JSON.stringify(result.summary)}`);
    // Text, sliders, plots and the 3D view are egui's and ringlab's own drawing in both; the
    // rasterisers differ (SwiftShader against lavapipe) by a few levels at edges.
    assert.ok(result.summary.meanAbs < 6, `mean difference ${result.summary.meanAbs} levels`);
    assert.ok(result.summary.worstTileMeanAbs < 20, `worst tile ${JSON.stringify(result.worst)}`);
    await page.close();
  });
}

test("ring against disk side by side in the page", async () => {
  const page = await pageAt("?compare=ring-vs-disk&t=60", 60);
  await page.screenshot({ path: path.join(shots, "page-ring-vs-disk-t60.png") });
  const status = await page.evaluate(() => JSON.parse(window.ringlab.status()));
  assert.deepEqual(status.runs.map((r) => r.case), ["paper-ring", "paper-disk-drag"]);
  assert.equal(status.compare, true);
  await page.close();
});

test("a drag change from the page changes the run", async () => {
  const base = await pageAt("?preset=paper-ring&t=60", 60);
  const before = PNG.sync.read(await base.screenshot());
  await base.close();
  const page = await pageAt("?preset=paper-ring&c1=0.2&c2=0.2&c3=0.2&t=60", 60);
  const status = await page.evaluate(() => JSON.parse(window.ringlab.status()));
  assert.deepEqual(status.drag, [0.2, 0.2, 0.2]);
  const shot = path.join(shots, "page-paper-ring-more-drag-t60.png");
  await page.screenshot({ path: shot });
  const changed = compareImages(PNG.sync.read(fs.readFileSync(shot)), before, { tiles: [8, 6] });
  console.log(`more drag against the paper's: ${JSON.stringify(changed.summary)}`);
  // The path, the ring's pose and the plots move: some tiles change a lot.
  assert.ok(changed.summary.worstTileMeanAbs > 10, "the picture did not change with the drag");
  await page.close();
});

test("the sample recording fitted in the page gives the desktop's C", async () => {
  const desktop = JSON.parse(execFileSync(cli, ["fit", path.join(root, "tests/data/sample-ring.csv"), "--json"]).toString());
  const page = await openPage(browser, url("?recording=sample-ring.csv&fit=1"), VIEW);
  // The fit runs in a worker: the page answers meanwhile, and shows the fit's progress.
  const seen = [];
  const status = await waitFor(page, (s) => {
    if (s.fitting) seen.push(s.fitting.text);
    return s.fit !== null || s.error !== null;
  }, 240_000);
  assert.ok(seen.length > 0, "the page never answered while the fit ran");
  assert.equal(status.error, null);
  await page.waitForTimeout(1000);
  await page.screenshot({ path: path.join(shots, "page-sample-fitted.png") });
  const shown = (x) => x.toPrecision(4);
  console.log(`progress seen while fitting: ${seen.length} times, last "${seen.at(-1)}"`);
  console.log(`C in the page ${status.fit.c}, on the desktop ${desktop.c} (${status.fit.compute_seconds.toFixed(1)} s in the page)`);
  assert.deepEqual(status.fit.c.map(shown), desktop.c.map(shown));
  await page.close();
});

test("the sample recording diagnosed in the page gives the desktop's answer", async () => {
  const desktop = JSON.parse(execFileSync(cli, ["diagnose", path.join(root, "tests/data/sample-ring.csv"), "--json"]).toString());
  const page = await openPage(browser, url("?recording=sample-ring.csv&diagnose=1"), VIEW);
  const seen = [];
  const status = await waitFor(page, (s) => {
    if (s.diagnosing) seen.push(s.diagnosing.text);
    return s.diagnosis !== null || s.error !== null;
  }, 300_000);
  assert.equal(status.error, null);
  assert.ok(seen.length > 0, "the page never answered while the diagnosis ran");
  await page.waitForTimeout(1000);
  await page.screenshot({ path: path.join(shots, "page-sample-diagnosed.png") });
  const d = status.diagnosis;
  console.log(`diagnosis in the page: ${JSON.stringify(d)}; desktop: ${desktop.left_out} at ${desktop.after.rms_px} px`);
  assert.equal(d.finding, desktopFinding(desktop));
  assert.equal(d.after_px.toFixed(3), desktopAfter(desktop).toFixed(3));
  await page.close();
});

test("a bad file gets the desktop's clear error in the page, and nothing panics", async () => {
  const page = await openPage(browser, url(""), VIEW);
  await waitFor(page, (s) => s.running, 60_000);
  const status = await page.evaluate(() => {
    window.ringlab.open_file("broken.csv", new TextEncoder().encode("# ringlab-recording v1\n# fps = banana\n"));
    return JSON.parse(window.ringlab.status());
  });
  assert.match(status.error ?? "", /broken\.csv/);
  await page.waitForTimeout(500);
  await page.screenshot({ path: path.join(shots, "page-bad-file.png") });
  assert.equal(await page.evaluate(() => window.ringlab.panic_message() ?? null), null);
  await page.close();
});
