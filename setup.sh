#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine and builds wsd: installs the missing Debian packages
# (apt-get as root, else through sudo), configures and builds into build/ (or $WSD_BUILD_DIR).
# Extra arguments are passed to CMake's configure step (e.g. -DWSD_SANITIZE=ON).
set -euo pipefail
cd "$(dirname "$0")"

packages=(cmake g++ make python3 libglm-dev libcli11-dev libstb-dev nlohmann-json3-dev catch2 libopenexr-dev
          openexr libcpp-httplib-dev pkgconf)
[[ -n "${WSD_EXTRA_PACKAGES:-}" ]] && read -r -a extra <<<"$WSD_EXTRA_PACKAGES" && packages+=("${extra[@]}")
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}" >&2
  sudo=""; [[ $(id -u) -ne 0 ]] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

build="${WSD_BUILD_DIR:-build}"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE="${WSD_BUILD_TYPE:-Release}" "$@" >/dev/null
cmake --build "$build" -j"$(nproc)"
