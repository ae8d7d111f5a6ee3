#!/usr/bin/env bash
# CTest: `wsd preview` in a real headless browser (tests/app/preview_browser.py). Runs it with the
# Python that has Selenium (Debian's python3-selenium lives in /usr/bin/python3, which another
# python3 earlier on PATH may not see). Without Selenium, chromium or chromedriver it exits 77
# (CTest's SKIP_RETURN_CODE), except under CI (CI=true), where they are required and it fails.
# Usage: preview_browser.sh WSD
set -uo pipefail
here=$(dirname "$0")
missing() {
  if [[ "${CI:-}" == "true" ]]; then
    echo "FAILED: $1 (CI requires it: WSD_EXTRA_PACKAGES in .ci/run installs chromium chromium-driver python3-selenium)"
    exit 1
  fi
  echo "SKIPPED: $1 (apt-get install chromium chromium-driver python3-selenium)"
  exit 77
}
python=""
for candidate in /usr/bin/python3 python3; do
  if "$candidate" -c 'import selenium' >/dev/null 2>&1; then
    python=$candidate
    break
  fi
done
[[ -n "$python" ]] || missing "python3-selenium is not installed"
command -v chromium >/dev/null 2>&1 || missing "chromium is not installed"
command -v chromedriver >/dev/null 2>&1 || missing "chromedriver (chromium-driver) is not installed"
exec "$python" "$here/preview_browser.py" "$1"
