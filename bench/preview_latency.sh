#!/usr/bin/env bash
# Save-to-pixels latency of `wsd preview` (bench/preview_latency.py): the time from writing the
# scene file to the first image of the new render reaching a client of the page's event stream.
# Usage: bench/preview_latency.sh [WSD] [SCENE] [EDITS]   (defaults: build/wsd examples/cornell.wsd 5)
set -euo pipefail
cd "$(dirname "$0")/.."
exec python3 bench/preview_latency.py "${1:-build/wsd}" "${2:-examples/cornell.wsd}" "${3:-5}"
