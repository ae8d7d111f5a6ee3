#!/usr/bin/env bash
# CI: shows that results do not depend on FMA contraction (docs/robustness.md: build invariance, R53).
# Builds wsd and the render suite with -ffp-contract=fast -mfma in build-fpc, runs the render
# suite there (watertightness, offsets, scale invariance, every hard case), then renders every
# example at 64x64 with both the contracted build and the Release build (build/, made by
# ./test.sh before this step) and requires the images to agree to within rounding: PSNR >= 40 dB.
# Skips the FMA part with a message on a processor without FMA (the build then has no FMA).
set -euo pipefail
cd "$(dirname "$0")/.."
build="${WSD_FPC_BUILD_DIR:-build-fpc}"
ref="${WSD_BUILD_DIR:-build}"

if ! grep -qw fma /proc/cpuinfo 2>/dev/null; then
  echo "fp-contract: this processor has no FMA instructions; nothing can be contracted, skipped"
  exit 0
fi
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DWSD_FP_CONTRACT_FAST=ON >/dev/null
cmake --build "$build" -j"$(nproc)" --target wsd_render_tests wsd
# The render suite's own assertions under contraction (no NaN, watertight meshes, invariances).
"$build/wsd_render_tests"

if [[ ! -x "$ref/wsd" ]]; then
  echo "fp-contract: no reference build in $ref (run ./test.sh first)" >&2
  exit 1
fi
out=$(mktemp -d "${TMPDIR:-/tmp}/wsd-fpc-XXXXXX")
trap 'rm -rf "$out"' EXIT
n=0
for scene in examples/*.wsd; do
  name=$(basename "$scene" .wsd)
  "$ref/wsd" render "$scene" --width 64 --height 64 --quiet -o "$out/$name-ref.pfm"
  "$build/wsd" render "$scene" --width 64 --height 64 --quiet -o "$out/$name-fma.pfm"
  psnr=$("$ref/wsd" diff "$out/$name-ref.pfm" "$out/$name-fma.pfm" | awk '/^PSNR/ {print $2}')
  same="differs in the float values"
  cmp -s "$out/$name-ref.pfm" "$out/$name-fma.pfm" && same="bit-identical"
  echo "fp-contract: $name: PSNR $psnr dB, $same (contracted against plain)"
  if [[ $psnr != inf ]] && awk -v p="$psnr" 'BEGIN{exit !(p < 40)}'; then
    echo "fp-contract: $name differs beyond rounding under -ffp-contract=fast" >&2
    exit 1
  fi
  n=$((n + 1))
done
echo "fp-contract: $n examples agree (PSNR >= 40 dB) with and without FMA contraction"
