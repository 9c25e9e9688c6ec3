#!/usr/bin/env bash
# Frames per second of the page in headless Chromium on a 640x480 clip, used as a person
# uses it: the first 300 frames of boat1_uav (../shared/data, or the data folder given)
# scaled to 640x480 and encoded as a 30 frames/s VP8 WebM by ffmpeg, opened in the page,
# the boat's box dragged with the mouse, Track pressed, played to the end; both trackers,
# N = 100. Prints per tracker the frames tracked of 300, the wall time against the clip's
# 10 s, the mean time of a step (frame copy into the module and step) and of a whole frame
# (canvas draw and read, copy, step), and the frames per second that allows. Needs
# Chromium, ffmpeg and `npm ci --prefix web/test`.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
data="${1:-$here/../../shared/data}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
ffmpeg -v error -nostdin -framerate 30 -i "$data/boat1_uav/img/%04d.jpg" -frames:v 300 \
  -vf scale=640:480,setsar=1 -c:v libvpx -b:v 4M "$work/boat.webm"
"$here/build.sh" "$work/dist" >/dev/null
# The first ground-truth box (1-based, 1280x720), 0-based and scaled to 640x480.
box="$(head -1 "$data/boat1_uav/groundtruth_rect.txt" | awk -F, '{
  printf "%d,%d,%d,%d", ($1 - 1) / 2, ($2 - 1) * 2 / 3, $3 / 2, $4 * 2 / 3 }')"
for tracker in 1 0; do
  name=$([ "$tracker" = 1 ] && echo "colour PF" || echo "RBPF")
  node "$here/test/browser.mjs" --dist "$work/dist" --video "$work/boat.webm" --box "$box" \
    --tracker "$tracker" --out "$work/out$tracker" |
    python3 -c "
import json, sys
d = json.load(sys.stdin)
print(f\"$name: {d['frames']} of 300 frames tracked in {d['wallSeconds']:.1f} s of wall time for a {d['videoSeconds']:.1f} s clip; \"
      f\"{d['stepMs']:.2f} ms a step, {d['frameMs']:.2f} ms a frame with the canvas read: {d['fps']:.0f} frames/s; {d['width']}x{d['height']} px\")"
done
