#!/usr/bin/env bash
# Caustics, accuracy against time: examples/cornell-caustics.wsd rendered by wsd and its POV-Ray
# port (bench/scenes/cornell-caustics.pov, Debian's povray) with the same photon counts, each
# compared with wsd's converged reference (32 times the most photons, 16 rays a pixel): CPU
# seconds of the whole process and the error (`wsd diff`: RMSE and PSNR on display values).
# Usage: bench/caustics_vs_povray.sh [SIZE=300] [THREADS=1] [COUNTS="25000 100000 400000"]
set -euo pipefail
cd "$(dirname "$0")/.."
size=${1:-300}; threads=${2:-1}; counts=${3:-"25000 100000 400000"}
wsd=${WSD:-build/wsd}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
TIMEFORMAT='%U %S'
scene=examples/cornell-caustics.wsd

# The scene with another photon count and sampling: its settings line rewritten.
variant() {  # PHOTONS SUPERSAMPLES FILE
  sed -E "s/caustic_photons [0-9]+/caustic_photons $1/; s/supersamples [0-9]+/supersamples $2/" "$scene" >"$3"
}
cpu_of() { awk '{print $1 + $2}' <<<"$1"; }
error_of() {  # IMAGE: "RMSE PSNR" against the reference
  "$wsd" diff "$out/ref.pfm" "$1" | awk '/^RMSE/ {r = $2} /^PSNR/ {p = $2} END {print r, p}'
}

largest=0
for n in $counts; do ((n > largest)) && largest=$n; done
variant $((32 * largest)) 16 "$out/ref.wsd"
cp -r examples/include examples/textures examples/models "$out/" 2>/dev/null || true
"$wsd" render "$out/ref.wsd" -o "$out/ref.pfm" --width "$size" --height "$size" --threads "$threads" --quiet

printf '%-8s %10s %10s %10s %10s\n' renderer photons CPU-s RMSE PSNR
for n in $counts; do
  variant "$n" 4 "$out/wsd-$n.wsd"
  t=$( { time "$wsd" render "$out/wsd-$n.wsd" -o "$out/wsd-$n.png" --width "$size" --height "$size" \
           --threads "$threads" --quiet >/dev/null 2>&1; } 2>&1 )
  read -r rmse psnr <<<"$(error_of "$out/wsd-$n.png")"
  printf '%-8s %10d %10.2f %10s %10s\n' wsd "$n" "$(cpu_of "$t")" "$rmse" "$psnr"
done
if command -v povray >/dev/null; then
  for n in $counts; do
    t=$( { time povray +Ibench/scenes/cornell-caustics.pov +O"$out/pov-$n.png" +W"$size" +H"$size" \
             +A0.0 +AM1 +R2 +WT"$threads" -D -V Declare=PHOTONS="$n" >"$out/pov-$n.log" 2>&1; } 2>&1 )
    read -r rmse psnr <<<"$(error_of "$out/pov-$n.png")"
    printf '%-8s %10d %10.2f %10s %10s\n' povray "$n" "$(cpu_of "$t")" "$rmse" "$psnr"
  done
else
  echo "povray: not installed"
fi
