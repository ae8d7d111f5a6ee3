#!/usr/bin/env bash
# CTest: tools/slurm-render.sh run locally as Slurm would run it, one process per array task with
# SLURM_ARRAY_TASK_ID / SLURM_ARRAY_TASK_COUNT (/ SLURM_ARRAY_TASK_MIN) set, then its --merge
# step; the merged image must equal a single render byte for byte. Covers a 1-based array
# (--array=1-4) and a 0-based one (--array=0-2), and a task outside the range.
# Usage: slurm_tiles.sh WSD SOURCE_DIR
set -euo pipefail
export WSD=$1
src=$2
script="$src/tools/slurm-render.sh"
work=$(mktemp -d "${TMPDIR:-/tmp}/wsd-slurm-XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"
scene="$src/examples/cornell.wsd"
opts=(--width 64 --height 64 --light-samples 2)
unset SLURM_ARRAY_TASK_ID SLURM_ARRAY_TASK_COUNT SLURM_ARRAY_TASK_MIN SLURM_CPUS_PER_TASK

"$WSD" render "$scene" "${opts[@]}" --quiet -o whole.png

# --array=1-4: SLURM_ARRAY_TASK_MIN is 1 (also the default when it is unset).
for id in 1 2 3 4; do
  SLURM_ARRAY_TASK_ID=$id SLURM_ARRAY_TASK_COUNT=4 SLURM_CPUS_PER_TASK=1 bash "$script" "$scene" tiles4 "${opts[@]}"
done
[[ $(ls tiles4) == $'tile-1.pfm\ntile-2.pfm\ntile-3.pfm\ntile-4.pfm' ]]
bash "$script" --merge tiles4 merged4.png
cmp whole.png merged4.png

# --array=0-2: three tasks numbered from 0 still make tiles 1/3 … 3/3; the caller's --threads wins.
for id in 0 1 2; do
  SLURM_ARRAY_TASK_ID=$id SLURM_ARRAY_TASK_COUNT=3 SLURM_ARRAY_TASK_MIN=0 \
    bash "$script" "$scene" tiles3 "${opts[@]}" --threads 1
done
[[ $(ls tiles3) == $'tile-1.pfm\ntile-2.pfm\ntile-3.pfm' ]]
bash "$script" --merge tiles3 merged3.png
cmp whole.png merged3.png

# A task outside the range, or no array at all, is refused before rendering.
if SLURM_ARRAY_TASK_ID=5 SLURM_ARRAY_TASK_COUNT=4 bash "$script" "$scene" bad "${opts[@]}" 2>/dev/null; then
  echo "task 5 of 4 was accepted" >&2; exit 1
fi
if bash "$script" "$scene" bad "${opts[@]}" 2>/dev/null; then
  echo "ran outside an array job" >&2; exit 1
fi
[[ ! -e bad ]]

# The merge step fails, naming the tile, when one is missing.
rm tiles4/tile-3.pfm
if bash "$script" --merge tiles4 broken.png 2>err.txt; then
  echo "merge accepted a missing tile" >&2; exit 1
fi
grep -q "3/4" err.txt
[[ ! -e broken.png ]]
echo "slurm tiles: all merges equal the single render"
