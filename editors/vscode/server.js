// How the extension starts the language server: `<wsd.path> lsp` over stdio. Kept apart from
// extension.js (which needs VS Code) so that it can be tested with plain Node.
'use strict';

const DEFAULT_PATH = 'wsd';

// The executable named by the `wsd.path` setting: a name looked up on PATH or a path; an empty
// or non-string setting falls back to "wsd". A leading "~/" is the home directory.
function serverCommand(setting, home) {
  let command = typeof setting === 'string' ? setting.trim() : '';
  if (command === '') command = DEFAULT_PATH;
  if (home && (command === '~' || command.startsWith('~/'))) command = home + command.slice(1);
  return { command, args: ['lsp'] };
}

module.exports = { serverCommand, DEFAULT_PATH };
