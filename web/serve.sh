#!/usr/bin/env bash
# Builds the page (build.sh) and serves it at http://localhost:8000 (or the port given).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
"$here/build.sh"
echo "open http://localhost:${1:-8000}/"
exec python3 -m http.server -d "$here/dist" "${1:-8000}"
