// The language client's wiring, with VS Code and vscode-languageclient replaced by recording
// fakes (after checking that the real library has the names the extension uses): activation starts `<wsd.path> lsp` over stdio for the wsd language, a change of
// `wsd.path` restarts it with the new executable, the restart command works, a server that
// cannot start is reported (not thrown), and deactivation stops it. Run: node test/client.test.js
'use strict';

const assert = require('assert');
const Module = require('module');
const path = require('path');

const { serverCommand } = require('../server');

// serverCommand on its own.
assert.deepStrictEqual(serverCommand('wsd'), { command: 'wsd', args: ['lsp'] });
assert.deepStrictEqual(serverCommand('  /opt/wsd/bin/wsd '), { command: '/opt/wsd/bin/wsd', args: ['lsp'] });
assert.deepStrictEqual(serverCommand(''), { command: 'wsd', args: ['lsp'] });
assert.deepStrictEqual(serverCommand(undefined), { command: 'wsd', args: ['lsp'] });
assert.deepStrictEqual(serverCommand(42), { command: 'wsd', args: ['lsp'] });
assert.deepStrictEqual(serverCommand('~/bin/wsd', '/home/a'), { command: '/home/a/bin/wsd', args: ['lsp'] });

// The real client library (with a stand-in for VS Code that answers every name) has what
// extension.js takes from it.
const realLoad = Module._load;
const anything = { get: (target, key) => (key in target ? target[key] : new Proxy(function () {}, anything)) };
Module._load = function (request, parent, isMain) {
  if (request === 'vscode') return new Proxy(function () {}, anything);
  return realLoad.call(this, request, parent, isMain);
};
const real = require('vscode-languageclient/node');
assert.strictEqual(typeof real.LanguageClient, 'function');
assert.strictEqual(typeof real.TransportKind.stdio, 'number');

// Recording fakes.
const settings = { path: '/first/wsd' };
const events = [];
const errors = [];
let configListener;
const commands = {};
let failNextStart = false;

const fakeVscode = {
  workspace: {
    getConfiguration: (section) => ({ get: (key) => (section === 'wsd' ? settings[key] : undefined) }),
    onDidChangeConfiguration: (listener) => {
      configListener = listener;
      return { dispose() {} };
    },
    createFileSystemWatcher: (glob) => ({ glob, dispose() {} }),
  },
  window: {
    createOutputChannel: (name) => ({ name, dispose() {} }),
    showErrorMessage: (message) => errors.push(message),
  },
  commands: {
    registerCommand: (name, fn) => {
      commands[name] = fn;
      return { dispose() {} };
    },
  },
};

class FakeClient {
  constructor(id, name, serverOptions, clientOptions) {
    this.serverOptions = serverOptions;
    this.clientOptions = clientOptions;
    FakeClient.last = this;
    events.push({ event: 'new', id, command: serverOptions.command, args: serverOptions.args });
  }
  async start() {
    events.push({ event: 'start', command: this.serverOptions.command });
    if (failNextStart) {
      failNextStart = false;
      throw new Error('spawn ' + this.serverOptions.command + ' ENOENT');
    }
  }
  async stop() {
    events.push({ event: 'stop', command: this.serverOptions.command });
  }
}
const fakeClientModule = { LanguageClient: FakeClient, TransportKind: real.TransportKind };

Module._load = function (request, parent, isMain) {
  if (request === 'vscode') return fakeVscode;
  if (request === 'vscode-languageclient/node') return fakeClientModule;
  return realLoad.call(this, request, parent, isMain);
};
const extension = require(path.join(__dirname, '..', 'extension.js'));
const packageJson = require(path.join(__dirname, '..', 'package.json'));

async function main() {
  const context = { subscriptions: [] };
  await extension.activate(context);
  assert.deepStrictEqual(events, [
    { event: 'new', id: 'wsd', command: '/first/wsd', args: ['lsp'] },
    { event: 'start', command: '/first/wsd' },
  ]);
  assert.ok(context.subscriptions.length >= 3, 'output channel, command and listener are disposed with the extension');

  // The first client: stdio, the wsd language in files and unsaved buffers.
  const made = FakeClient.last;
  assert.strictEqual(made.serverOptions.transport, fakeClientModule.TransportKind.stdio);
  assert.deepStrictEqual(made.clientOptions.documentSelector, [
    { scheme: 'file', language: 'wsd' },
    { scheme: 'untitled', language: 'wsd' },
  ]);
  assert.strictEqual(made.clientOptions.synchronize.fileEvents.glob, '**/*.{wsd,wsdi}');
  const language = packageJson.contributes.languages.find((l) => l.id === 'wsd');
  assert.deepStrictEqual(language.extensions, ['.wsd', '.wsdi']);
  assert.ok(packageJson.activationEvents.includes('onLanguage:wsd'));
  assert.strictEqual(packageJson.contributes.configuration.properties['wsd.path'].default, 'wsd');
  // A workspace that is not trusted cannot choose the executable.
  assert.deepStrictEqual(packageJson.capabilities.untrustedWorkspaces.restrictedConfigurations, ['wsd.path']);
  const first = events.length;
  assert.ok(commands['wsd.restartServer'], 'the restart command is registered');
  const packaged = packageJson.contributes.commands.map((c) => c.command);
  assert.ok(packaged.includes('wsd.restartServer'), 'package.json declares the restart command');

  // A change to another setting leaves the server alone; a change of wsd.path restarts it.
  configListener({ affectsConfiguration: (key) => key === 'editor.tabSize' });
  await new Promise((r) => setImmediate(r));
  assert.strictEqual(events.length, first);
  settings.path = '/second/wsd';
  configListener({ affectsConfiguration: (key) => key === 'wsd.path' });
  await new Promise((r) => setImmediate(r));
  assert.deepStrictEqual(events.slice(first), [
    { event: 'stop', command: '/first/wsd' },
    { event: 'new', id: 'wsd', command: '/second/wsd', args: ['lsp'] },
    { event: 'start', command: '/second/wsd' },
  ]);

  // A server that cannot start is an error message, and the extension stays usable.
  settings.path = '/missing/wsd';
  failNextStart = true;
  await commands['wsd.restartServer']();
  assert.strictEqual(errors.length, 1);
  assert.match(errors[0], /\/missing\/wsd lsp/);
  assert.match(errors[0], /wsd\.path/);
  settings.path = '';
  const before = events.length;
  await commands['wsd.restartServer']();
  assert.deepStrictEqual(events.slice(before), [
    { event: 'new', id: 'wsd', command: 'wsd', args: ['lsp'] },
    { event: 'start', command: 'wsd' },
  ]);

  // Deactivation stops the running server.
  const end = events.length;
  await extension.deactivate();
  assert.deepStrictEqual(events.slice(end), [{ event: 'stop', command: 'wsd' }]);
  console.log('client: starts, restarts and stops `wsd lsp` as the settings say');
}

main().catch((err) => {
  console.error(err);
  process.exit(1);
});
