#!/usr/bin/env bash
# CTest: the frame-array form of tools/slurm-render.sh, run locally as Slurm would run it (one
# process per array task with SLURM_ARRAY_TASK_ID set). Array task K renders frame K; with
# --tiles 3 the tasks 0 … 3·F−1 render the tiles of every frame and a second array merges them,
# frame by frame. Every frame must equal the same frame of one `wsd render --frames` run, byte for
# byte. Tasks outside the range are refused, and a missing tile is named.
# Usage: slurm_frames.sh WSD SOURCE_DIR
set -euo pipefail
export WSD=$1
src=$2
script="$src/tools/slurm-render.sh"
work=$(mktemp -d "${TMPDIR:-/tmp}/wsd-slurm-frames-XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"
scene="$src/examples/bounce.wsd"
opts=(--width 48 --height 30 --supersamples 1 --light-samples 2)
unset SLURM_ARRAY_TASK_ID SLURM_ARRAY_TASK_COUNT SLURM_ARRAY_TASK_MIN SLURM_CPUS_PER_TASK

mkdir whole
"$WSD" render "$scene" "${opts[@]}" --quiet --frames 2-5 -o 'whole/f-#.png'

# --array=2-5: task K renders frame K.
for k in 2 3 4 5; do
  SLURM_ARRAY_TASK_ID=$k SLURM_ARRAY_TASK_COUNT=4 SLURM_CPUS_PER_TASK=1 \
    bash "$script" --frames 2-5 "$scene" frames "${opts[@]}"
done
[[ $(ls frames) == $'frame-0002.png\nframe-0003.png\nframe-0004.png\nframe-0005.png' ]]
for k in 2 3 4 5; do cmp "whole/f-$k.png" "frames/frame-000$k.png"; done

# --tiles 3: tasks 0 … 11 (4 frames × 3 tiles), then the merge array (task K merges frame K).
for t in $(seq 0 11); do
  SLURM_ARRAY_TASK_ID=$t bash "$script" --frames 2-5 --tiles 3 "$scene" tiles "${opts[@]}" --threads 1
done
parts=(tiles/*)
[[ ${#parts[@]} == 12 ]]
ls tiles/frame-0004.tile-2-of-3.pfm >/dev/null
for k in 2 3 4 5; do
  SLURM_ARRAY_TASK_ID=$k bash "$script" --merge --frames 2-5 tiles 'merged/m-##.png'
done
for k in 2 3 4 5; do cmp "whole/f-$k.png" "merged/m-0$k.png"; done
# Without an array, the merge step merges every frame in turn.
bash "$script" --merge --frames 2-5 tiles 'all/m-#.pfm'
"$WSD" render "$scene" "${opts[@]}" --quiet --frames 2-5 --frame 4 -o single.pfm
cmp single.pfm all/m-4.pfm

# Tasks outside the range are refused before rendering.
if SLURM_ARRAY_TASK_ID=6 bash "$script" --frames 2-5 "$scene" bad "${opts[@]}" 2>/dev/null; then
  echo "frame 6 of 2-5 was accepted" >&2; exit 1
fi
if SLURM_ARRAY_TASK_ID=12 bash "$script" --frames 2-5 --tiles 3 "$scene" bad "${opts[@]}" 2>/dev/null; then
  echo "task 12 of 4 frames × 3 tiles was accepted" >&2; exit 1
fi
[[ -z $(ls bad 2>/dev/null) ]]

# The merge step fails, naming the tile, when one is missing.
rm tiles/frame-0003.tile-2-of-3.pfm
if SLURM_ARRAY_TASK_ID=3 bash "$script" --merge --frames 2-5 tiles 'broken-#.png' 2>err.txt; then
  echo "merge accepted a missing tile" >&2; exit 1
fi
grep -q "2/3" err.txt
[[ ! -e broken-3.png ]]
echo "slurm frames: every frame equals the single render"
