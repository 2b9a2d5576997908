// The browser test's plumbing: the built site served on localhost, Debian's Chromium started
// headless, a page opened and waited on through the app's own status (`window.ringlab`).
import fs from "node:fs";
import http from "node:http";
import path from "node:path";

const TYPES = {
  ".html": "text/html; charset=utf-8",
  ".js": "text/javascript; charset=utf-8",
  ".wasm": "application/wasm",
  ".csv": "text/csv; charset=utf-8",
  ".png": "image/png",
};

/** A static server of `dir` on 127.0.0.1 (a free port), as any web server hosts the site. */
export function serveSite(dir) {
  const server = http.createServer((req, res) => {
    const name = decodeURIComponent(new URL(req.url, "http://x").pathname);
    const file = path.join(dir, name.endsWith("/") ? name + "index.html" : name);
    if (!file.startsWith(dir) || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
      res.writeHead(404).end("not found");
      return;
    }
    res.writeHead(200, { "content-type": TYPES[path.extname(file)] ?? "application/octet-stream" });
    fs.createReadStream(file).pipe(res);
  });
  return new Promise((resolve) => server.listen(0, "127.0.0.1", () => resolve(server)));
}

/** Debian's Chromium (CHROMIUM overrides the path), headless, with a software GPU. */
export function launchChromium(chromium) {
  const executablePath = process.env.CHROMIUM ?? "/usr/bin/chromium";
  if (!fs.existsSync(executablePath)) {
    throw new Error(`${executablePath} is missing: apt-get install chromium`);
  }
  return chromium.launch({
    executablePath,
    headless: true,
    args: [
      "--no-sandbox",
      "--no-first-run",
      // This machine reaches no network: no background fetches, updates or sync.
      "--disable-background-networking",
      "--disable-component-update",
      "--disable-sync",
      "--disable-quic",
      // No GPU here: WebGL2 (ANGLE) and WebGPU (Dawn on Vulkan) on SwiftShader, Chromium's
      // software rasteriser; without the Vulkan ones a WebGPU canvas stays blank headless.
      "--use-angle=swiftshader",
      "--enable-unsafe-swiftshader",
      "--enable-unsafe-webgpu",
      "--enable-features=Vulkan",
      "--use-vulkan=swiftshader",
      "--use-webgpu-adapter=swiftshader",
      "--ignore-gpu-blocklist",
    ],
  });
}

/** A fresh page (no stored settings) at `url`, its console's errors and crashes kept. */
export async function openPage(browser, url, viewport) {
  const context = await browser.newContext({ viewport, deviceScaleFactor: 1 });
  const page = await context.newPage();
  page.errors = [];
  page.on("console", (m) => {
    if (m.type() === "error") page.errors.push(m.text());
  });
  page.on("pageerror", (e) => page.errors.push(String(e)));
  await page.goto(url);
  await page.waitForFunction(() => window.ringlabReady === true || document.querySelector("#status.error"), null, { timeout: 120_000 });
  const failed = await page.evaluate(() => document.querySelector("#status.error")?.textContent ?? null);
  if (failed) throw new Error(`the page did not start: ${failed}\n${page.errors.join("\n")}`);
  return page;
}

/** Polls the app's status until `done(status)`; returns that status. */
export async function waitFor(page, done, timeoutMs) {
  const start = Date.now();
  for (;;) {
    const status = await page.evaluate(() => JSON.parse(window.ringlab.status()));
    if (done(status)) return status;
    const panic = await page.evaluate(() => window.ringlab.panic_message() ?? null);
    if (panic) throw new Error(`the app panicked: ${panic}`);
    if (Date.now() - start > timeoutMs) {
      throw new Error(`timed out after ${timeoutMs} ms; status ${JSON.stringify(status)}; console: ${page.errors.join("\n")}`);
    }
    await page.waitForTimeout(250);
  }
}
