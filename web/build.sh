#!/usr/bin/env bash
# Builds the browser page into web/dist (or the folder given): the core in WebAssembly
# (wasm32-unknown-unknown, the `web` profile: release without debug information) and the
# page's static files. Serve the folder with any static file server, e.g.
#   python3 -m http.server -d web/dist 8000
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
out="${1:-$here/dist}"
rustup target add wasm32-unknown-unknown >/dev/null 2>&1 || true
cargo build --manifest-path "$here/../Cargo.toml" -p rbtrack-web --profile web \
  --target wasm32-unknown-unknown --target-dir "$here/../target/web"
mkdir -p "$out"
cp "$here"/www/* "$out"/
cp "$here/../target/web/wasm32-unknown-unknown/web/rbtrack_web.wasm" "$out"/
echo "built $out: $(wc -c < "$out/rbtrack_web.wasm") B of WebAssembly, $(cat "$here"/www/* | wc -c) B of page"
