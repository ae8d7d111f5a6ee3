#!/usr/bin/env bash
# Renders one scene on a Slurm cluster as a job array: array task K renders tile I/N of the image
# (I counted from 1, N = the number of tasks), then a dependent job merges the tiles.
#
#   jid=$(sbatch --parsable --array=1-16 tools/slurm-render.sh scene.wsd tiles/ --width 3840 --height 2160)
#   sbatch --dependency=afterok:$jid tools/slurm-render.sh --merge tiles/ scene.png
#
# Render mode: slurm-render.sh SCENE TILE_DIR [wsd render options...]
#   writes TILE_DIR/tile-I.pfm. The array must be one contiguous range (1-16, 0-15 or 1-16%4 all
#   give tiles 1/16 … 16/16); the scene and the files it names must be at the same path on every
#   node (a shared file system), as must TILE_DIR. --threads defaults to the task's CPUs.
# Merge mode:  slurm-render.sh --merge TILE_DIR OUT
#   merges TILE_DIR/tile-*.pfm into OUT. `wsd merge` refuses a missing, duplicate or stale tile
#   and names it, so an empty TILE_DIR per render is best.
# The wsd executable is $WSD if set, else `wsd` on the PATH. Outside Slurm (a test, or by hand)
# set SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT (and SLURM_ARRAY_TASK_MIN if not 1) yourself.
#
#SBATCH --job-name=wsd-render
#SBATCH --array=1-16
#SBATCH --cpus-per-task=4
#SBATCH --output=wsd-render-%A_%a.log
set -euo pipefail
wsd=${WSD:-wsd}

if [[ "${1:-}" == "--merge" ]]; then
  if [[ $# -ne 3 ]]; then
    echo "usage: $0 --merge TILE_DIR OUT" >&2
    exit 2
  fi
  shopt -s nullglob
  tiles=("$2"/tile-*.pfm)
  if ((${#tiles[@]} == 0)); then
    echo "$0: no tiles (tile-*.pfm) in '$2'" >&2
    exit 1
  fi
  exec "$wsd" merge "${tiles[@]}" -o "$3"
fi

if [[ $# -lt 2 ]]; then
  echo "usage: $0 SCENE TILE_DIR [wsd render options...]   (as a Slurm array job)" >&2
  exit 2
fi
scene=$1
dir=$2
shift 2
id=${SLURM_ARRAY_TASK_ID:?not a Slurm array task: SLURM_ARRAY_TASK_ID is not set}
count=${SLURM_ARRAY_TASK_COUNT:?not a Slurm array task: SLURM_ARRAY_TASK_COUNT is not set}
min=${SLURM_ARRAY_TASK_MIN:-1}
index=$((id - min + 1))
if ((index < 1 || index > count)); then
  echo "$0: array task $id is not in the contiguous range $min..$((min + count - 1))" >&2
  exit 2
fi
threads=(--threads "${SLURM_CPUS_PER_TASK:-0}")
for arg in "$@"; do [[ $arg == --threads* ]] && threads=(); done  # the caller's own --threads wins
mkdir -p "$dir"
exec "$wsd" render "$scene" "${threads[@]}" --quiet "$@" --tile "$index/$count" -o "$dir/tile-$index.pfm"
