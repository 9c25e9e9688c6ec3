// The rbtrack core in WebAssembly (rbtrack_web.wasm, built from web/src): loading it,
// handing it frames, reading its estimates, and the host tool's per-frame CSV.

/**
 * Each tracker's colour in the page's pictures, by its code of `start` (0 RBPF, 1 colour
 * PF, 2 correlation filter): the host tool's (`TrackerKind::colour`, host-tests).
 */
export const TRACKER_COLOURS = ["#e6b900", "#00bed2", "#ff8000"];

/** Status codes of the report: 0 lost, 1 uncertain, 2 tracking. */
export const STATUS = ["lost", "uncertain", "tracking"];

/** Error codes of `start` and `step` (web/src/lib.rs, WebError::code). */
const ERRORS = {
  "-1": "particle count must be 25, 50, 100 or 200",
  "-2": "frame size must be 1 to 4096 px a side",
  "-3": "the box is too small (a half-axis below the tracker's minimum)",
  "-4": "the box's centre lies outside the frame",
  "-5": "the tracker refused its configuration",
  "-6": "not started",
};

/** A u64 the module returned (as a BigInt) as 0x + 16 hex digits. */
function hex64(v) {
  return "0x" + BigInt.asUintN(64, v).toString(16).padStart(16, "0");
}

/** Loads the module at `url`; returns the tracker's interface. */
export async function load(url) {
  const bytes = await (await fetch(url)).arrayBuffer();
  const { instance } = await WebAssembly.instantiate(bytes, {});
  const x = instance.exports;
  const check = (code) => {
    if (code !== 0) throw new Error(ERRORS[code] ?? `error ${code}`);
  };
  return {
    /** The module's size, bytes. */
    size: bytes.byteLength,
    /** Copies a frame's RGBA bytes (an ImageData) into the module. */
    frame(image) {
      const ptr = x.rb_frame(image.width, image.height);
      if (ptr === 0) throw new Error(ERRORS["-2"]);
      new Uint8Array(x.memory.buffer, ptr, image.data.length).set(image.data);
    },
    /**
     * Starts on the frame given: tracker 0 RBPF, 1 colour PF or 2 correlation filter (which
     * takes no particle count and reads 0 pixels in the report), the 0-based box
     * [x, y, w, h], px.
     */
    start(tracker, particles, seed, box) {
      check(x.rb_start(tracker, particles, seed, ...box));
    },
    /** Tracks the frame given. */
    step() {
      check(x.rb_step());
    },
    /** The last estimate: ellipse, velocity, confidence, status, pixels read, and the Q16.16 bits. */
    report() {
      const r = new Float64Array(x.memory.buffer, x.rb_report(), 9);
      const bits = Int32Array.from(new Int32Array(x.memory.buffer, x.rb_report_bits(), 7));
      return {
        cx: r[0], cy: r[1], hx: r[2], hy: r[3], vx: r[4], vy: r[5],
        confidence: r[6], status: STATUS[r[7]] ?? "lost", pixels: r[8], bits,
      };
    },
    /** The example firmware's scene, both particle filters: the checksum QEMU prints, as 0x + 16 hex digits. */
    checksum() {
      return hex64(x.rb_firmware_checksum());
    },
    /** The correlation-filter firmware's run of the same scene: the checksum QEMU prints. */
    cfChecksum() {
      return hex64(x.rb_cf_firmware_checksum());
    },
  };
}

/**
 * `v` with `digits` decimals as Rust's `{:.N}` writes it: the exact binary value rounded
 * half to even (JavaScript's toFixed rounds halves up). Exact for values with at most 40
 * binary fraction digits, as every Q16.16 value and sum of them is.
 */
export function fixed(v, digits) {
  let k = 0;
  while (k < 40 && !Number.isInteger(v * 2 ** k)) k++;
  if (k === 40) return v.toFixed(digits);
  const negative = v < 0 || Object.is(v, -0);
  const scaled = BigInt(Math.abs(v * 2 ** k)) * 10n ** BigInt(digits);
  const shift = BigInt(k);
  let q = scaled >> shift;
  if (k > 0) {
    const r = scaled - (q << shift);
    const half = 1n << (shift - 1n);
    if (r > half || (r === half && (q & 1n) === 1n)) q += 1n;
  }
  const text = q.toString().padStart(digits + 1, "0");
  const whole = digits ? `${text.slice(0, -digits)}.${text.slice(-digits)}` : text;
  return (negative ? "-" : "") + whole;
}

/** The header of the host tool's `--per-frame` CSV. */
export const CSV_HEADER = "frame,x,y,w,h,cx,cy,hx,hy,vx,vy,confidence,status";

/**
 * One row of that CSV, 1-based like the host tool's default: frame number `n` (from 1),
 * the box (`box`, 0-based [x, y, w, h], for the first frame; else the estimate's, its
 * ellipse's bounding box) and the estimate `r` (a `report()`).
 */
export function csvRow(n, r, box) {
  const [x, y, w, h] = box ?? [r.cx - r.hx + 0.5, r.cy - r.hy + 0.5, 2 * r.hx, 2 * r.hy];
  const cells = [
    fixed(x + 1, 2), fixed(y + 1, 2), fixed(w, 2), fixed(h, 2),
    fixed(r.cx + 1, 2), fixed(r.cy + 1, 2), fixed(r.hx, 2), fixed(r.hy, 2),
    fixed(r.vx, 3), fixed(r.vy, 3), fixed(r.confidence, 4), r.status,
  ];
  return `${n},${cells.join(",")}`;
}
