#!/usr/bin/env python3
"""rbtrack against OpenCV's trackers on the same OTB-layout sequences, in one run.

    pip install opencv-contrib-python-headless==5.0.0.93 numpy   # once (this script installs nothing)
    cargo build --release -p rbtrack-host                        # the `rbtrack` binary
    python3 benches/compare_opencv.py --zero-based-sequences ball1_vot15   # ../shared/data
    python3 benches/compare_opencv.py DATA_DIR --seeds 1,2,3 --per-sequence --rbtrack PATH
    python3 benches/compare_opencv.py ../shared/data ../valset --zero-based-sequences ball1_vot15
    python3 benches/compare_opencv.py --seeds 1,2,3 --starts spatial --peers CSRT \
        --zero-based-sequences ball1_vot15
    pip install ./python    # once, for --in-process: rbtrack's Python module
    python3 benches/compare_opencv.py --in-process --zero-based-sequences ball1_vot15

Runs OpenCV's CSRT, KCF, MIL and MOSSE (the legacy API of opencv-contrib, `cv2.legacy`,
default parameters), a CamShift baseline (hue histogram of the first box, back-projection,
`cv2.CamShift`) and `rbtrack track` (RBPF, colour PF, the f64 correlation-filter tracker
cf64 and the core's integer one cf, over each of `--seeds`; `--rbtrack-trackers` picks
them) on every sequence of every data folder given (several as with `rbtrack eval DATA_DIR
[DATA_DIR...]`; a sequence name may be in one folder only), and prints one table: success
AUC, precision at 20 px and tracking-only milliseconds per frame, with rbtrack's time as a
ratio to each tracker's, all measured in this run; with several folders, one block of rows
per folder and one pooled over all their sequences.

The protocol, one for every tracker and the same as `rbtrack eval`'s:
- Frames: each sequence's `img/*.jpg|png`, decoded once by rbtrack itself
  (`rbtrack frames SEQ DUMP`, the decoder `rbtrack eval` and `rbtrack track` use) into a raw
  RGB888 dump; the OpenCV trackers get those pixels (as BGR), rbtrack gets the dump
  (`rbtrack track DUMP --raw WxH:rgb888`), so every tracker sees the same pixels, and
  rbtrack's rows equal `rbtrack eval`'s for the same seeds and starts.
- Starts: `--starts box` (the default) starts every tracker from the first ground-truth
  box; `--starts spatial` also from that box shifted 2 px left, right, up and down and
  scaled by 0.95 and 1.05 about its centre (7 starts, as `rbtrack eval --starts
  spatial`), each tracker scored from its own start; the rows are means over starts (and
  rbtrack's seeds), and a second table gives each tracker's mean per start.
- Boxes: `groundtruth_rect.txt` has one `x,y,w,h` per line (commas, spaces or tabs) in a
  stated convention: 1-based by default (OTB, UAV123, LaSOT and MOT as published),
  `--zero-based` for all, `--zero-based-sequences NAMES` for some (ball1_vot15 in the shared
  data, as its README says); `rbtrack eval` takes the same flags. Every box is converted
  to 0-based pixels (a box covers `x..x+w-1`) before use: OpenCV's trackers are
  initialised with the first line so converted, rbtrack with the same line and the same
  convention flag (it converts it the same way), and every tracker is scored against the
  converted ground truth.
- Scores (as `rbtrack eval`, host-tests/src/metrics.rs): every frame with a valid
  ground-truth box (finite, `w, h > 0`) counts, the first included (the initial box
  itself); success AUC is the mean over the IoU thresholds 0, 0.05, ..., 1 (21) of the
  share of frames with IoU strictly above the threshold; precision at 20 px is the share of
  frames whose centre error (centres `x + (w-1)/2, y + (h-1)/2`) is at most 20 px. The
  table's figures are means over sequences (each folder's, and with several folders the
  pooled mean, every sequence weighing the same); rbtrack's are first averaged over its
  seeds.
- ms/frame: time inside the tracker's update (OpenCV: `tracker.update(frame)`; CamShift:
  HSV conversion, back-projection and `cv2.CamShift`; rbtrack: its own `ms_per_frame`,
  time inside `Tracker::step`), reading excluded, averaged over the frames after the first;
  OpenCV runs on one thread (`cv2.setNumThreads(1)`, `--threads` to change) like rbtrack.
- A tracker that reports failure for a frame keeps its last box.

With `--in-process`, rbtrack runs in this process through its Python module
(`rbtrack.Tracker`, `pip install ./python`) on the same BGR frames as OpenCV's trackers, from
the same first boxes: its boxes are those of `rbtrack track` on the dump
(python/tests/test_tracker.py checks it), scored by the metrics below from their exact
values, and its ms/frame is the time of `Tracker.update` as for OpenCV's trackers.

rbtrack's scores come from its JSON; the script recomputes them from its `--boxes` output
(two decimals) with the metrics below and warns if they differ by more than 0.002 (a check
of this script's metrics; the rounding of the box file moves an AUC by up to ~5e-4).

Feeding OpenCV the first line *unconverted* (the file's 1-based box on 0-based images, one
pixel right of and below the annotated target; `--zero-based` reproduces it) moves its
scores a lot: CSRT 0.702 instead of 0.649 on Crossing, KiteSurf, PETS09S2L1_id11,
ball1_vot15 and boat1_uav (KiteSurf 0.501 instead of 0.314), 0.589 instead of 0.531 on the
14 shared sequences (TUDStadtmitte_id2 0.697 instead of 0.070). The trackers are
sensitive to the decoder too (`cv2.imread`'s JPEG decoding instead of rbtrack's moves
rbtrack's mean AUC by up to a few hundredths), hence one reader for all.
"""

import argparse
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

try:
    import cv2
    import numpy as np
except ImportError:
    sys.exit(
        "compare_opencv.py: needs OpenCV and NumPy: "
        "pip install opencv-contrib-python-headless==5.0.0.93 numpy"
    )

SUCCESS_STEPS = 21
PRECISION_PX = 20.0
REPO = Path(__file__).resolve().parent.parent


# --- sequences ---------------------------------------------------------------------------


def read_boxes(path):
    """Boxes of a ground-truth or box file, one per line; NaN box for an unreadable line."""
    boxes = []
    for line in path.read_text().splitlines():
        fields = [f for f in re.split(r"[,\s]+", line.strip()) if f]
        if not fields:
            continue
        try:
            x, y, w, h = (float(f) for f in fields[:4])
        except ValueError:
            x = y = w = h = math.nan
        boxes.append((x, y, w, h))
    return boxes


def to_zero_based(box, zero_based):
    """A box of a file in the given convention, in 0-based pixels."""
    if zero_based:
        return box
    x, y, w, h = box
    return (x - 1.0, y - 1.0, w, h)


def decode(binary, seq, dump):
    """Decodes a sequence with `rbtrack frames` into `dump`; its `--raw` layout and its
    frames as BGR arrays."""
    out = subprocess.run([str(binary), "frames", str(seq), str(dump)],
                         capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"compare_opencv.py: rbtrack frames {seq}: {out.stderr.strip()}")
    layout, count = out.stdout.split()
    width, height = (int(v) for v in layout.split(":")[0].split("x"))
    rgb = np.fromfile(dump, dtype=np.uint8).reshape(int(count), height, width, 3)
    return layout, [cv2.cvtColor(f, cv2.COLOR_RGB2BGR) for f in rgb]


# (name, dx px, dy px, scale): rbtrack eval's starts (host-tests/src/cli/runs.rs, Start).
STARTS = [
    ("box", 0.0, 0.0, 1.0),
    ("left2", -2.0, 0.0, 1.0),
    ("right2", 2.0, 0.0, 1.0),
    ("up2", 0.0, -2.0, 1.0),
    ("down2", 0.0, 2.0, 1.0),
    ("scale0.95", 0.0, 0.0, 0.95),
    ("scale1.05", 0.0, 0.0, 1.05),
]


def start_box(box, start):
    """`box` moved to `start`: shifted, and scaled about its centre (either convention)."""
    _, dx, dy, scale = start
    x, y, w, h = box
    return (x + (w - w * scale) / 2 + dx, y + (h - h * scale) / 2 + dy, w * scale, h * scale)


def sequences(data):
    for seq in sorted(p for p in data.iterdir() if p.is_dir()):
        if (seq / "img").is_dir() and (seq / "groundtruth_rect.txt").is_file():
            yield seq


# --- metrics (host-tests/src/metrics.rs) -------------------------------------------------


def valid(b):
    return all(math.isfinite(v) for v in b) and b[2] > 0 and b[3] > 0


def iou(a, b):
    if not valid(a) or not valid(b):
        return 0.0
    w = min(a[0] + a[2], b[0] + b[2]) - max(a[0], b[0])
    h = min(a[1] + a[3], b[1] + b[3]) - max(a[1], b[1])
    inter = w * h if w > 0 and h > 0 else 0.0
    union = a[2] * a[3] + b[2] * b[3] - inter
    return min(max(inter / union, 0.0), 1.0) if inter > 0 and union > 0 else 0.0


def centre_error(a, b):
    if not all(math.isfinite(v) for v in a + b):
        return math.inf
    ax, ay = a[0] + (a[2] - 1) / 2, a[1] + (a[3] - 1) / 2
    bx, by = b[0] + (b[2] - 1) / 2, b[1] + (b[3] - 1) / 2
    return math.hypot(ax - bx, ay - by)


def scores(truth, estimates):
    """(success AUC, precision at 20 px) of 0-based estimates against 0-based truth."""
    pairs = [(t, e) for t, e in zip(truth, estimates) if valid(t)]
    if not pairs:
        return 0.0, 0.0
    ious = [iou(t, e) for t, e in pairs]
    errors = [centre_error(t, e) for t, e in pairs]
    thresholds = [i / (SUCCESS_STEPS - 1) for i in range(SUCCESS_STEPS)]
    auc = sum(sum(v > t for v in ious) / len(ious) for t in thresholds) / SUCCESS_STEPS
    prec = sum(e <= PRECISION_PX for e in errors) / len(errors)
    return auc, prec


# --- trackers ----------------------------------------------------------------------------


def opencv_tracker(name):
    make = {
        "CSRT": cv2.legacy.TrackerCSRT_create,
        "KCF": cv2.legacy.TrackerKCF_create,
        "MIL": cv2.legacy.TrackerMIL_create,
        "MOSSE": cv2.legacy.TrackerMOSSE_create,
    }[name]

    class Legacy:
        def __init__(self, frame, box):
            self.t = make()
            self.box = box
            self.t.init(frame, tuple(float(v) for v in box))

        def update(self, frame):
            ok, box = self.t.update(frame)
            if ok:
                self.box = tuple(float(v) for v in box)
            return self.box

    return Legacy


class CamShift:
    """Hue back-projection and CamShift (the OpenCV tutorial's baseline)."""

    def __init__(self, frame, box):
        x, y, w, h = (int(round(v)) for v in box)
        H, W = frame.shape[:2]
        x, y = max(0, min(x, W - 1)), max(0, min(y, H - 1))
        w, h = max(1, min(w, W - x)), max(1, min(h, H - y))
        self.window = (x, y, w, h)
        hsv = cv2.cvtColor(frame[y : y + h, x : x + w], cv2.COLOR_BGR2HSV)
        mask = cv2.inRange(hsv, np.array((0.0, 60.0, 32.0)), np.array((180.0, 255.0, 255.0)))
        self.hist = cv2.calcHist([hsv], [0], mask, [180], [0, 180])
        cv2.normalize(self.hist, self.hist, 0, 255, cv2.NORM_MINMAX)
        self.crit = (cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, 10, 1)

    def update(self, frame):
        hsv = cv2.cvtColor(frame, cv2.COLOR_BGR2HSV)
        back = cv2.calcBackProject([hsv], [0], self.hist, [0, 180], 1)
        _, window = cv2.CamShift(back, self.window, self.crit)
        if window[2] > 0 and window[3] > 0:
            self.window = window
        return tuple(float(v) for v in self.window)


def run_peer(make, frames, init):
    """0-based boxes and mean ms per frame (after the first) of one tracker over frames."""
    tracker = make(frames[0], init)
    boxes, times = [init], []
    for frame in frames[1:]:
        t0 = time.perf_counter()
        box = tracker.update(frame)
        times.append(time.perf_counter() - t0)
        boxes.append(box)
    return boxes, 1000.0 * statistics.fmean(times) if times else 0.0


def run_rbtrack(binary, seq, dump, layout, zero_based, tracker, seed, start, args):
    """rbtrack's JSON result and 0-based boxes for one tracker, seed and start over the
    dump."""
    with tempfile.TemporaryDirectory() as tmp:
        boxes_file = Path(tmp) / "boxes.txt"
        groundtruth = seq / "groundtruth_rect.txt"
        first = start_box(read_boxes(groundtruth)[0], start)
        cmd = [
            str(binary), "track", str(dump), "--raw", layout,
            "--zero-based" if zero_based else "--one-based",
            "--init", ",".join(repr(v) for v in first), "--groundtruth", str(groundtruth),
            "--tracker", tracker, "--seed", str(seed), "--particles", str(args.particles),
            "--json", "--boxes", str(boxes_file),
        ]
        out = subprocess.run(cmd, capture_output=True, text=True)
        if out.returncode != 0:
            sys.exit(f"compare_opencv.py: {' '.join(cmd)}: {out.stderr.strip()}")
        result = json.loads(out.stdout)
        boxes = [to_zero_based(b, zero_based) for b in read_boxes(boxes_file)]
    return result, boxes


def run_rbtrack_in_process(frames, init, tracker, seed, particles):
    """0-based boxes and mean ms per frame (after the first) of rbtrack's Python module over
    BGR frames from the 0-based box `init` (`seed` and `particles` for the particle filters
    alone: the correlation-filter tracker has neither)."""
    import rbtrack

    if tracker == "cf":
        t = rbtrack.Tracker(variant="cf")
    else:
        t = rbtrack.Tracker(variant=tracker, particles=particles, seed=seed)
    t.init(frames[0], init)
    boxes, times = [t.box], []
    for frame in frames[1:]:
        t0 = time.perf_counter()
        t.update(frame)
        times.append(time.perf_counter() - t0)
        boxes.append(t.box)
    return boxes, 1000.0 * statistics.fmean(times) if times else 0.0


def find_rbtrack(arg):
    if arg:
        return Path(arg)
    candidates = []
    if os.environ.get("CARGO_TARGET_DIR"):
        candidates.append(Path(os.environ["CARGO_TARGET_DIR"]) / "release" / "rbtrack")
    candidates.append(REPO / "target" / "release" / "rbtrack")
    for c in candidates:
        if c.is_file():
            return c
    sys.exit(
        "compare_opencv.py: no rbtrack binary; build it with "
        "`cargo build --release -p rbtrack-host` or pass --rbtrack PATH"
    )


# --- main --------------------------------------------------------------------------------


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("data", nargs="*", default=[str(REPO.parent / "shared" / "data")],
                        help="folders of sequence folders (default ../shared/data)")
    parser.add_argument("--rbtrack", help="path of the rbtrack binary")
    parser.add_argument("--particles", type=int, default=100)
    parser.add_argument("--seeds", default="1", help="rbtrack's seeds, comma-separated (default 1)")
    parser.add_argument("--starts", choices=("box", "spatial"), default="box",
                        help="first boxes: the ground truth's, or also 6 perturbed ones")
    parser.add_argument("--peers", default="CSRT,KCF,MIL,MOSSE,CamShift",
                        help="OpenCV trackers to run, comma-separated (default all)")
    convention = parser.add_mutually_exclusive_group()
    convention.add_argument("--zero-based", action="store_true",
                            help="ground-truth files count pixels from 0")
    convention.add_argument("--one-based", action="store_true",
                            help="ground-truth files count pixels from 1 (the default)")
    parser.add_argument("--zero-based-sequences", default="",
                        help="comma-separated sequences whose ground truth counts from 0")
    parser.add_argument("--threads", type=int, default=1, help="OpenCV threads (default 1)")
    parser.add_argument("--per-sequence", action="store_true", help="also print every sequence")
    parser.add_argument("--json", action="store_true", help="print the results as JSON")
    parser.add_argument("--in-process", action="store_true",
                        help="run rbtrack through its Python module (pip install ./python); "
                             "cf64, host only, still runs through the binary")
    parser.add_argument("--rbtrack-trackers", default="rbpf,pf,cf64,cf",
                        help="rbtrack's trackers, comma-separated (default rbpf,pf,cf64,cf)")
    args = parser.parse_args()

    folders = [Path(d) for d in args.data]
    for data in folders:
        if not data.is_dir():
            sys.exit(f"compare_opencv.py: no data folder {data}")
    sets = [list(sequences(data)) for data in folders]  # each folder's sequences
    seen = {}
    for seq in (seq for set_ in sets for seq in set_):
        if seq.name in seen:
            sys.exit(f"compare_opencv.py: sequence {seq.name} is in two data folders: "
                     f"{seen[seq.name]} and {seq}")
        seen[seq.name] = seq
    listed = ", ".join(str(data) for data in folders)
    seeds = [int(s) for s in args.seeds.split(",") if s.strip()]
    zero_named = {n.strip() for n in args.zero_based_sequences.split(",") if n.strip()}
    missing = zero_named - set(seen)
    if missing:
        sys.exit(f"compare_opencv.py: --zero-based-sequences: no sequence {sorted(missing)} in {listed}")
    binary = find_rbtrack(args.rbtrack)  # `rbtrack frames` decodes for every tracker
    if args.in_process:
        try:
            import rbtrack  # noqa: F401
        except ImportError:
            sys.exit("compare_opencv.py: --in-process needs rbtrack's Python module: pip install ./python")
    cv2.setNumThreads(args.threads)

    makers = {name: opencv_tracker(name) for name in ("CSRT", "KCF", "MIL", "MOSSE")}
    makers["CamShift"] = CamShift
    chosen = [p.strip() for p in args.peers.split(",") if p.strip()]
    unknown = [p for p in chosen if p not in makers]
    if unknown:
        sys.exit(f"compare_opencv.py: --peers: no tracker {unknown}; choose from {list(makers)}")
    peers = {name: makers[name] for name in chosen}
    starts = STARTS if args.starts == "spatial" else STARTS[:1]
    ours = [t.strip() for t in args.rbtrack_trackers.split(",") if t.strip()]
    if not ours or not set(ours) <= {"rbpf", "pf", "cf64", "cf"}:
        sys.exit("compare_opencv.py: --rbtrack-trackers: choose from rbpf, pf, cf64, cf")
    names = [f"rbtrack-{t}" for t in ours] + list(peers)
    rows = {n: [] for n in names}  # per sequence: (sequence, auc, prec20, ms)
    by_start = {n: {s[0]: [] for s in starts} for n in names}  # per start: AUC per sequence
    for seq in (seq for set_ in sets for seq in set_):
        zero_based = args.zero_based or seq.name in zero_named
        first = read_boxes(seq / "groundtruth_rect.txt")[0]  # in the file's convention
        truth = [to_zero_based(b, zero_based) for b in read_boxes(seq / "groundtruth_rect.txt")]
        with tempfile.TemporaryDirectory() as tmp:
            dump = Path(tmp) / f"{seq.name}.rgb"
            layout, frames = decode(binary, seq, dump)
            for tracker in ours:
                name = f"rbtrack-{tracker}"
                runs = []
                for start in starts:
                    per_start = []
                    for seed in seeds:
                        if args.in_process and tracker in ("cf", "rbpf", "pf"):
                            init = to_zero_based(start_box(first, start), zero_based)
                            boxes, ms = run_rbtrack_in_process(
                                frames, init, tracker, seed, args.particles
                            )
                            auc, prec = scores(truth, boxes)
                            per_start.append((auc, prec, ms))
                            continue
                        result, boxes = run_rbtrack(
                            binary, seq, dump, layout, zero_based, tracker, seed, start, args
                        )
                        auc, prec = scores(truth, boxes)
                        # The box file has two decimals, so an IoU next to a threshold can
                        # land on either side: allow a little.
                        if abs(auc - result["auc"]) > 2e-3 or abs(prec - result["prec20"]) > 2e-3:
                            print(
                                f"warning: {seq.name} {tracker} seed {seed} {start[0]}: "
                                f"recomputed AUC {auc:.6f} / prec {prec:.6f} differ from "
                                f"rbtrack's {result['auc']:.6f} / {result['prec20']:.6f}",
                                file=sys.stderr,
                            )
                        per_start.append((result["auc"], result["prec20"], result["ms_per_frame"]))
                    by_start[name][start[0]].append(statistics.fmean(r[0] for r in per_start))
                    runs.extend(per_start)
                rows[name].append(
                    (seq.name, *(statistics.fmean(r[i] for r in runs) for i in range(3)))
                )
        for name, make in peers.items():
            runs = []
            for start in starts:
                init = to_zero_based(start_box(first, start), zero_based)
                boxes, ms = run_peer(make, frames, init)
                auc, prec = scores(truth, boxes)
                by_start[name][start[0]].append(auc)
                runs.append((auc, prec, ms))
            rows[name].append(
                (seq.name, *(statistics.fmean(r[i] for r in runs) for i in range(3)))
            )
        print(f"{seq.name}: done", file=sys.stderr)

    def means(part):
        """Per tracker, the means over the sequences `part` (a slice of the rows): (AUC,
        prec@20, ms/frame), and the AUC per start."""
        mean = {
            n: tuple(statistics.fmean(r[i] for r in rows[n][part]) for i in (1, 2, 3))
            if rows[n][part] else (0, 0, 0)
            for n in names
        }
        start_means = {
            n: {k: statistics.fmean(v[part]) for k, v in by_start[n].items() if v[part]}
            for n in names
        }
        return mean, start_means

    # (label, sequences, means): each folder's, then with several folders the pooled.
    groups, offset = [], 0
    for data, set_ in zip(folders, sets):
        groups.append((str(data), len(set_), means(slice(offset, offset + len(set_)))))
        offset += len(set_)
    pooled = means(slice(None))
    shown = groups + [("all", offset, pooled)] if len(groups) > 1 else [(None, offset, pooled)]
    first = names[0]  # the time ratios are this tracker's time over each one's

    def as_json(mean):
        return {n: dict(zip(("auc", "prec20", "ms_per_frame"), mean[n])) for n in names}

    if args.json:
        print(json.dumps({**({"data": str(folders[0])} if len(folders) == 1 else {}),
                          "data_dirs": [str(data) for data in folders],
                          "particles": args.particles, "seeds": seeds,
                          "starts": [s[0] for s in starts],
                          "mean_auc_per_start": pooled[1],
                          "zero_based": args.zero_based,
                          "zero_based_sequences": sorted(zero_named),
                          "opencv": cv2.__version__, "threads": args.threads,
                          "rbtrack_in_process": args.in_process,
                          "sequences": {n: rows[n] for n in names},
                          "mean": as_json(pooled[0]),
                          "sets": [{"data": label, "sequences": count, "mean": as_json(m),
                                    "mean_auc_per_start": sm}
                                   for label, count, (m, sm) in groups]}, indent=1))
        return
    counts = f" ({' + '.join(str(len(set_)) for set_ in sets)})" if len(sets) > 1 else ""
    scope = ("means over sequences" if len(sets) == 1
             else "means over each folder's sequences and over all of them")
    print(
        f"{listed}: {offset} sequences{counts}; OpenCV {cv2.__version__} on {args.threads} "
        f"thread(s); rbtrack {'in process (Python module)' if args.in_process else 'by rbtrack track'}; "
        f"rbtrack N = {args.particles}, seeds {args.seeds} (mean); "
        f"{len(starts)} start(s) per tracker (mean); boxes "
        f"{'0-based' if args.zero_based else '1-based'}"
        f"{' except ' + ', '.join(sorted(zero_named)) if zero_named else ''}; "
        f"{scope}"
    )
    print()
    print(f"{'tracker':14} {'AUC':>6} {'prec@20':>8} {'ms/frame':>9}  {first} time / this")
    print("-" * 66)
    for label, count, (mean, _) in shown:
        if label:
            print(f"{label} ({count} sequences)")
        for n in names:
            auc, prec, ms = mean[n]
            ratio = mean[first][2] / ms if ms > 0 else math.inf
            share = f"{ratio:8.3f}  (1/{1 / ratio:.0f})" if 0 < ratio < 1 else f"{ratio:8.3f}"
            print(f"{n:14} {auc:6.3f} {prec:8.3f} {ms:9.3f}  {share}")
    if len(starts) > 1:
        print()
        print("mean AUC per start (over sequences" + (" and seeds" if len(seeds) > 1 else "") + ")")
        print(f"{'tracker':14} " + " ".join(f"{s[0]:>9}" for s in starts) + "  perturbed")
        for label, count, (_, start_means) in shown:
            if label:
                print(f"{label} ({count} sequences)")
            for n in names:
                per = start_means[n]
                perturbed = statistics.fmean(per[s[0]] for s in starts[1:])
                print(f"{n:14} " + " ".join(f"{per[s[0]]:9.3f}" for s in starts) + f"  {perturbed:9.3f}")
    if args.per_sequence:
        print()
        print(f"{'sequence':16} {'tracker':14} {'AUC':>6} {'prec@20':>8} {'ms/frame':>9}")
        for i, (seq, *_rest) in enumerate(rows[first]):
            for n in names:
                _, auc, prec, ms = rows[n][i]
                print(f"{seq:16} {n:14} {auc:6.3f} {prec:8.3f} {ms:9.3f}")


if __name__ == "__main__":
    main()
