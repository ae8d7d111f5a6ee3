#!/usr/bin/env bash
# Renders one scene on a Slurm cluster as a job array: array task K renders tile I/N of the image
# (I counted from 1, N = the number of tasks), then a dependent job merges the tiles. With
# --frames, it renders an animation: array task K renders frame K (and with --tiles N, each
# frame is split into N tiles that a dependent array merges, frame by frame).
#
#   jid=$(sbatch --parsable --array=1-16 tools/slurm-render.sh scene.wsd tiles/ --width 3840 --height 2160)
#   sbatch --dependency=afterok:$jid tools/slurm-render.sh --merge tiles/ scene.png
#
#   sbatch --array=1-48 tools/slurm-render.sh --frames 1-48 scene.wsd frames/
#
#   jid=$(sbatch --parsable --array=0-191 tools/slurm-render.sh --frames 1-48 --tiles 4 scene.wsd tiles/)
#   sbatch --dependency=afterok:$jid --array=1-48 tools/slurm-render.sh --merge --frames 1-48 tiles/ 'out/frame-####.png'
#
# Render mode: slurm-render.sh SCENE TILE_DIR [wsd render options...]
#   writes TILE_DIR/tile-I.pfm. The array must be one contiguous range (1-16, 0-15 or 1-16%4 all
#   give tiles 1/16 … 16/16); the scene and the files it names must be at the same path on every
#   node (a shared file system), as must TILE_DIR. --threads defaults to the task's CPUs.
# Merge mode:  slurm-render.sh --merge TILE_DIR OUT
#   merges TILE_DIR/tile-*.pfm into OUT. `wsd merge` refuses a missing, duplicate or stale tile
#   and names it, so an empty TILE_DIR per render is best.
# Frames:      slurm-render.sh --frames A-B SCENE DIR [wsd render options...]
#   array task K renders frame K of A-B into DIR/frame-####.png (K zero-padded to four digits);
#   any array within A-B works (--array=1-48, or --array=7 to render frame 7 again).
# Frames in tiles: slurm-render.sh --frames A-B --tiles N SCENE DIR [wsd render options...]
#   the array counts frames × tiles: --array=0-M with M = (B−A+1)·N − 1; task T renders tile
#   T mod N + 1 of frame A + T div N into DIR/frame-####.tile-I-of-N.pfm.
# Merging frames: slurm-render.sh --merge --frames A-B DIR OUT_PATTERN
#   merges the tiles of each frame in DIR into OUT_PATTERN with its '#'s replaced by the frame
#   number (zero-padded), as wsd names frames; as an array task K it merges frame K only.
# The wsd executable is $WSD if set, else `wsd` on the PATH. Outside Slurm (a test, or by hand)
# set SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT (and SLURM_ARRAY_TASK_MIN if not 1) yourself.
#
#SBATCH --job-name=wsd-render
#SBATCH --array=1-16
#SBATCH --cpus-per-task=4
#SBATCH --output=wsd-render-%A_%a.log
set -euo pipefail
wsd=${WSD:-wsd}

merge=0; frames=; tiles=
while (($#)); do
  case $1 in
    --merge) merge=1; shift ;;
    --frames) frames=${2:?--frames needs A-B}; shift 2 ;;
    --tiles) tiles=${2:?--tiles needs a number}; shift 2 ;;
    *) break ;;
  esac
done
if [[ -n $frames ]]; then
  if [[ ! $frames =~ ^([0-9]+)-([0-9]+)$ ]] || ((10#${BASH_REMATCH[1]} > 10#${BASH_REMATCH[2]})); then
    echo "$0: --frames: expected A-B with A <= B, got '$frames'" >&2
    exit 2
  fi
  first=$((10#${BASH_REMATCH[1]})); last=$((10#${BASH_REMATCH[2]}))
fi
if [[ -n $tiles ]] && { [[ -z $frames ]] || [[ ! $tiles =~ ^[1-9][0-9]*$ ]]; }; then
  echo "$0: --tiles N needs --frames A-B and a whole number N >= 1 (for a still, the array size is the tile count)" >&2
  exit 2
fi

# PATTERN FRAME: PATTERN with each run of '#' replaced by FRAME, zero-padded to the run's length.
frame_name() {
  local rest=$1 name=
  while [[ $rest =~ ^([^#]*)(#+)(.*)$ ]]; do
    name+=${BASH_REMATCH[1]}$(printf "%0${#BASH_REMATCH[2]}d" "$2")
    rest=${BASH_REMATCH[3]}
  done
  echo "$name$rest"
}

if ((merge)) && [[ -n $frames ]]; then
  if [[ $# -ne 2 ]]; then
    echo "usage: $0 --merge --frames A-B DIR OUT_PATTERN" >&2
    exit 2
  fi
  shopt -s nullglob
  list=("${SLURM_ARRAY_TASK_ID:-}")
  [[ -n ${list[0]} ]] || mapfile -t list < <(seq "$first" "$last")
  for k in "${list[@]}"; do
    if ((k < first || k > last)); then
      echo "$0: array task $k is not a frame of $frames" >&2
      exit 2
    fi
    parts=("$1"/"$(frame_name "frame-####" "$k")".tile-*.pfm)
    if ((${#parts[@]} == 0)); then
      echo "$0: no tiles of frame $k in '$1'" >&2
      exit 1
    fi
    out=$(frame_name "$2" "$k")
    mkdir -p "$(dirname "$out")"
    "$wsd" merge "${parts[@]}" -o "$out"
  done
  exit 0
fi

if ((merge)); then
  if [[ $# -ne 2 ]]; then
    echo "usage: $0 --merge TILE_DIR OUT" >&2
    exit 2
  fi
  shopt -s nullglob
  parts=("$1"/tile-*.pfm)
  if ((${#parts[@]} == 0)); then
    echo "$0: no tiles (tile-*.pfm) in '$1'" >&2
    exit 1
  fi
  exec "$wsd" merge "${parts[@]}" -o "$2"
fi

if [[ $# -lt 2 ]]; then
  echo "usage: $0 [--frames A-B [--tiles N]] SCENE DIR [wsd render options...]   (as a Slurm array job)" >&2
  exit 2
fi
scene=$1
dir=$2
shift 2
id=${SLURM_ARRAY_TASK_ID:?not a Slurm array task: SLURM_ARRAY_TASK_ID is not set}
threads=(--threads "${SLURM_CPUS_PER_TASK:-0}")
for arg in "$@"; do [[ $arg == --threads* ]] && threads=(); done  # the caller's own --threads wins

if [[ -n $frames ]]; then
  mkdir -p "$dir"
  if [[ -z $tiles ]]; then
    exec "$wsd" render "$scene" "${threads[@]}" --quiet "$@" --frames "$frames" --frame "$id" \
      -o "$dir/frame-####.png"
  fi
  if ((id < 0 || id >= (last - first + 1) * tiles)); then
    echo "$0: array task $id is not in 0..$(((last - first + 1) * tiles - 1)) ($frames × $tiles tiles)" >&2
    exit 2
  fi
  tile=$((id % tiles + 1))
  exec "$wsd" render "$scene" "${threads[@]}" --quiet "$@" --frames "$frames" --frame "$((first + id / tiles))" \
    --tile "$tile/$tiles" -o "$dir/frame-####.tile-$tile-of-$tiles.pfm"
fi
count=${SLURM_ARRAY_TASK_COUNT:?not a Slurm array task: SLURM_ARRAY_TASK_COUNT is not set}
min=${SLURM_ARRAY_TASK_MIN:-1}
index=$((id - min + 1))
if ((index < 1 || index > count)); then
  echo "$0: array task $id is not in the contiguous range $min..$((min + count - 1))" >&2
  exit 2
fi
mkdir -p "$dir"
exec "$wsd" render "$scene" "${threads[@]}" --quiet "$@" --tile "$index/$count" -o "$dir/tile-$index.pfm"
