#!/usr/bin/env bash
# CTest: tools/animate.sh renders the frames of an animated scene and joins them into a GIF with
# one picture per frame (one fewer with --loop); bad options are usage errors and nothing is
# written then. Exits 77 (CTest's SKIP_RETURN_CODE) when ImageMagick is not installed.
# Usage: animate_gif.sh WSD SOURCE_DIR
set -euo pipefail
export WSD=$1
src=$2
if ! command -v convert >/dev/null 2>&1 || ! command -v identify >/dev/null 2>&1; then
  echo "SKIPPED: ImageMagick is not installed (apt-get install imagemagick)"
  exit 77
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/wsd-animate-XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"
opts=(--width 32 --height 20 --supersamples 1 --light-samples 1 --quiet)
bash "$src/tools/animate.sh" --frames 0-4 "$src/examples/bounce.wsd" all.gif "${opts[@]}"
[[ $(identify all.gif | wc -l) == 5 ]]
[[ $(identify -format '%w×%h\n' all.gif | head -1) == "32×20" ]]
bash "$src/tools/animate.sh" --frames 0-4 --loop --fps 25 "$src/examples/bounce.wsd" loop.gif "${opts[@]}"
[[ $(identify loop.gif | wc -l) == 4 ]]
[[ $(identify -format '%T\n' loop.gif | head -1) == 4 ]]  # 1/25 s, in hundredths
for bad in "--frames 5-1" "--frames x" "--fps 0"; do
  # shellcheck disable=SC2086
  if bash "$src/tools/animate.sh" $bad "$src/examples/bounce.wsd" bad.gif "${opts[@]}" 2>/dev/null; then
    echo "animate.sh accepted $bad" >&2; exit 1
  fi
done
[[ ! -e bad.gif ]]
echo "animate: GIFs have one picture per frame"
