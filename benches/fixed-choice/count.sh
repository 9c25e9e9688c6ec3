#!/usr/bin/env bash
# Instruction counts of Q16.16 operations for thumbv7em-none-eabihf (Cortex-M4F/M7):
# rbtrack's Q16 against fixed::types::I16F16. Prints, per operation and type, the
# instructions in the function body (prologue and return included) and whether the body
# branches or calls a routine; for branch-free bodies the count is exactly what runs.
# Usage: bash benches/fixed-choice/count.sh   (needs: rustup component add llvm-tools)
set -euo pipefail
cd "$(dirname "$0")"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-target}"
cargo build -q --release --target thumbv7em-none-eabihf
objdump=$(find "$(rustc --print sysroot)" -name llvm-objdump -type f | head -n 1)
dis=$("$objdump" -d --demangle "$CARGO_TARGET_DIR/thumbv7em-none-eabihf/release/libfixed_choice.rlib" 2>/dev/null)

# body NAME: the disassembled instructions of fixed_choice::NAME
body() {
  echo "$dis" | awk -v f="<fixed_choice::$1::h" 'index($0, f) && /:$/ {on=1; next} on && /^$/ {on=0} on && /^ +[0-9a-f]+:/'
}
# count NAME: "instructions[+branches]"; add and own_add may be folded into one symbol
count() {
  local b n kind=""
  b=$(body "$1")
  [ -z "$b" ] && b=$(body "fixed_${1#own_}")
  n=$(echo "$b" | grep -c .)
  echo "$b" | grep -qE '\s(bl|b\.w|blx)\s' && kind=" +call"
  echo "$b" | grep -qE '\s(b(eq|ne|lt|ge|hs|lo|hi|ls|gt|le)(\.w)?|cbz|cbnz)\s' && kind="$kind +branch"
  echo "$n$kind"
}
printf '%-5s %-20s %-20s\n' op "own Q16" "fixed I16F16"
for op in add mul div sqrt; do
  printf '%-5s %-20s %-20s\n' "$op" "$(count "own_$op")" "$(count "fixed_$op")"
done
