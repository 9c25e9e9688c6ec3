#!/usr/bin/env python3
"""Flash of a firmware ELF by crate, inlined code included.

    python3 benches/flash_by_crate.py target/thumbv7em-none-eabihf/release/examples/firmware

Each byte of `.text` goes to the crate of the innermost function that the debug
information places there: a function inlined into another counts for its own crate (the
tracker's step inlined into the firmware's `main` counts for `rbtrack`), except that the
standard library's small functions inlined into a crate's code (slice iterators, integer
methods) count for that crate, not for `core`. `.rodata` goes to
the crate named in its symbol where there is one (anonymous constants count as
"unattributed"). Needs pyelftools (`pip install pyelftools`) and a build with debug
information (the release profile has `debug = true`).
"""

import collections
import sys

from elftools.elf.elffile import ELFFile


# Library crates whose inlined functions count for the function they are inlined into.
STD = {"core", "alloc", "compiler_builtins"}


def crate_of(die, cache):
    """The top-level namespace (crate) of a subprogram DIE, following abstract origins."""
    key = die.offset
    if key in cache:
        return cache[key]
    target = die
    for attr in ("DW_AT_abstract_origin", "DW_AT_specification"):
        if attr in target.attributes:
            target = target.get_DIE_from_attribute(attr)
            break
    if "DW_AT_specification" in target.attributes:
        target = target.get_DIE_from_attribute("DW_AT_specification")
    crate = None
    parent = target.get_parent()
    while parent is not None and parent.tag != "DW_TAG_compile_unit":
        if parent.tag == "DW_TAG_namespace" and "DW_AT_name" in parent.attributes:
            crate = parent.attributes["DW_AT_name"].value.decode()
        parent = parent.get_parent()
    cache[key] = crate or "unattributed"
    return cache[key]


def ranges_of(die, dwarf, cu):
    """The address ranges of a DIE: low_pc/high_pc or DW_AT_ranges."""
    attrs = die.attributes
    if "DW_AT_low_pc" in attrs and "DW_AT_high_pc" in attrs:
        low = attrs["DW_AT_low_pc"].value
        high = attrs["DW_AT_high_pc"]
        end = high.value if high.form == "DW_FORM_addr" else low + high.value
        return [(low, end)]
    if "DW_AT_ranges" in attrs:
        rl = dwarf.range_lists()
        base = cu.get_top_DIE().attributes.get("DW_AT_low_pc")
        base = base.value if base else 0
        out = []
        for entry in rl.get_range_list_at_offset(attrs["DW_AT_ranges"].value, cu=cu):
            if hasattr(entry, "begin_offset"):
                out.append((base + entry.begin_offset, base + entry.end_offset))
            elif hasattr(entry, "base_address"):
                base = entry.base_address
        return out
    return []


def main():
    path = sys.argv[1]
    with open(path, "rb") as f:
        elf = ELFFile(f)
        text = elf.get_section_by_name(".text")
        t0, t1 = text["sh_addr"], text["sh_addr"] + text["sh_size"]
        dwarf = elf.get_dwarf_info()
        # (depth, start, end, crate) for every concrete and inlined function.
        spans = []
        cache = {}
        for cu in dwarf.iter_CUs():
            stack = [(cu.get_top_DIE(), 0)]
            while stack:
                die, depth = stack.pop()
                if die.tag in ("DW_TAG_subprogram", "DW_TAG_inlined_subroutine"):
                    crate = crate_of(die, cache)
                    inlined = die.tag == "DW_TAG_inlined_subroutine"
                    for lo, hi in ranges_of(die, dwarf, cu):
                        # Functions the linker dropped keep ranges from address 0.
                        if t0 <= lo < hi <= t1 and not (inlined and crate in STD):
                            spans.append((depth, lo, hi, crate))
                for child in die.iter_children():
                    stack.append((child, depth + 1))
        # Innermost (deepest) span wins for each byte: paint in order of depth.
        owner = {}
        spans.sort()
        for depth, lo, hi, crate in spans:
            for a in range(lo, hi):
                owner[a] = crate
        by_crate = collections.Counter(owner.values())
        by_crate["unattributed"] += (t1 - t0) - len(owner)
        # .rodata by symbol name.
        rodata = elf.get_section_by_name(".rodata")
        r0, r1 = rodata["sh_addr"], rodata["sh_addr"] + rodata["sh_size"]
        ro = collections.Counter()
        named = 0
        for sym in elf.get_section_by_name(".symtab").iter_symbols():
            addr, size = sym["st_value"], sym["st_size"]
            if size and r0 <= addr < r1 and sym["st_info"]["type"] == "STT_OBJECT":
                name = sym.name
                crate = "unattributed"
                for prefix, c in (("_ZN7rbtrack", "rbtrack"), ("_ZN16rbtrack_firmware", "rbtrack_firmware")):
                    if name.startswith(prefix):
                        crate = c
                ro[crate] += size
                named += size
        ro["unattributed"] += (r1 - r0) - named
    print(f".text {t1 - t0} bytes:")
    for crate, n in by_crate.most_common():
        print(f"  {n:8d}  {crate}")
    print(f".rodata {r1 - r0} bytes:")
    for crate, n in ro.most_common():
        print(f"  {n:8d}  {crate}")


if __name__ == "__main__":
    main()
