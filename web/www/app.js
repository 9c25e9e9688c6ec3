// The page: a video file or the webcam, a box drawn by hand, the tracker on every frame,
// the estimate drawn live, confidence over time, time per step, the boxes as CSV.
import { load, csvRow, CSV_HEADER, TRACKER_COLOURS } from "./rbtrack.js";

/** Frames wider than this are scaled down to it before tracking, px. */
const MAX_WIDTH = 640;
/** Confidence values kept for the plot. */
const PLOT_POINTS = 480;

const $ = (id) => document.getElementById(id);
const view = $("view");
const viewCtx = view.getContext("2d");
const work = document.createElement("canvas");
const workCtx = work.getContext("2d", { willReadFrequently: true });
const video = $("video");

const core = await load("rbtrack_web.wasm");
let box = null; // the drawn box, 0-based [x, y, w, h] in frame px
let still = null; // the frame the box is drawn on (ImageData)
let tracking = false;
let rows = [];
let confidences = [];
let colour = TRACKER_COLOURS[2]; // the running tracker's
let stepMs = 0;
let frameMs = 0;
let steps = 0;
let shownTime = -1; // media time of the last frame tracked, s

if ("serviceWorker" in navigator && location.protocol.startsWith("http")) {
  navigator.serviceWorker.register("sw.js").catch(() => {});
}

/** Draws `source` into the work canvas at tracking size and returns its pixels. */
function grab(source, width, height) {
  const scale = Math.min(1, MAX_WIDTH / width);
  const w = Math.max(1, Math.round(width * scale));
  const h = Math.max(1, Math.round(height * scale));
  if (work.width !== w || work.height !== h) [work.width, work.height] = [w, h];
  workCtx.drawImage(source, 0, 0, w, h);
  return workCtx.getImageData(0, 0, w, h, { colorSpace: "srgb" });
}

/** Shows `image` with the estimate `r` (and the drawn box while choosing). */
function show(image, r) {
  if (view.width !== image.width || view.height !== image.height) {
    [view.width, view.height] = [image.width, image.height];
  }
  viewCtx.putImageData(image, 0, 0);
  viewCtx.lineWidth = 2;
  if (box && !tracking) {
    viewCtx.strokeStyle = "#3f3";
    viewCtx.strokeRect(box[0], box[1], box[2], box[3]);
  }
  if (r) {
    viewCtx.strokeStyle = colour;
    viewCtx.beginPath();
    viewCtx.ellipse(r.cx + 0.5, r.cy + 0.5, r.hx, r.hy, 0, 0, 2 * Math.PI);
    viewCtx.stroke();
    viewCtx.fillStyle = "rgba(0,0,0,.6)";
    viewCtx.fillRect(0, 0, 190, 22);
    viewCtx.fillStyle = colour;
    viewCtx.font = "14px system-ui, sans-serif";
    viewCtx.fillText(`${r.status} ${r.confidence.toFixed(2)}`, 6, 16);
  }
}

/** The confidence plot. */
function plot() {
  const c = $("plot").getContext("2d");
  const { width: w, height: h } = c.canvas;
  c.clearRect(0, 0, w, h);
  c.strokeStyle = "#ccc";
  c.strokeRect(0, 0, w, h);
  c.strokeStyle = colour;
  c.beginPath();
  confidences.forEach((v, i) => {
    const span = Math.min(Math.max(confidences.length, 100), PLOT_POINTS) - 1;
    const [x, y] = [(i / span) * w, h - v * (h - 2) - 1];
    if (i) c.lineTo(x, y); else c.moveTo(x, y);
  });
  c.stroke();
}

/** Starts the tracker on the frame `image` and the box. */
function start(image, tracker, particles, seed, initial) {
  core.frame(image);
  core.start(tracker, particles, seed, initial);
  colour = TRACKER_COLOURS[tracker];
  const r = core.report();
  rows = [csvRow(1, r, initial)];
  confidences = [r.confidence];
  [stepMs, frameMs, steps] = [0, 0, 0];
  return r;
}

/** Tracks one frame's pixels; `began` is when reading them started (ms). */
function step(image, began) {
  const t0 = performance.now();
  core.frame(image);
  core.step();
  const t1 = performance.now();
  const r = core.report();
  rows.push(csvRow(rows.length + 1, r));
  confidences.push(r.confidence);
  if (confidences.length > PLOT_POINTS) confidences.shift();
  steps += 1;
  stepMs += t1 - t0;
  frameMs += t1 - began;
  return r;
}

function stats(r) {
  const status = `<b class="${r.status}">${r.status}</b> ${r.confidence.toFixed(3)}`;
  const timing = steps
    ? `; ${(stepMs / steps).toFixed(2)} ms a step (frame copy and step), ` +
      `${(1000 / (frameMs / steps)).toFixed(0)} frames/s with the canvas read`
    : "";
  $("stats").innerHTML =
    `frame ${rows.length}, ${work.width}x${work.height} px: ${status}` +
    (r.pixels ? `, ${r.pixels} pixels read` : "") + timing;
}

/** Every presented video frame while tracking (each frame once). */
function onVideoFrame(_now, meta) {
  if (!tracking) return;
  if (meta.mediaTime === shownTime) {
    if (!video.paused && !video.ended) video.requestVideoFrameCallback(onVideoFrame);
    return;
  }
  shownTime = meta.mediaTime;
  const began = performance.now();
  const image = grab(video, video.videoWidth, video.videoHeight);
  const r = step(image, began);
  show(image, r);
  stats(r);
  plot();
  if (!video.paused && !video.ended) video.requestVideoFrameCallback(onVideoFrame);
}

/** Shows the current video frame for drawing a box on. */
function freeze() {
  still = grab(video, video.videoWidth, video.videoHeight);
  show(still, null);
}

$("file").addEventListener("change", (e) => {
  const file = e.target.files[0];
  if (!file) return;
  tracking = false;
  video.srcObject = null;
  video.src = URL.createObjectURL(file);
  // A paused video that never played may not have painted its first frame: play until
  // one is presented, then stop there.
  video.requestVideoFrameCallback(() => { video.pause(); freeze(); });
  video.play().catch(() => {}); // interrupted by that pause
  $("play").disabled = true;
});

$("webcam").addEventListener("click", async () => {
  tracking = false;
  video.srcObject = await navigator.mediaDevices.getUserMedia({ video: true });
  await video.play();
  const live = () => {
    if (tracking || box) return;
    show(grab(video, video.videoWidth, video.videoHeight), null);
    requestAnimationFrame(live);
  };
  live();
});

let dragFrom = null;
const at = (e) => {
  const rect = view.getBoundingClientRect();
  return [
    Math.round(((e.clientX - rect.left) * view.width) / rect.width),
    Math.round(((e.clientY - rect.top) * view.height) / rect.height),
  ];
};
view.addEventListener("pointerdown", (e) => {
  if (!video.videoWidth) return;
  tracking = false;
  video.pause();
  freeze();
  dragFrom = at(e);
  box = null;
});
view.addEventListener("pointermove", (e) => {
  if (!dragFrom) return;
  const [x, y] = at(e);
  box = [Math.min(x, dragFrom[0]), Math.min(y, dragFrom[1]), Math.abs(x - dragFrom[0]), Math.abs(y - dragFrom[1])];
  show(still, null);
});
view.addEventListener("pointerup", () => {
  dragFrom = null;
  $("track").disabled = !(box && box[2] >= 4 && box[3] >= 4);
});

$("track").addEventListener("click", async () => {
  try {
    const r = start(still, Number($("tracker").value), Number($("particles").value), 1, box);
    shownTime = video.currentTime;
    tracking = true;
    $("hint").textContent = "Tracking. Pause, or drag a new box to start again.";
    $("csv").disabled = false;
    $("play").disabled = false;
    show(still, r);
    stats(r);
    video.requestVideoFrameCallback(onVideoFrame);
    await video.play();
  } catch (err) {
    $("hint").textContent = `Cannot start: ${err.message}`;
  }
});

$("play").addEventListener("click", async () => {
  if (video.paused) {
    video.requestVideoFrameCallback(onVideoFrame);
    await video.play();
  } else {
    video.pause();
  }
});

$("csv").addEventListener("click", () => {
  const blob = new Blob([[CSV_HEADER, ...rows].join("\n") + "\n"], { type: "text/csv" });
  const a = Object.assign(document.createElement("a"), {
    href: URL.createObjectURL(blob),
    download: "rbtrack.csv",
  });
  a.click();
});

$("checksum").addEventListener("click", () => {
  const t0 = performance.now();
  const value = core.checksum();
  const cf = core.cfChecksum();
  $("checksum-out").textContent =
    `checksum ${value}, correlation filter ${cf} ` +
    `(${(performance.now() - t0).toFixed(0)} ms for 180 steps)`;
});

/**
 * For tests and benchmarks: tracks the lossless frames at `frames` (image URLs) from the
 * 0-based `box` of the first, as the page tracks a video; returns the CSV, the mean time
 * of a step (frame copy and step) and of a frame (canvas read, copy and step), ms.
 */
window.rbtrackRun = async ({ frames, box: initial, tracker = 2, particles = 100, seed = 1 }) => {
  let r = null;
  let image = null;
  for (const [i, url] of frames.entries()) {
    const blob = await (await fetch(url)).blob();
    const bitmap = await createImageBitmap(blob, { colorSpaceConversion: "none", premultiplyAlpha: "none" });
    const began = performance.now();
    image = grab(bitmap, bitmap.width, bitmap.height);
    r = i === 0 ? start(image, tracker, particles, seed, initial) : step(image, began);
    bitmap.close();
  }
  show(image, r);
  stats(r);
  plot();
  return {
    csv: [CSV_HEADER, ...rows].join("\n") + "\n",
    stepMs: stepMs / Math.max(steps, 1),
    frameMs: frameMs / Math.max(steps, 1),
    width: work.width,
    height: work.height,
    wasmBytes: core.size,
  };
};
/** For tests and benchmarks: what the tracking of a video so far measured. */
window.rbtrackStats = () => ({
  steps,
  stepMs: stepMs / Math.max(steps, 1),
  frameMs: frameMs / Math.max(steps, 1),
  width: work.width,
  height: work.height,
  csv: [CSV_HEADER, ...rows].join("\n") + "\n",
});
window.rbtrackChecksum = () => core.checksum();
window.rbtrackCfChecksum = () => core.cfChecksum();
window.rbtrackReady = true;
