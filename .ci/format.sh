#!/usr/bin/env bash
# CI: every tracked C++ file is formatted as .clang-format says (clang-format --dry-run --Werror
# reports each difference as an error). Fix with: git ls-files '*.cpp' '*.h' | xargs clang-format -i
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v clang-format >/dev/null; then
  echo "format: clang-format not found: install the Debian package clang-format" >&2
  exit 1
fi
mapfile -t files < <(git ls-files '*.cpp' '*.h')
clang-format --dry-run --Werror "${files[@]}"
echo "format: ${#files[@]} files formatted as .clang-format says"
