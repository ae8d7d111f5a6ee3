// The grammar on valid scenes: the files named as arguments (relative to the repository), or else
// every example scene and fragment (examples/*.wsd, examples/include/*.wsdi). Valid scenes get no `invalid` scope, and each file ends at the top
// level (no comment, string, parenthesis or vector left open, as a `<` misread as a vector would
// leave one). Run: node test/examples.test.js [FILE...]
'use strict';

const fs = require('fs');
const path = require('path');
const vsctm = require('vscode-textmate');
const oniguruma = require('vscode-oniguruma');

const root = path.join(__dirname, '..', '..', '..');
const grammarPath = path.join(__dirname, '..', 'syntaxes', 'wsd.tmLanguage.json');

async function main() {
  const wasm = fs.readFileSync(require.resolve('vscode-oniguruma/release/onig.wasm')).buffer;
  await oniguruma.loadWASM(wasm);
  const registry = new vsctm.Registry({
    onigLib: Promise.resolve({
      createOnigScanner: (patterns) => new oniguruma.OnigScanner(patterns),
      createOnigString: (s) => new oniguruma.OnigString(s),
    }),
    loadGrammar: async (scopeName) =>
      scopeName === 'source.wsd' ? vsctm.parseRawGrammar(fs.readFileSync(grammarPath, 'utf8'), grammarPath) : null,
  });
  const grammar = await registry.loadGrammar('source.wsd');

  const files = process.argv.slice(2);
  if (files.length === 0) {
    for (const [dir, ext] of [['examples', '.wsd'], [path.join('examples', 'include'), '.wsdi']])
      for (const name of fs.readdirSync(path.join(root, dir)).sort())
        if (name.endsWith(ext)) files.push(path.join(dir, name));
  }
  if (files.length < 5) throw new Error(`only ${files.length} files to read under ${root}`);

  const problems = [];
  let lines = 0;
  for (const file of files) {
    let stack = vsctm.INITIAL;
    const text = fs.readFileSync(path.join(root, file), 'utf8').split(/\r\n|\r|\n/);
    text.forEach((line, i) => {
      const result = grammar.tokenizeLine(line, stack);
      for (const token of result.tokens) {
        const bad = token.scopes.find((s) => s.startsWith('invalid'));
        if (bad) problems.push(`${file}:${i + 1}:${token.startIndex + 1}: ${bad} on "${line.slice(token.startIndex, token.endIndex)}"`);
      }
      stack = result.ruleStack;
      lines++;
    });
    // At the end of the file no region may be open: the stack is the initial one again.
    const probe = grammar.tokenizeLine('x', stack).tokens[0].scopes;
    if (probe.length !== 2 || probe[1] !== 'variable.other.wsd')
      problems.push(`${file}: ends inside ${probe.slice(1, -1).join(' ')}`);
  }
  if (problems.length) {
    console.error(problems.join('\n'));
    process.exit(1);
  }
  console.log(`valid scenes: ${files.length} files, ${lines} lines, no invalid scope, no region left open`);
}

main().catch((err) => {
  console.error(err);
  process.exit(1);
});
