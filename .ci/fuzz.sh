#!/usr/bin/env bash
# CI: fuzzes the language front end (fuzz/fuzz_lang.cpp) with libFuzzer under ASan+UBSan for a
# bounded time, seeded with every scene of tests/golden and examples. Fails on any crash, sanitizer
# report, timeout or out-of-memory; the input that caused it is kept in build-fuzz/artifacts/.
# Installs clang, libclang-rt-14-dev and the libraries when missing (apt-get as root, else through sudo).
# Environment: WSD_FUZZ_SECONDS (default 60), WSD_FUZZ_BUILD_DIR (default build-fuzz).
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${WSD_FUZZ_SECONDS:-60}"
build="${WSD_FUZZ_BUILD_DIR:-build-fuzz}"

packages=(cmake make clang libclang-rt-14-dev libglm-dev libcli11-dev libstb-dev nlohmann-json3-dev libopenexr-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "fuzz: installing ${missing[*]}" >&2
  sudo=""; [[ $(id -u) -ne 0 ]] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# -O1 -g without NDEBUG: readable stacks, and every assertion checked.
CC=clang CXX=clang++ cmake -S . -B "$build" -DWSD_FUZZ=ON -DWSD_TESTS=OFF \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" >/dev/null
cmake --build "$build" -j"$(nproc)" --target wsd_fuzz_lang

corpus=$(mktemp -d "${TMPDIR:-/tmp}/wsd-fuzz-corpus-XXXXXX")
trap 'rm -rf "$corpus"' EXIT
n=0
while IFS= read -r -d '' f; do
  cp "$f" "$corpus/seed-$n-$(basename "$f")"
  n=$((n + 1))
done < <(find tests/golden examples -type f \( -name '*.wsd' -o -name '*.wsdi' \) -print0)
if ((n == 0)); then
  echo "fuzz: no seed scenes found under tests/golden and examples" >&2
  exit 1
fi
mkdir -p "$build/artifacts"
echo "fuzz: $n seeds, ${seconds} s"

export ASAN_OPTIONS="abort_on_error=1:detect_leaks=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
# libFuzzer exits non-zero on a crash, a leak, a timeout (one input over 10 s) or more than
# 2 GB of memory, after writing the input to artifacts/; set -e then fails the job.
"$build/wsd_fuzz_lang" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
  -artifact_prefix="$build/artifacts/" -print_final_stats=1 "$corpus"
echo "fuzz: no crash in ${seconds} s"
