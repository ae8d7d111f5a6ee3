#!/usr/bin/env bash
# CTest: docs/many-machines.md's GNU parallel recipes over frames, for real. Renders four frames of
# examples/bounce.wsd with one job per frame (`--frame {}`), then with every frame split into two
# tiles (one job per frame and tile) merged frame by frame; each frame must equal the same frame
# of a single `wsd render --frames` run, byte for byte.
# Exits 77 (CTest's SKIP_RETURN_CODE) when GNU parallel is not installed.
# Usage: parallel_frames.sh WSD SOURCE_DIR
set -euo pipefail
wsd=$1
src=$2
if ! command -v parallel >/dev/null 2>&1; then
  echo "SKIPPED: GNU parallel is not installed (apt-get install parallel)"
  exit 77
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/wsd-parallel-frames-XXXXXX")
trap 'rm -rf "$work"' EXIT
export PARALLEL_HOME="$work/.parallel"  # parallel keeps state there; never touch the real $HOME
cd "$work"
cp "$src/examples/bounce.wsd" scene.wsd
cp -r "$src/examples/include" include
opts=(--width 48 --height 30 --supersamples 1 --light-samples 2 --threads 1 --quiet)

mkdir whole frames
"$wsd" render scene.wsd "${opts[@]}" --frames 1-4 -o 'whole/frame-####.png'

# One job per frame.
seq 1 4 | parallel --will-cite -j 2 --halt now,fail=1 \
  "$wsd" render scene.wsd "${opts[@]}" --frames 1-4 --frame {} -o 'frames/frame-####.png'
for k in 1 2 3 4; do cmp "whole/frame-000$k.png" "frames/frame-000$k.png"; done

# One job per frame and tile (default names scene-####.tile-I-of-2.pfm), then one merge per frame.
parallel --will-cite -j 2 --halt now,fail=1 \
  "$wsd" render scene.wsd "${opts[@]}" --frames 1-4 --frame '{1}' --tile '{2}/2' ::: 1 2 3 4 ::: 1 2
tiles=(scene-*.tile-*.pfm)
[[ ${#tiles[@]} == 8 ]]
mkdir out
# shellcheck disable=SC2016  # {=…=} is parallel's Perl expression, not the shell's
parallel --will-cite -j 2 --halt now,fail=1 \
  "$wsd" merge 'scene-{=$_=sprintf("%04d",$_)=}.tile-*.pfm' -o 'out/frame-{=$_=sprintf("%04d",$_)=}.png' ::: 1 2 3 4
for k in 1 2 3 4; do cmp "whole/frame-000$k.png" "out/frame-000$k.png"; done
echo "parallel frames: every frame equals the single render"
