#!/usr/bin/env bash
# Accuracy against time for indirect light: examples/cornell-indirect.wsd rendered by wsd with
# 1 … 32 indirect paths a camera sample, and its POV-Ray port (bench/scenes/cornell-indirect.pov)
# with radiosity at rising `count`, in one run, on one thread; each image against wsd's converged
# reference (many paths, the same 3 bounces, another seed): the error is the distance from the
# image the scene asks for. Prints one row a render: renderer, setting,
# CPU-seconds, RMSE and PSNR (wsd diff: display values) against the reference.
# Usage: bench/indirect_vs_povray.sh [SIZE=96] [REFERENCE_PATHS=256]
set -euo pipefail
cd "$(dirname "$0")/.."
size=${1:-96}; ref_paths=${2:-256}
wsd=${WSD:-build/wsd}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
TIMEFORMAT='%U %S'
scene=examples/cornell-indirect.wsd
common=(--width "$size" --height "$size" --supersamples 4 --quiet)

cpu() { awk '{ printf "%.2f", $1 + $2 }' <<<"$1"; }
error() { "$wsd" diff "$out/ref.pfm" "$1" | awk '/^RMSE/ { r = $2 } /^PSNR/ { p = $2 } END { print r, p }'; }

"$wsd" render "$scene" "${common[@]}" --threads 2 -o "$out/ref.pfm" \
  --indirect-samples "$ref_paths" --indirect-bounces 3 --seed 12345 >/dev/null
printf '%-8s %-22s %8s %10s %8s\n' renderer setting CPU-s RMSE PSNR
for n in 1 2 4 8 16 32; do
  t=$( { time "$wsd" render "$scene" "${common[@]}" --threads 1 --indirect-samples "$n" -o "$out/wsd.pfm" >/dev/null; } 2>&1 )
  read -r rmse psnr < <(error "$out/wsd.pfm")
  printf '%-8s %-22s %8s %10s %8s\n' wsd "indirect_samples $n" "$(cpu "$t")" "$rmse" "$psnr"
done
if ! command -v povray >/dev/null; then
  echo "povray not installed: no POV-Ray rows" >&2
  exit 0
fi
for count in 20 50 100 200 400; do
  t=$( { time povray +Ibench/scenes/cornell-indirect.pov +O"$out/pov.hdr" +FH +W"$size" +H"$size" \
           +A0.0 +AM1 +R2 +WT1 -D -V Declare=COUNT="$count" Declare=BOUNCES=3 >"$out/pov.log" 2>&1; } 2>&1 )
  read -r rmse psnr < <(error "$out/pov.hdr")
  printf '%-8s %-22s %8s %10s %8s\n' povray "radiosity count $count" "$(cpu "$t")" "$rmse" "$psnr"
done
