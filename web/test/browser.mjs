// Drives the rbtrack page in headless Chromium: serves the built page and a folder of
// lossless frames over HTTP, loads the page, tracks the frames from a box, runs the
// firmware's scene, writes the boxes (the host tool's --per-frame CSV) and a screenshot,
// and prints one JSON line of figures.
//
//   node web/test/browser.mjs --dist web/dist --frames DIR --box x,y,w,h [--tracker 0|1|2]
//       [--particles N] [--out DIR]
//   node web/test/browser.mjs --dist web/dist --video FILE --box x,y,w,h [--tracker 0|1|2]
//       [--particles N] [--out DIR]
//   node web/test/browser.mjs --dist web/dist --webcam SECONDS --box x,y,w,h ...
//
// --frames: PNG frames, tracked in name order; --box: the first frame's box, 0-based px;
// --tracker: 0 the RBPF, 1 the colour PF, 2 the correlation filter (default). With --video instead, the page is used
// as a person would: the file opened, the box dragged with the mouse, Track pressed, the
// video played to its end; the figures then include the frames tracked. With --webcam, the
// same on Chromium's fake camera (a test pattern), tracked for that many seconds. The
// browser is $CHROMIUM, else /usr/bin/chromium.
import { createServer } from "node:http";
import { readFile, readdir, mkdir, writeFile } from "node:fs/promises";
import { extname, join, resolve } from "node:path";
import puppeteer from "puppeteer-core";

const args = Object.fromEntries(
  process.argv.slice(2).reduce((pairs, a, i, all) => {
    if (a.startsWith("--")) pairs.push([a.slice(2), all[i + 1]]);
    return pairs;
  }, []),
);
for (const required of ["dist", "box"]) {
  if (!args[required]) throw new Error(`--${required} is required`);
}
if ([args.frames, args.video, args.webcam].filter(Boolean).length !== 1) {
  throw new Error("give one of --frames, --video and --webcam");
}
const out = resolve(args.out ?? "out/browser");
const dist = resolve(args.dist);
const framesDir = resolve(args.frames ?? ".");

const TYPES = { ".html": "text/html", ".js": "text/javascript", ".wasm": "application/wasm", ".png": "image/png" };
const server = createServer(async (req, res) => {
  const path = decodeURIComponent(new URL(req.url, "http://x").pathname);
  const file = path.startsWith("/frames/")
    ? join(framesDir, path.slice("/frames/".length))
    : join(dist, path === "/" ? "index.html" : path);
  try {
    const body = await readFile(file);
    res.writeHead(200, { "content-type": TYPES[extname(file)] ?? "application/octet-stream" });
    res.end(body);
  } catch {
    res.writeHead(404).end();
  }
});
await new Promise((ok) => server.listen(0, "127.0.0.1", ok));
const base = `http://127.0.0.1:${server.address().port}`;

const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
  headless: true,
  args: [
    "--no-sandbox",
    "--disable-dev-shm-usage",
    "--use-fake-device-for-media-stream",
    "--use-fake-ui-for-media-stream",
  ],
});
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1000, height: 640 });
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  page.on("console", (m) => m.type() === "error" && errors.push(m.text()));
  await page.goto(`${base}/`, { waitUntil: "load" });
  await page.waitForFunction(() => window.rbtrackReady === true, { timeout: 60_000 });
  const box = args.box.split(",").map(Number);
  const tracker = String(args.tracker ?? 2);
  const particles = String(args.particles ?? 100);
  let run;
  let frames;
  if (args.video) {
    run = await trackVideo(page, resolve(args.video), box, tracker, particles);
    frames = run.steps + 1;
  } else if (args.webcam) {
    run = await trackWebcam(page, Number(args.webcam), box, tracker, particles);
    frames = run.steps + 1;
  } else {
    const files = (await readdir(framesDir)).filter((f) => f.endsWith(".png")).sort();
    frames = files.length;
    run = await page.evaluate((spec) => window.rbtrackRun(spec), {
      frames: files.map((f) => `/frames/${f}`),
      box,
      tracker: Number(tracker),
      particles: Number(particles),
    });
  }
  const checksum = await page.evaluate(() => window.rbtrackChecksum());
  const cfChecksum = await page.evaluate(() => window.rbtrackCfChecksum());

  await page.evaluate(
    ([v, cf]) => {
      document.getElementById("checksum-out").textContent = `checksum ${v}, correlation filter ${cf}`;
    },
    [checksum, cfChecksum],
  );
  await mkdir(out, { recursive: true });
  await writeFile(join(out, "boxes.csv"), run.csv);
  await page.screenshot({ path: join(out, "screenshot.png"), fullPage: true });
  // Offline once loaded: with the server gone and the network cut, a reload comes from the
  // service worker's cache.
  const worker = await page.evaluate(() =>
    Promise.race([
      navigator.serviceWorker.ready.then(() => true),
      new Promise((ok) => setTimeout(() => ok(false), 10_000)),
    ]),
  );
  server.closeAllConnections();
  await new Promise((ok) => server.close(ok));
  await page.setOfflineMode(true);
  let offline = false;
  if (worker) {
    await page.reload({ waitUntil: "load" });
    offline = await page
      .waitForFunction(() => window.rbtrackReady === true, { timeout: 20_000 })
      .then(async () => (await page.evaluate(() => window.rbtrackChecksum())) === checksum)
      .catch(() => false);
  }
  if (errors.length) throw new Error(`the page reported: ${errors.join("; ")}`);
  const { csv, ...figures } = run;
  console.log(
    JSON.stringify({ ...figures, frames, fps: 1000 / run.frameMs, checksum, cf_checksum: cfChecksum, offline }),
  );
} finally {
  await browser.close();
  if (server.listening) server.close();
}

/** Opens `file` in the page, drags `box` on its first frame, tracks it to its end. */
async function trackVideo(page, file, box, tracker, particles) {
  await page.select("#tracker", tracker);
  await page.select("#particles", particles);
  const input = await page.$("#file");
  await input.uploadFile(file);
  await page.waitForFunction(() => document.getElementById("video").readyState >= 2, { timeout: 60_000 });
  const started = await dragAndTrack(page, box);
  await page.waitForFunction(() => document.getElementById("video").ended, { timeout: 300_000, polling: 200 });
  const seconds = (Date.now() - started) / 1000;
  const duration = await page.evaluate(() => document.getElementById("video").duration);
  const stats = await page.evaluate(() => window.rbtrackStats());
  return { ...stats, videoSeconds: duration, wallSeconds: seconds };
}

/** Starts the (fake) webcam, drags `box` on its picture, tracks for `seconds`. */
async function trackWebcam(page, seconds, box, tracker, particles) {
  await page.select("#tracker", tracker);
  await page.select("#particles", particles);
  await page.click("#webcam");
  await page.waitForFunction(() => document.getElementById("video").readyState >= 2, { timeout: 60_000 });
  await dragAndTrack(page, box);
  await new Promise((ok) => setTimeout(ok, seconds * 1000));
  const stats = await page.evaluate(() => window.rbtrackStats());
  return { ...stats, wallSeconds: seconds };
}

/** Drags `box` (frame px) on the picture with the mouse and presses Track; returns when. */
async function dragAndTrack(page, [x, y, w, h]) {
  await page.waitForFunction(() => document.getElementById("view").width > 0);
  const canvas = await page.$("#view");
  const rect = await canvas.boundingBox();
  const size = await page.evaluate(() => [document.getElementById("view").width, document.getElementById("view").height]);
  const to = (px, py) => [rect.x + (px * rect.width) / size[0], rect.y + (py * rect.height) / size[1]];
  await page.mouse.move(...to(x, y));
  await page.mouse.down();
  await page.mouse.move(...to(x + w, y + h), { steps: 4 });
  await page.mouse.up();
  const started = Date.now();
  await page.click("#track");
  return started;
}
