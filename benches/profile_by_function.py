#!/usr/bin/env python3
"""Instructions of a whole firmware run by function, from an instruction-level emulator.

    python3 benches/profile_by_function.py ELF [--frames N] [--top K]

Runs the ELF from its vector table under the workplace's Cortex-M4 model
(`../shared/tools/m4-cycle-model/ucount.py`, unicorn; its instruction counts equal
QEMU's), counts every instruction by address (an IT block's skipped instructions
included, as QEMU counts them) and sums them by the function that holds the address (a
function inlined into another counts for the one it was inlined into). With `--frames N`
the sums are also divided by N: the firmware's frames, for instructions a frame. The
emulator runs about a hundred thousand instructions a second: the correlation-filter
firmware's 60 frames and their rendering, 1.2 G instructions, take most of an hour.
Needs `pip install unicorn capstone pyelftools`.
"""

import argparse
import collections
import os
import sys

MODEL = os.path.join(os.path.dirname(__file__), "..", "..", "shared", "tools", "m4-cycle-model")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("elf")
    ap.add_argument("--frames", type=int, default=0, help="divide by this many frames")
    ap.add_argument("--top", type=int, default=30, help="functions listed")
    ap.add_argument("--model", default=MODEL, help="folder of ucount.py")
    a = ap.parse_args()
    sys.path.insert(0, a.model)
    import ucount  # the workplace's emulator, not part of this repository

    runner = ucount.Runner(a.elf, "m4", 2)
    function_of = runner._func_of
    # Count by address: the runner counts "functions" through this lookup.
    runner._func_of = lambda address: address
    runner.in_window = True
    runner.start_addr = runner.end_addr = -1
    runner.boot()
    by_function = collections.Counter()
    for address, count in runner.func_insns.items():
        by_function[function_of(address)] += count
    total = sum(by_function.values())
    print(f"{total} instructions")
    for name, count in by_function.most_common(a.top):
        per_frame = f"{count / a.frames:12.0f} a frame" if a.frames else ""
        short = ucount.demangle_last(name) or name
        print(f"{count:12d} {100 * count / total:5.1f}% {per_frame} {short}")


if __name__ == "__main__":
    main()
