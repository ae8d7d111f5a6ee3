#!/usr/bin/env bash
# Renders the Cornell box (examples/cornell.wsd) in one run with full sampling (every camera ray of
# the grid, every light cell, bailout 0) and with each adaptive option, and prints CPU-seconds,
# shadow rays, ray queries, the speed-up and the error (PSNR, SSIM from `wsd diff`) against the
# full image. Same seed everywhere, so the difference is the adaptive approximation alone.
# Usage: bench/adaptive_vs_full.sh [SIZE=1200] [THREADS=1]
set -euo pipefail
cd "$(dirname "$0")/.."
size=${1:-1200}; threads=${2:-1}
wsd=$(realpath "${WSD:-build/wsd}")
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
TIMEFORMAT='%U %S'

# Full sampling: the scene with `bailout 0` (read from stdin inside examples/, so that the
# scene's relative texture paths resolve as they do for the file itself).
full_scene=$(sed 's/ambient 0.2 }/ambient 0.2  bailout 0 }/' examples/cornell.wsd)
grep -q 'bailout 0' <<<"$full_scene" || { echo "cannot set bailout 0 in examples/cornell.wsd" >&2; exit 1; }

# run NAME SCENE-TEXT-OR-EMPTY FLAGS...: renders, records CPU-s and the stats JSON.
run() {
    local name=$1 text=$2; shift 2
    local t
    if [[ -n $text ]]; then
        t=$( { cd examples; time "$wsd" render - -o "$out/$name.png" --width "$size" --height "$size" \
                 --threads "$threads" --quiet --stats-json "$out/$name.json" "$@" <<<"$text" >/dev/null 2>&1; } 2>&1 )
    else
        t=$( { time "$wsd" render examples/cornell.wsd -o "$out/$name.png" --width "$size" --height "$size" \
                 --threads "$threads" --quiet --stats-json "$out/$name.json" "$@" >/dev/null 2>&1; } 2>&1 )
    fi
    awk '{print $1 + $2}' <<<"$t" >"$out/$name.cpu"
}

run full "$full_scene"
run default ""
run lights "" --adaptive-lights
run aa "" --adaptive-aa
run both "" --adaptive-aa --adaptive-lights
run both_b0 "$full_scene" --adaptive-aa --adaptive-lights

full_cpu=$(cat "$out/full.cpu")
full_shadow=$(python3 -c "import json;print(json.load(open('$out/full.json'))['shadow_rays'])")
printf '%-36s %8s %8s %14s %12s %10s %9s %8s %8s\n' setting CPU-s speed-up ray-queries shadow-rays \
    shadow÷ adaptive-px PSNR-dB SSIM
for name in full default lights aa both both_b0; do
    case $name in
        full) label="full (bailout 0, no adaptive)";;
        default) label="scene defaults (bailout 1/512)";;
        lights) label="--adaptive-lights";;
        aa) label="--adaptive-aa";;
        both) label="--adaptive-aa --adaptive-lights";;
        both_b0) label="--adaptive-aa --adaptive-lights, bailout 0";;
    esac
    cpu=$(cat "$out/$name.cpu")
    read -r rq sh ap < <(python3 -c "import json;d=json.load(open('$out/$name.json'));print(d['ray_queries'],d['shadow_rays'],d['adaptive_pixels'])")
    d=$("$wsd" diff "$out/full.png" "$out/$name.png")
    psnr=$(awk '/^PSNR:/ {print $2}' <<<"$d"); ssim=$(awk '/^SSIM:/ {print $2}' <<<"$d")
    printf '%-36s %8.2f %7.2fx %14d %12d %9.2fx %9d %8s %8s\n' "$label" "$cpu" \
        "$(awk "BEGIN{print $full_cpu/$cpu}")" "$rq" "$sh" "$(awk "BEGIN{print $full_shadow/$sh}")" "$ap" "$psnr" "$ssim"
done
echo "size ${size}x${size}, ${threads} thread(s); CPU-s = user + sys of the whole wsd process (load, build, render, write)"
