#!/usr/bin/env bash
# CTest: the VS Code extension in editors/vscode. Installs its npm packages (`npm ci`, only when
# package-lock.json changed since the last install into node_modules/), runs the grammar scope
# tests (vscode-tmgrammar-test on editors/vscode/test/*.wsd, *.wsdi), the language client's test
# and the grammar over every example and golden file that `wsd check` accepts (no invalid scope,
# no region left open), and packages the extension with vsce into OUT_DIR/wsd.vsix, which must
# hold the manifest, the grammar, the client and its runtime dependency. Exits 77 (CTest's
# SKIP_RETURN_CODE) when Node.js 20 or later with npm is not installed, except in CI (CI=true),
# where that is a failure.
# Usage: vscode.sh WSD SOURCE_DIR OUT_DIR
set -euo pipefail
wsd=$(realpath "$1")
src=$(realpath "$2")
out=$(realpath -m "$3")
ext="$src/editors/vscode"

missing=""
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  missing="Node.js and npm are not installed"
elif (($(node -p 'process.versions.node.split(".")[0]') < 20)); then
  missing="Node.js $(node --version) is too old (@vscode/vsce 3 needs Node.js 20 or later)"
fi
if [[ -n "$missing" ]]; then
  if [[ "${CI:-}" == true ]]; then
    echo "vscode.sh: $missing: the extension cannot be tested" >&2
    exit 1
  fi
  echo "SKIPPED: $missing"
  exit 77
fi

cd "$ext"
# One install at a time (two build directories may test at once); package.json is the lock.
exec 9<package.json
flock 9
stamp=node_modules/.wsd-lock-sha256
want=$(sha256sum package-lock.json | cut -d' ' -f1)
if [[ ! -f $stamp || $(cat "$stamp") != "$want" ]]; then
  echo "vscode.sh: npm ci"
  npm ci --no-audit --no-fund --loglevel=error
  echo "$want" >"$stamp"
fi
npx --no-install vscode-tmgrammar-test -g syntaxes/wsd.tmLanguage.json "test/*.wsd" "test/*.wsdi"
node test/client.test.js
valid=()
while IFS= read -r -d '' file; do
  "$wsd" check "$src/$file" >/dev/null 2>&1 && valid+=("$file")
done < <(cd "$src" && find examples tests/golden \( -name '*.wsd' -o -name '*.wsdi' \) -print0 | sort -z)
if ((${#valid[@]} < 10)); then
  echo "vscode.sh: only ${#valid[@]} example and golden files pass '$wsd check'" >&2
  exit 1
fi
node test/examples.test.js "${valid[@]}"
mkdir -p "$out"
rm -f "$out/wsd.vsix"
npx --no-install vsce package --no-update-package-json --allow-missing-repository -o "$out/wsd.vsix" \
  >"$out/vsce.log" 2>&1 || { cat "$out/vsce.log" >&2; exit 1; }
flock -u 9

# The package holds what VS Code loads.
node - "$out/wsd.vsix" <<'NODE'
const fs = require('fs');
const data = fs.readFileSync(process.argv[2]);
// The names in the zip's central directory (signature 0x02014b50).
const names = [];
for (let i = 0; i + 46 <= data.length; i++) {
  if (data.readUInt32LE(i) !== 0x02014b50) continue;
  const length = data.readUInt16LE(i + 28);
  names.push(data.toString('utf8', i + 46, i + 46 + length));
}
const needed = [
  'extension.vsixmanifest',
  'extension/package.json',
  'extension/extension.js',
  'extension/server.js',
  'extension/language-configuration.json',
  'extension/syntaxes/wsd.tmLanguage.json',
  'extension/node_modules/vscode-languageclient/package.json',
];
const absent = needed.filter((n) => !names.includes(n));
const stray = names.filter((n) => n.startsWith('extension/test/') || n.includes('/vscode-tmgrammar-test/'));
if (absent.length || stray.length) {
  console.error('vscode.sh: wsd.vsix lacks ' + JSON.stringify(absent) + ', has ' + JSON.stringify(stray));
  process.exit(1);
}
console.log(`vscode: grammar and client tests pass; wsd.vsix packaged (${names.length} files)`);
NODE
