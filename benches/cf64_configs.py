#!/usr/bin/env python3
"""The f64 correlation-filter tracker (cf64) over its configurations: dev-set accuracy
from the first box and over 7 starts, loss detection, and the cost model's Cortex-M4
instructions a frame, one row per configuration, as a Markdown table.

    cargo build --release -p rbtrack-host
    python3 benches/cf64_configs.py ../shared/data --zero-based-sequences ball1_vot15 > table.md
    python3 benches/cf64_configs.py ../shared/data --zero-based-sequences ball1_vot15 --rows default,port
    python3 benches/cf64_configs.py --from-json figures.json    # the table of an earlier --json run

Each row runs `rbtrack eval DATA --tracker cf64 --seed 1 --starts spatial --json` with its
`--set cf.FIELD=VALUE`s on top of the defaults (`cf64::Params::default`); the tracker is
deterministic (seed 1 only feeds the particle rows). Columns:
- box: mean success AUC over the sequences from the first ground-truth box;
- 7 starts: the same over the box, 2 px shifts left, right, up, down and scales 0.95, 1.05;
- ROC, flagged, good as Lost: `rbtrack eval`'s loss table over all runs (the confidence's ROC
  AUC for frames with IoU < 0.1; losses of 5+ frames flagged `Lost` within 5; frames of
  IoU >= 0.5 flagged `Lost`);
- < 0.20: sequences whose 7-start mean is below 0.20;
- instructions: `cf64::cost`'s estimate for a frame on a Cortex-M4 (the integer design's
  per-operation costs, host-tests/src/cf64/cost.rs).
"""

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent

# The port: what the microcontroller tracker takes (docs/accuracy.md chooses it): one patch
# a frame (learning on the detection patch), the 9 unsigned fHOG channels and grey, 8 scales
# at 1.08 read between samples, 4 bits a colour channel, colour on every second pixel.
PORT = [
    "fresh_patch=false", "hog=9", "scales=8", "scale_step=1.08", "scale_window=false",
    "scale_interpolate=true", "scale_limit=1", "colour_bits=4", "colour_step=2",
]

# (group, name, settings on top of the defaults)
ROWS = [
    ("default", "default", []),
    ("grid", "16 cells a side (64 px)", ["grid=16"]),
    ("grid", "32 cells of 2 px (64 px)", ["cell=2"]),
    ("grid", "64 cells of 2 px (128 px)", ["grid=64", "cell=2"]),
    ("channels", "31 (fHOG with texture) + grey", ["hog=31"]),
    ("channels", "13 (unsigned + texture) + grey", ["hog=13"]),
    ("channels", "9 (unsigned) + grey", ["hog=9"]),
    ("channels", "grey only", ["hog=off"]),
    ("scales", "17 at 1.04", ["scales=17", "scale_step=1.04"]),
    ("scales", "9 at 1.08, read between, no window",
     ["scales=9", "scale_step=1.08", "scale_window=false", "scale_interpolate=true",
      "scale_limit=1"]),
    ("scales", "none (the first box's size)", ["scales=0"]),
    ("merge", "colour off (0)", ["merge=0"]),
    ("merge", "0.2", ["merge=0.2"]),
    ("merge", "0.4", ["merge=0.4"]),
    ("merge", "colour alone (1)", ["merge=1"]),
    ("colour", "4 bits a channel", ["colour_bits=4"]),
    ("colour", "every second pixel", ["colour_step=2"]),
    ("rates", "filter 0.005", ["cf_rate=0.005"]),
    ("rates", "filter 0.02", ["cf_rate=0.02"]),
    ("rates", "colour 0.02", ["colour_rate=0.02"]),
    ("rates", "colour 0.08", ["colour_rate=0.08"]),
    ("rates", "scale 0.01", ["scale_rate=0.01"]),
    ("rates", "scale 0.05", ["scale_rate=0.05"]),
    ("learning", "no gate (learn every frame)", ["learn_above=0"]),
    ("learning", "gate 0.25", ["learn_above=0.25", "lost_below=0.25"]),
    ("learning", "on the detection patch", ["fresh_patch=false"]),
    ("lost", "re-detection and coasting", ["redetect=2", "coast=true"]),
    ("particles", "100 particles on the map", ["particles=100", "particle_noise=0.05"]),
    ("port", "port (2 M budget)", PORT),
    ("port", "budget: port with 16 cells (1 M)", PORT + ["grid=16"]),
]


def find_rbtrack(arg):
    if arg:
        return Path(arg)
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    binary = target / "release" / "rbtrack"
    if not binary.exists():
        sys.exit("cf64_configs.py: no rbtrack binary; cargo build --release -p rbtrack-host "
                 "or pass --rbtrack PATH")
    return binary


def run(binary, data, zero_based, settings):
    cmd = [str(binary), "eval", str(data), "--tracker", "cf64", "--seed", "1",
           "--starts", "spatial", "--json"]
    if zero_based:
        cmd += ["--zero-based-sequences", zero_based]
    for s in settings:
        cmd += ["--set", f"cf.{s}"]
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"cf64_configs.py: {' '.join(cmd)}: {out.stderr.strip()}")
    doc = json.loads(out.stdout)
    mean = doc["mean"][0]
    loss = mean["loss"]
    box = next(s["auc"] for s in mean["per_start"] if s["start"] == "box")
    return {
        "box": box,
        "starts": mean["auc"],
        "roc": loss["roc_auc"],
        "flagged": loss["flagged_share"],
        "good_lost": loss["good_flagged_share"],
        "below_020": sum(1 for r in doc["sequences"] if r["auc"] < 0.20),
        "instructions": doc["cf64_cost"]["instructions"],
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data", nargs="?", default=str(REPO.parent / "shared" / "data"))
    parser.add_argument("--zero-based-sequences", default="",
                        help="comma-separated sequences whose ground truth counts from 0")
    parser.add_argument("--rows", help="comma-separated row names (default: all)")
    parser.add_argument("--rbtrack", help="path of the rbtrack binary")
    parser.add_argument("--json", help="also write the figures to this file (after each row)")
    parser.add_argument("--from-json", help="print the table of a file --json wrote, running nothing")
    args = parser.parse_args()
    binary = None if args.from_json else find_rbtrack(args.rbtrack)
    rows = ROWS
    if args.rows:
        wanted = [r.strip() for r in args.rows.split(",")]
        rows = [r for r in ROWS if r[1] in wanted or r[0] in wanted]
    if args.from_json:
        results = json.loads(Path(args.from_json).read_text())
        print(HEADER)
        for r in results:
            print(row(r))
        return
    print(HEADER)
    results = []
    for group, name, settings in rows:
        r = run(binary, args.data, args.zero_based_sequences, settings)
        results.append({"group": group, "name": name, "settings": settings, **r})
        print(row(results[-1]), flush=True)
        if args.json:
            Path(args.json).write_text(json.dumps(results, indent=1))


HEADER = (
    "| group | configuration | `--set` (cf.) | box | 7 starts | ROC | flagged | good as Lost "
    "| < 0.20 | instructions |\n|---|---|---|---|---|---|---|---|---|---|"
)


def row(r):
    """One table row of a configuration's figures."""
    pct = lambda v, digits: "-" if v is None else f"{100 * v:.{digits}f} %"
    return (f"| {r['group']} | {r['name']} | {' '.join(r['settings']) or '-'} | {r['box']:.3f} | "
            f"{r['starts']:.3f} | {r['roc'] or 0:.3f} | {pct(r['flagged'], 0)} | "
            f"{pct(r['good_lost'], 2)} | {r['below_020']} | {r['instructions'] / 1e6:.2f} M |")


if __name__ == "__main__":
    main()
