#!/usr/bin/env bash
# CTest: the README's GNU parallel recipe, for real. Renders examples/cornell.wsd at 64×64 as four
# --tile I/N tiles with `parallel -j 2`, merges them and compares the result byte for byte with
# a single render; then the same with a 2×2 grid of --region rectangles, and once more through
# `--sshlogin :` (parallel's name for the local host: no ssh involved).
# Exits 77 (CTest's SKIP_RETURN_CODE) when GNU parallel is not installed.
# Usage: parallel_tiles.sh WSD SOURCE_DIR
set -euo pipefail
wsd=$1
src=$2
if ! command -v parallel >/dev/null 2>&1; then
  echo "SKIPPED: GNU parallel is not installed (apt-get install parallel)"
  exit 77
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/wsd-parallel-XXXXXX")
trap 'rm -rf "$work"' EXIT
export PARALLEL_HOME="$work/.parallel"  # parallel keeps state there; never touch the real $HOME
cd "$work"
scene="$src/examples/cornell.wsd"
# Small and cheap (a 2×2 light grid), but every effect of the scene is still rendered.
opts=(--width 64 --height 64 --light-samples 2 --threads 1 --quiet)

"$wsd" render "$scene" "${opts[@]}" -o whole.png
"$wsd" render "$scene" "${opts[@]}" -o whole.pfm

# Tiles: job I of 4 renders --tile I/4 ({#} is parallel's job number, counting from 1).
parallel --will-cite -j 2 --halt now,fail=1 \
  "$wsd" render "$scene" "${opts[@]}" --tile '{#}/4' -o 'tile-{#}.pfm' ::: 1 2 3 4
ls tile-1.pfm tile-2.pfm tile-3.pfm tile-4.pfm >/dev/null
"$wsd" merge tile-*.pfm -o merged.png
"$wsd" merge tile-4.pfm tile-2.pfm tile-3.pfm tile-1.pfm -o merged.pfm
cmp whole.png merged.png
cmp whole.pfm merged.pfm

# Regions: a 2×2 grid of unequal rectangles, one argument per job.
parallel --will-cite -j 2 --halt now,fail=1 \
  "$wsd" render "$scene" "${opts[@]}" --region '{}' -o 'region-{#}.pfm' \
  ::: 0,0,40,23 40,0,64,23 0,23,40,64 40,23,64,64
"$wsd" merge region-*.pfm -o merged-regions.png
cmp whole.png merged-regions.png

# The --sshlogin recipe with ':' (the local host, run without ssh). This checks the command line
# only: for ':' parallel transfers nothing and ignores --return (with a warning).
mkdir ssh && cd ssh
parallel --will-cite -j 2 --halt now,fail=1 --sshlogin : --return 'tile-{}.pfm' --cleanup \
  "$wsd" render "$scene" "${opts[@]}" --tile '{}/3' -o 'tile-{}.pfm' ::: 1 2 3
"$wsd" merge tile-1.pfm tile-2.pfm tile-3.pfm -o merged.png
cmp ../whole.png merged.png

# A missing tile is caught by merge, and the message names it.
rm tile-2.pfm
if "$wsd" merge tile-1.pfm tile-3.pfm -o broken.png 2>err.txt; then
  echo "merge accepted a missing tile" >&2
  exit 1
fi
grep -q "2/3" err.txt
[[ ! -e broken.png ]]
echo "parallel tiles: all merges equal the single render"
