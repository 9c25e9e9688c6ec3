#!/usr/bin/env bash
# Builds (and runs) the C examples against the C library, librbtrack_ffi.a (docs/c.md):
#
#   ffi/c/build.sh host       # target/c/track: tracks a raw RGB888 sequence (system cc)
#   ffi/c/build.sh firmware   # target/c/firmware.elf (arm-none-eabi-gcc), run in QEMU's
#                             # mps2-an386: prints the example firmware's checksum (the
#                             # library with RGB565 alone; FFI_FEATURES=default: all formats)
#   ffi/c/build.sh cf-firmware  # target/c/cf_firmware.elf, the same for the correlation-
#                             # filter firmware's workload: prints its `cf checksum`
#   ffi/c/build.sh proof      # links every C function of the thumbv7em library with its
#                             # panic handler, which cannot link: fails if a panic is reachable
#
# The firmware and the proof need arm-none-eabi-gcc (Debian: gcc-arm-none-eabi) and the
# thumbv7em-none-eabihf Rust target; the firmware runs in qemu-system-arm.
set -euo pipefail
cd "$(dirname "$0")/../.."
mkdir -p target/c

target=thumbv7em-none-eabihf
arm_flags=(-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16)
arm_lib="target/$target/release/librbtrack_ffi.a"

case "${1:-}" in
host)
  cargo build -q --release -p rbtrack-ffi
  # The host library links Rust's std for its panic runtime: these are the system
  # libraries `cargo rustc -- --print native-static-libs` names for it.
  cc -std=c11 -O2 -Wall -Wextra -Werror -Iffi/include ffi/c/host/track.c \
    target/release/librbtrack_ffi.a -lgcc_s -lutil -lrt -lpthread -lm -ldl -lc -o target/c/track
  echo "target/c/track"
  ;;
firmware | cf-firmware)
  # The scene is RGB565 little-endian: the library is built with that pixel format alone,
  # as a firmware builds it for its camera (FFI_FEATURES=default: all seven formats).
  cargo build -q --release -p rbtrack-ffi --target "$target" --no-default-features \
    --features "${FFI_FEATURES:-rgb565le}"
  elf="target/c/${1/-/_}.elf"
  workload=()
  [ "$1" = cf-firmware ] && workload=(-DCF_FIRMWARE)
  arm-none-eabi-gcc "${arm_flags[@]}" "${workload[@]}" -std=c11 -O2 -Wall -Wextra -Werror -ffreestanding \
    -ffunction-sections -fdata-sections -nostdlib -Iffi/include -T ffi/c/firmware/link.ld \
    -Wl,--gc-sections,-z,noexecstack ffi/c/firmware/startup.c ffi/c/firmware/main.c "$arm_lib" -lgcc -o "$elf"
  arm-none-eabi-size -A "$elf" | awk -v elf="$elf" '
    $1 ~ /^\.(vectors|text|rodata|ARM\.exidx|data)$/ { flash += $2 }
    $1 ~ /^\.(data|bss)$/ { ram += $2 }
    END { printf "%s: %d B of flash, %d B of RAM in .data and .bss\n", elf, flash, ram }'
  # SYS_WRITE0 goes to QEMU's stderr: the firmware's output on stdout with the rest.
  timeout 600 qemu-system-arm -machine mps2-an386 -cpu cortex-m4 -nographic \
    -semihosting-config enable=on,target=native -kernel "$elf" 2>&1
  ;;
proof)
  cargo build -q --release -p rbtrack-ffi --target "$target" # every pixel format
  mapfile -t functions < <(arm-none-eabi-nm -g --defined-only "$arm_lib" 2>/dev/null |
    awk '$2 == "T" && $3 ~ /^rbt_/ { print $3 }' | sort -u)
  [ "${#functions[@]}" -gt 0 ] || { echo "no rbt_ functions in $arm_lib"; exit 1; }
  # Every C function is a root of the link; a panic reachable from any of them keeps the
  # panic handler, whose call to rbtrack_panic_path_is_reachable (defined nowhere) fails it.
  arm-none-eabi-gcc "${arm_flags[@]}" -nostdlib -Wl,--gc-sections -Wl,-e,rbt_step \
    "${functions[@]/#/-Wl,-u,}" "$arm_lib" -lgcc -o target/c/no_panic.elf
  echo "no panic reachable from the ${#functions[@]} C functions: ${functions[*]}"
  ;;
*)
  echo "usage: ffi/c/build.sh host|firmware|cf-firmware|proof" >&2
  exit 2
  ;;
esac
