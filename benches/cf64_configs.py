#!/usr/bin/env python3
"""The correlation-filter tracker's configurations against the integer design: accuracy on
each data folder and pooled, over 7 starts and from the first box, loss detection, and the
cost model's Cortex-M4 instructions a frame, one row per configuration, as a Markdown table.

    cargo build --release -p rbtrack-host
    python3 benches/cf64_configs.py ../shared/data ../valset --zero-based-sequences ball1_vot15 > table.md
    python3 benches/cf64_configs.py ../shared/data ../valset --zero-based-sequences ball1_vot15 --rows port,grid
    python3 benches/cf64_configs.py --from-json figures.json    # the table of an earlier --json run

Each row runs `rbtrack eval DATA... --tracker cf64 --preset core --seed 1 --starts spatial
--json` with its `--set cf.FIELD=VALUE`s on top of the f64 reference of the integer
design at its defaults (`cf64::Params::of_core`), and, where the integer tracker has the
row's settings, the same with `--tracker cf`. Both trackers are deterministic. Columns:
- cf64 and cf, per data folder and pooled: mean success AUC over the sequences and the 7
  starts (the box, 2 px shifts left, right, up, down, scales 0.95 and 1.05); "box": the
  pooled mean from the first ground-truth box alone;
- ROC, flagged, good as Lost: cf64's loss table over all runs pooled (the confidence's ROC
  AUC for frames with IoU < 0.1; losses of 5+ frames flagged `Lost` within 5; frames of
  IoU >= 0.5 flagged `Lost`);
- instructions: `cf64::cost`'s estimate of a frame on a Cortex-M4, on the budget example's
  scene (`rbtrack cost --preset core --set ...`: the model fitted to that example's QEMU
  counts, recomputed for every row also with --from-json);
- first folder alone / pooled: against the first row, whether the first folder's (the
  dev set's) 7-start mean and the pooled one would take the row's change (+), leave it
  (-) or not tell (=, within 0.01, the spread of a pooled 7-start mean under a 1e-6
  change of one setting).
"""

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent

# (group, name, settings on top of the integer design's reference)
ROWS = [
    ("port", "the integer design (its defaults)", []),
    ("grid", "8 cells a side (32 px)", ["grid=8"]),
    ("grid", "32 cells a side (128 px)", ["grid=32"]),
    ("grid", "16 cells of 2 px (32 px)", ["cell=2", "colour_step=1"]),
    ("region", "padding 0.75", ["padding=0.75"]),
    ("region", "padding 1.5", ["padding=1.5"]),
    ("channels", "13 (unsigned + texture) + grey", ["hog=13"]),
    ("channels", "31 (fHOG) + grey", ["hog=31"]),
    ("channels", "grey only", ["hog=off"]),
    ("gradients", "of the strongest colour channel", ["luma_gradient=false"]),
    ("colour", "4 bits a channel", ["colour_bits=4"]),
    ("colour", "5 bits a channel", ["colour_bits=5"]),
    ("colour", "every pixel", ["colour_step=1"]),
    ("scales", "4 scales", ["scales=4"]),
    ("scales", "16 scales of 1.04", ["scales=16", "scale_step=1.04"]),
    ("scales", "step 1.04", ["scale_step=1.04"]),
    ("scales", "step 1.12", ["scale_step=1.12"]),
    ("scales", "model 256 px^2", ["scale_area=256"]),
    ("scales", "model 1024 px^2", ["scale_area=1024"]),
    ("scales", "31 channels", ["scale_hog=31"]),
    ("scales", "none (the first box's size)", ["scales=0"]),
    ("rates", "filter 0.01", ["cf_rate=0.01"]),
    ("rates", "filter 0.03", ["cf_rate=0.03"]),
    ("rates", "colour 0.02", ["colour_rate=0.02"]),
    ("rates", "colour 0.08", ["colour_rate=0.08"]),
    ("rates", "scale 0.0125", ["scale_rate=0.0125"]),
    ("rates", "scale 0.05", ["scale_rate=0.05"]),
    ("merge", "0.2", ["merge=0.2"]),
    ("merge", "0.4", ["merge=0.4"]),
    ("motion", "search on the last position (lead 0)", ["lead=0"]),
    ("motion", "lead 0.75", ["lead=0.75"]),
    ("gates", "size changes on every frame (scale_above 0)", ["scale_above=0"]),
    ("gates", "scale_above 0.3", ["scale_above=0.3"]),
    ("gates", "learn_above 0.15", ["learn_above=0.15"]),
    ("gates", "learn_above 0.25", ["learn_above=0.25"]),
    ("lost", "lost_below 0.18", ["lost_below=0.18"]),
    ("lost", "lost_below 0.26", ["lost_below=0.26"]),
    ("lost", "no re-detection", ["redetect=0"]),
    ("lost", "4 ring regions", ["redetect=4"]),
    ("lost", "coasting", ["coast=true"]),
]

# The noise of a pooled 7-start mean (docs/accuracy.md): a change within it tells nothing.
NOISE = 0.01


def find_rbtrack(arg):
    if arg:
        return Path(arg)
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    binary = target / "release" / "rbtrack"
    if not binary.exists():
        sys.exit("cf64_configs.py: no rbtrack binary; cargo build --release -p rbtrack-host "
                 "or pass --rbtrack PATH")
    return binary


def run(binary, data, zero_based, tracker, settings):
    """One eval's figures, or None where the integer tracker lacks a setting."""
    cmd = [str(binary), "eval", *data, "--tracker", tracker, "--preset", "core", "--seed", "1",
           "--starts", "spatial", "--json"]
    if zero_based:
        cmd += ["--zero-based-sequences", zero_based]
    for s in settings:
        cmd += ["--set", f"cf.{s}"]
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        if tracker == "cf" and ("integer tracker" in out.stderr or "(grid, scales)" in out.stderr):
            return None
        sys.exit(f"cf64_configs.py: {' '.join(cmd)}: {out.stderr.strip()}")
    doc = json.loads(out.stdout)
    mean = doc["mean"][0]
    loss = mean["loss"]
    return {
        "sets": [s["mean"][0]["auc"] for s in doc["sets"]],
        "pooled": mean["auc"],
        "box": next(s["auc"] for s in mean["per_start"] if s["start"] == "box"),
        "roc": loss["roc_auc"],
        "flagged": loss["flagged_share"],
        "good_lost": loss["good_flagged_share"],
    }


def cost(binary, settings):
    """The cost model's instructions a frame for a row's settings."""
    cmd = [str(binary), "cost", "--preset", "core", "--json"]
    for s in settings:
        cmd += ["--set", f"cf.{s}"]
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"cf64_configs.py: {' '.join(cmd)}: {out.stderr.strip()}")
    return json.loads(out.stdout)["instructions"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data", nargs="*",
                        default=[str(REPO.parent / "shared" / "data"), str(REPO.parent / "valset")])
    parser.add_argument("--zero-based-sequences", default="",
                        help="comma-separated sequences whose ground truth counts from 0")
    parser.add_argument("--rows", help="comma-separated row names or groups (default: all)")
    parser.add_argument("--rbtrack", help="path of the rbtrack binary")
    parser.add_argument("--json", help="also write the figures to this file (after each row)")
    parser.add_argument("--from-json", help="print the table of a file --json wrote, running nothing")
    args = parser.parse_args()
    binary = find_rbtrack(args.rbtrack)
    if args.from_json:
        doc = json.loads(Path(args.from_json).read_text())
        for r in doc["rows"]:
            r["instructions"] = cost(binary, r["settings"])
        print(table(doc["data"], doc["rows"]))
        return
    rows = ROWS
    if args.rows:
        wanted = [r.strip() for r in args.rows.split(",")]
        rows = [r for r in ROWS if r[1] in wanted or r[0] in wanted]
    results = []
    for group, name, settings in rows:
        r = {"group": group, "name": name, "settings": settings}
        for tracker in ("cf64", "cf"):
            r[tracker] = run(binary, args.data, args.zero_based_sequences, tracker, settings)
        r["instructions"] = cost(binary, settings)
        results.append(r)
        print(f"{name}: done", file=sys.stderr, flush=True)
        if args.json:
            Path(args.json).write_text(json.dumps({"data": args.data, "rows": results}, indent=1))
    print(table(args.data, results))


def table(data, rows):
    """The Markdown table of `rows` run over the folders `data`."""
    names = [Path(d).name for d in data]
    figures = " | ".join(f"{t} {n}" for t in ("cf64", "cf") for n in names + ["pooled"])
    head = (f"| group | configuration | `--set` (cf.) | {figures} | cf64 box, pooled | ROC | "
            f"flagged | good as Lost | instructions | {names[0]} alone / pooled |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    base = rows[0]["cf64"] if rows else None
    for r in rows:
        lines.append(row(r, base, len(names)))
    return "\n".join(lines)


def row(r, base, folders):
    """One table row; `base` is the first row's cf64 figures."""
    def fig(f):
        if f is None:
            return " | ".join("-" for _ in range(folders + 1))
        return " | ".join(f"{v:.3f}" for v in f["sets"] + [f["pooled"]])

    def says(delta):
        return "=" if abs(delta) < NOISE else ("+" if delta > 0 else "-")

    c = r["cf64"]
    pct = lambda v, digits: "-" if v is None else f"{100 * v:.{digits}f} %"
    verdict = "-"
    if base is not None and r["settings"]:
        verdict = f"{says(c['sets'][0] - base['sets'][0])} / {says(c['pooled'] - base['pooled'])}"
    instructions = f"{r['instructions'] / 1e6:.2f} M"
    return (f"| {r['group']} | {r['name']} | {' '.join(r['settings']) or '-'} | {fig(c)} | "
            f"{fig(r['cf'])} | {c['box']:.3f} | {c['roc'] or 0:.3f} | {pct(c['flagged'], 0)} | "
            f"{pct(c['good_lost'], 2)} | {instructions} | {verdict} |")


if __name__ == "__main__":
    main()
