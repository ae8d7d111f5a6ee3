#!/usr/bin/env bash
# The Cornell box at equal error: POV-Ray's adaptive area light beside wsd's default settings and
# wsd's targeted mode, in one run, one renderer after the other. wsd's errors are measured by
# `wsd diff` (display values) against a converged reference of the same scene at the same size:
# `--target-error REF` (default 0.002) with `exact_area_lights on` (the limit the light's cells
# converge to) and another seed, at most REF_TIME seconds (default 600), rendered once on all
# cores and cached in CACHE (default build/bench-cache), keyed by the scene, the size, REF and
# `wsd --version` (delete the cache when the renderer's model changes). The reference keeps an
# error of its own (its estimate), which adds to each row's in quadrature: a row's own error is
# sqrt(RMSE² − reference²) (net). The rows:
#   povray    bench/scenes/cornell.pov with `adaptive 1` (as cornell_vs_povray.sh --adaptive);
#             its RMSE against wsd's reference includes the two renderers' differences of model
#   default   examples/cornell.wsd as it is (4 camera rays a pixel, the full 10×10 light)
#   exact     --adaptive-lights and `exact_area_lights on`, 4 camera rays a pixel
#   targeted  --adaptive-lights, `exact_area_lights on` and --target-error E, for each E in
#             TARGETS (default "0.08 0.04 0.02"). The target bounds each pixel's own estimated
#             error, so the image's error ends well below it; the question is which target
#             reaches the default row's error, and at what cost
# Each line: row CPU-s RMSE net estimated-RMSE (or -) CPU-ratio (POV-Ray ÷ row); the reference's
# own estimate comes first, the verdict last: the cheapest targeted row whose net error is at most
# the default row's. CPU-s is user + system time of the whole process.
# Usage: bench/cornell_targeted.sh [SIZE=1200] [THREADS=1]; WSD names the executable (default
# build/wsd); REF and CACHE as above. About 2 CPU-minutes, plus the reference the first time.
set -euo pipefail
cd "$(dirname "$0")/.."
size=${1:-1200}; threads=${2:-1}
wsd=${WSD:-build/wsd}
ref_target=${REF:-0.002}
targets=${TARGETS:-0.08 0.04 0.02}
ref_time=${REF_TIME:-600}
cache=${CACHE:-build/bench-cache}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
TIMEFORMAT='%U %S'
command -v povray >/dev/null || { echo "cornell_targeted: povray is not installed" >&2; exit 3; }

# The scene with exact_area_lights on, beside a link to the textures it names.
mkdir "$out/scene"
ln -s "$PWD/examples/textures" "$out/scene/textures"
sed 's/^settings {/settings { exact_area_lights on /' examples/cornell.wsd >"$out/scene/cornell.wsd"
grep -q '^settings { exact_area_lights on' "$out/scene/cornell.wsd" || { echo "cornell_targeted: no settings line" >&2; exit 1; }

json() { python3 -c "import json, sys; v = json.load(open(sys.argv[1])).get(sys.argv[2]); print('-' if v is None else v)" "$@"; }
rmse() { "$wsd" diff "$1" "$reference" | awk '/^RMSE:/ { print $2 }'; }
cpu_of() { awk '{ print $1 + $2 }' <<<"$1"; }

mkdir -p "$cache"
key=$( { cat examples/cornell.wsd; echo "$size $ref_target $ref_time"; "$wsd" --version; } | sha256sum | cut -c1-16)
reference=$cache/cornell-reference-$size-$key.pfm
if [[ ! -f $reference ]]; then
  echo "cornell_targeted: rendering the reference (--target-error $ref_target at ${size}x${size}, all cores)" >&2
  "$wsd" render "$out/scene/cornell.wsd" -o "$out/reference.pfm" --width "$size" --height "$size" --threads 0 \
    --target-error "$ref_target" --time-limit "$ref_time" --seed 7919 --stats-json "$out/reference.json" --quiet
  mv "$out/reference.json" "${reference%.pfm}.json"
  mv "$out/reference.pfm" "$reference"
fi
ref_est=$(json "${reference%.pfm}.json" estimated_rmse)
echo "reference ${size}x${size} --target-error $ref_target: estimated RMSE $ref_est"
net() { awk -v m="$1" -v r="$ref_est" 'BEGIN { d = m * m - r * r; printf "%.6f", (d > 0) ? sqrt(d) : 0 }'; }

wsd_run() {  # wsd_run NAME SCENE [options...]: prints CPU-s
  local name=$1 scene=$2 t; shift 2
  t=$( { time "$wsd" render "$scene" -o "$out/$name.pfm" --width "$size" --height "$size" --threads "$threads" \
           --quiet --stats-json "$out/$name.json" "$@" >/dev/null 2>&1; } 2>&1 )
  cpu_of "$t"
}

t=$( { time povray +Ibench/scenes/cornell.pov +O"$out/pov.png" +W"$size" +H"$size" +A0.0 +AM1 +R2 \
         +WT"$threads" -D -V Declare=ADAPTIVE=1 >"$out/pov.log" 2>&1; } 2>&1 )
pov_cpu=$(cpu_of "$t")
pov_rmse=$(rmse "$out/pov.png")

default_cpu=$(wsd_run default examples/cornell.wsd)
default_rmse=$(rmse "$out/default.pfm")
exact_cpu=$(wsd_run exact "$out/scene/cornell.wsd" --adaptive-lights)
exact_rmse=$(rmse "$out/exact.pfm")
printf '%-9s %8s %10s %10s %10s %10s\n' row CPU-s RMSE net estimated pov/row
line() { printf '%-9s %8.2f %10.6f %10s %10s %10s\n' "$1" "$2" "$3" "$(net "$3")" "$4" "$(awk -v p="$pov_cpu" -v c="$2" 'BEGIN { printf "%.2f", p / c }')"; }
line povray "$pov_cpu" "$pov_rmse" -
line default "$default_cpu" "$default_rmse" -
line exact "$exact_cpu" "$exact_rmse" -
default_net=$(net "$default_rmse")
best=""
for target in $targets; do
  cpu=$(wsd_run "targeted-$target" "$out/scene/cornell.wsd" --adaptive-lights --target-error "$target")
  r=$(rmse "$out/targeted-$target.pfm")
  est=$(json "$out/targeted-$target.json" estimated_rmse)
  spp=$(python3 -c "import json, sys; s = json.load(open(sys.argv[1]))['samples_per_pixel']; print('%s/%s/%s' % (s['min'], s['median'], s['max']))" "$out/targeted-$target.json")
  line "targeted" "$cpu" "$r" "$(awk -v e="$est" 'BEGIN { printf "%.6f", e }')" | sed "s|\$| $target $spp|"
  if [[ -z $best ]] && awk -v a="$(net "$r")" -v b="$default_net" 'BEGIN { exit !(a <= b) }'; then
    best="$target $cpu $(net "$r") $(awk -v p="$pov_cpu" -v c="$cpu" 'BEGIN { printf "%.2f", p / c }')"
  fi
done
# The cheapest target is the largest: TARGETS lists them from the largest down.
echo "verdict default-net $default_net targeted ${best:-none}"
