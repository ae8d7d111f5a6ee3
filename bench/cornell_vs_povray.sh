#!/usr/bin/env bash
# Renders the Cornell box with wsd and with POV-Ray (bench/scenes/cornell.pov, Debian's povray) in
# one run and prints CPU-seconds, ray queries and ray queries per CPU-second for both, and ratios.
# Usage: bench/cornell_vs_povray.sh [SIZE=1200] [THREADS=1] [--adaptive]
# --adaptive: `adaptive 1` on POV-Ray's area light, --adaptive-lights for wsd. WSD_FLAGS adds more
# wsd render options, e.g. WSD_FLAGS=--adaptive-aa.
# Defaults are examples/cornell.wsd's settings: 1200x1200, 4 camera rays per pixel, 10x10 light, depth 5.
set -euo pipefail
cd "$(dirname "$0")/.."
size=${1:-1200}; threads=${2:-1}; adaptive=${3:-}
wsd=${WSD:-build/wsd}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
TIMEFORMAT='%U %S'

wsd_flags=(); pov_flags=()
if [[ $adaptive == --adaptive ]]; then wsd_flags=(--adaptive-lights); pov_flags=(Declare=ADAPTIVE=1); fi
read -r -a extra <<<"${WSD_FLAGS:-}"
wsd_flags+=("${extra[@]}")
echo "wsd flags: ${wsd_flags[*]:-none}; povray: ${pov_flags[*]:-full area light}; ${size}x${size}, ${threads} thread(s)"

t=$( { time "$wsd" render examples/cornell.wsd -o "$out/wsd.png" --width "$size" --height "$size" \
         --threads "$threads" --quiet --stats-json "$out/wsd.json" "${wsd_flags[@]}" >/dev/null 2>&1; } 2>&1 )
wsd_cpu=$(awk '{print $1 + $2}' <<<"$t")
wsd_rays=$(python3 -c "import json;d=json.load(open('$out/wsd.json'));print(d['camera_rays']+d['shadow_rays']+d['reflection_rays']+d['refraction_rays'])")
# Shadow rays whose shaft proved the answer (fully lit or fully blocked) and needed no traversal.
wsd_shaft=$(python3 -c "import json;print(json.load(open('$out/wsd.json')).get('shaft_answered_rays', 0))")

t=$( { time povray +Ibench/scenes/cornell.pov +O"$out/pov.png" +W"$size" +H"$size" +A0.0 +AM1 +R2 \
         +WT"$threads" -D -V "${pov_flags[@]}" >"$out/pov.log" 2>&1; } 2>&1 )
pov_cpu=$(awk '{print $1 + $2}' <<<"$t")
# POV-Ray's statistics: camera and secondary rays ("Rays"), plus every shadow ray test.
pov_rays=$(awk '/^Rays:/ {r=$2} /^Shadow Ray Tests:/ {s=$4} END {print r + s}' "$out/pov.log")

printf '%-8s %12s %14s %16s\n' renderer CPU-s ray-queries rays/CPU-s
printf '%-8s %12.2f %14d %16.0f\n' wsd "$wsd_cpu" "$wsd_rays" "$(awk "BEGIN{print $wsd_rays/$wsd_cpu}")"
printf '%-8s %12.2f %14d %16.0f\n' povray "$pov_cpu" "$pov_rays" "$(awk "BEGIN{print $pov_rays/$pov_cpu}")"
awk "BEGIN{printf \"wsd: %d of its shadow rays answered by their shaft alone; %.0f traversals per CPU-s\n\", $wsd_shaft, ($wsd_rays - $wsd_shaft)/$wsd_cpu}"
awk "BEGIN{printf \"povray/wsd CPU-time ratio: %.2f; rays/CPU-s ratio wsd/povray: %.2f\n\", $pov_cpu/$wsd_cpu, ($wsd_rays/$wsd_cpu)/($pov_rays/$pov_cpu)}"
