#!/usr/bin/env bash
# Sets up, builds and runs every test suite (Catch2 unit, golden, analytic render and example
# tests through CTest). `./test.sh --sanitize` does the same in an ASan+UBSan build at -O1
# (build-asan/).
# WSD_WERROR=ON (as CI sets it) makes every compiler warning an error.
set -euo pipefail
cd "$(dirname "$0")"
if [[ "${1:-}" == "--sanitize" ]]; then
  export WSD_BUILD_DIR=build-asan WSD_BUILD_TYPE=RelWithDebInfo
  ./setup.sh -DWSD_SANITIZE=ON -DWSD_WERROR="${WSD_WERROR:-OFF}"
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  export WSD_SANITIZED=1
else
  ./setup.sh -DWSD_WERROR="${WSD_WERROR:-OFF}"
fi
cd "${WSD_BUILD_DIR:-build}"
ctest --output-on-failure -j"$(nproc)"
