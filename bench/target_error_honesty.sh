#!/usr/bin/env bash
# How far to trust `--target-error`'s own estimate: for every example scene (the scenes the gallery
# renders) and the scenes of bench/scenes/honesty-*.wsd (which the sampler was not tuned on: an
# image-textured floor at grazing angles, a glass sphere over a checker, a room lit only by an
# emissive sphere through indirect light), renders with `--target-error E` for each target and
# compares the image with a long reference of the same scene (`--target-error REF`, another
# seed, at most REF_TIME seconds: default 8) by `wsd diff` on display values. Prints one line per scene and target:
#   scene target estimated measured raw reference predicted ratio within
# estimated is the render's `estimated_rmse` (--stats-json), measured the RMSE `wsd diff` reports
# against the reference, raw = measured / estimated. The reference has its own error (its
# estimate: reference; at most 1024 samples a pixel, and slow scenes stop at REF_TIME),
# and independent errors add in quadrature: an honest estimate predicts a measured RMSE of
# sqrt(estimated² + reference²) (predicted), and ratio = measured / predicted. within is "yes"
# where ratio lies between 1/1.5 and 1.5. A last line counts the renders within 1.5×, by ratio
# and by raw.
# Usage: bench/target_error_honesty.sh [WIDTH=80] [HEIGHT=60] [TARGETS="0.02 0.01"] [REF=0.0025]
# THREADS (default 2) sets the render threads: with a target the image does not depend on them.
# WSD names the executable (default build/wsd). About 2 CPU-minutes at the defaults (the references
# are bounded by wall time: at most 19 × REF_TIME seconds).
set -euo pipefail
cd "$(dirname "$0")/.."
width=${1:-80}; height=${2:-60}; targets=${3:-0.02 0.01}; ref_target=${4:-0.0025}
wsd=${WSD:-build/wsd}
threads=${THREADS:-2}
ref_time=${REF_TIME:-8}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

json() { python3 -c "import json, sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$@"; }
render() {  # render SCENE OUT TARGET [options...]
  local scene=$1 image=$2 target=$3; shift 3
  "$wsd" render "$scene" -o "$image" --width "$width" --height "$height" --threads "$threads" \
    --target-error "$target" --stats-json "${image%.pfm}.json" --quiet "$@"
}

echo "${width}x${height}; targets $targets; reference --target-error $ref_target --time-limit $ref_time --seed 7919; $threads thread(s)"
printf '%-20s %6s %9s %9s %6s %9s %9s %6s %s\n' scene target estimated measured raw reference predicted ratio within
total=0 within=0 within_raw=0
for scene in examples/*.wsd bench/scenes/honesty-*.wsd; do
  name=$(basename "$scene" .wsd)
  render "$scene" "$out/ref.pfm" "$ref_target" --seed 7919 --time-limit "$ref_time"
  ref_est=$(json "$out/ref.json" estimated_rmse)
  for target in $targets; do
    render "$scene" "$out/img.pfm" "$target"
    est=$(json "$out/img.json" estimated_rmse)
    measured=$("$wsd" diff "$out/img.pfm" "$out/ref.pfm" | awk '/^RMSE:/ { print $2 }')
    awk -v n="$name" -v t="$target" -v m="$measured" -v e="$est" -v r="$ref_est" 'BEGIN {
      p = sqrt(e * e + r * r); raw = (e > 0) ? m / e : 0; q = (p > 0) ? m / p : 0
      printf "%-20s %6s %9.6f %9.6f %6.3f %9.6f %9.6f %6.3f %s %s\n", n, t, e, m, raw, r, p, q,
             (q >= 1 / 1.5 && q <= 1.5) ? "yes" : "no", (raw >= 1 / 1.5 && raw <= 1.5) ? "" : "(raw outside)" }' >"$out/line"
    cat "$out/line"
    total=$((total + 1))
    grep -q ' yes' "$out/line" && within=$((within + 1))
    grep -q 'raw outside' "$out/line" || within_raw=$((within_raw + 1))
  done
done
echo "within 1.5x: $within of $total by ratio, $within_raw of $total by raw"
