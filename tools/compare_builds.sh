#!/usr/bin/env bash
# Renders every example scene (and any extra scenes given) with two wsd binaries and compares the
# linear .pfm outputs byte for byte: a change that must not alter images is checked with
#   tools/compare_builds.sh OLD_WSD NEW_WSD [SCENE...]
# Renders are small (WSD_COMPARE_SIZE, default 96) and use every mode that picks a different path.
set -euo pipefail
old=$1 new=$2
shift 2
cd "$(dirname "$0")/.."
size=${WSD_COMPARE_SIZE:-96}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
scenes=(examples/*.wsd "$@")
modes=("" "--supersamples 1" "--supersamples 9" "--adaptive-aa" "--general" "--no-bvh" "--threads 1"
       "--light-samples 2" "--region 10,20,60,70")
fail=0 count=0
for scene in "${scenes[@]}"; do
  for mode in "${modes[@]}"; do
    # shellcheck disable=SC2086
    "$old" render -q --width "$size" --height "$size" $mode -o "$tmp/old.pfm" "$scene" 2>/dev/null || { echo "old build failed: $scene $mode"; fail=1; continue; }
    # shellcheck disable=SC2086
    "$new" render -q --width "$size" --height "$size" $mode -o "$tmp/new.pfm" "$scene" 2>/dev/null || { echo "new build failed: $scene $mode"; fail=1; continue; }
    count=$((count + 1))
    cmp -s "$tmp/old.pfm" "$tmp/new.pfm" || { echo "DIFFERS: $scene $mode"; fail=1; }
  done
done
echo "compared $count renders: $([[ $fail == 0 ]] && echo all identical || echo differences found)"
exit $fail
