#!/usr/bin/env bash
# Renders the frames of an animated scene (one that uses `clock` or `frame`) with
# `wsd render --frames A-B` and joins them into a GIF with ImageMagick, or into a video (.mp4,
# .webm, .mkv) with ffmpeg (Debian: apt-get install imagemagick, or ffmpeg).
#
# Usage: tools/animate.sh [--frames A-B] [--fps N] [--loop] SCENE OUT [wsd render options...]
#   --frames A-B  the frames to render (default 0-36: clock goes 0, 1/36, …, 1)
#   --fps N       frames a second (default 12)
#   --loop        leave out the last frame: for a scene whose clock 1 looks as clock 0 does,
#                 the GIF or video then loops without showing that picture twice
#   OUT           a .gif, or a video file for ffmpeg
#   e.g. tools/animate.sh --loop examples/bounce.wsd bounce.gif --width 320 --height 200
# The frames are rendered into a temporary directory, removed at the end; OUT is written under
# a temporary name and renamed, so it is never half-written. wsd is $WSD if set, else build/wsd
# when it exists, else `wsd` on the PATH.
set -euo pipefail
frames=0-36; fps=12; loop=0
while (($#)); do
  case $1 in
    --frames) frames=${2:?--frames needs A-B}; shift 2 ;;
    --fps) fps=${2:?--fps needs a number}; shift 2 ;;
    --loop) loop=1; shift ;;
    *) break ;;
  esac
done
if (($# < 2)); then
  echo "usage: $0 [--frames A-B] [--fps N] [--loop] SCENE OUT [wsd render options...]" >&2
  exit 2
fi
scene=$1; out=$2; shift 2
if [[ ! $frames =~ ^([0-9]+)-([0-9]+)$ ]] || ((BASH_REMATCH[1] > BASH_REMATCH[2])); then
  echo "$0: --frames: expected A-B with A <= B, got '$frames'" >&2
  exit 2
fi
first=$((10#${BASH_REMATCH[1]})); last=$((10#${BASH_REMATCH[2]}))
if [[ ! $fps =~ ^[0-9]+$ ]] || ((fps < 1 || fps > 100)); then
  echo "$0: --fps: expected a whole number from 1 to 100, got '$fps'" >&2
  exit 2
fi
wsd=${WSD:-}
if [[ -z $wsd ]]; then
  wsd=wsd
  [[ -x "$(dirname "$0")/../build/wsd" ]] && wsd="$(dirname "$0")/../build/wsd"
fi

work=$(mktemp -d "${TMPDIR:-/tmp}/wsd-animate-XXXXXX")
trap 'rm -rf "$work"' EXIT
"$wsd" render "$scene" --frames "$first-$last" -o "$work/frame-######.png" "$@"
if ((loop && last > first)); then rm "$work/$(printf 'frame-%06d.png' "$last")"; fi

tmp="$(dirname "$out")/.$(basename "$out").tmp-$$"
trap 'rm -rf "$work" "$tmp"' EXIT
case $out in
  *.gif)
    command -v convert >/dev/null || { echo "$0: ImageMagick's convert is needed (apt-get install imagemagick)" >&2; exit 1; }
    # GIF delays are in hundredths of a second.
    convert -delay "$((100 / fps))" -loop 0 "$work"/frame-*.png -layers Optimize "gif:$tmp" ;;
  *)
    command -v ffmpeg >/dev/null || { echo "$0: ffmpeg is needed for '$out' (apt-get install ffmpeg)" >&2; exit 1; }
    ext=${out##*.}
    ffmpeg -loglevel error -y -framerate "$fps" -start_number "$first" -i "$work/frame-%06d.png" \
      -pix_fmt yuv420p -f "$( [[ $ext == mkv ]] && echo matroska || echo "$ext")" "$tmp" ;;
esac
mv "$tmp" "$out"
echo "animate: wrote $out" >&2
