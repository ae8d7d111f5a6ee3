// The wsd extension: a language client that starts `wsd lsp` (the executable in the `wsd.path`
// setting) for .wsd and .wsdi files, and restarts it when the setting changes. Highlighting is
// the TextMate grammar in syntaxes/; everything else (diagnostics as you type, hover,
// completion, go to definition, symbols, formatting) comes from the server.
'use strict';

const os = require('os');
const vscode = require('vscode');
const { LanguageClient, TransportKind } = require('vscode-languageclient/node');
const { serverCommand } = require('./server');

let client;
let output;

function makeClient() {
  const setting = vscode.workspace.getConfiguration('wsd').get('path');
  const { command, args } = serverCommand(setting, os.homedir());
  const serverOptions = { command, args, transport: TransportKind.stdio };
  const clientOptions = {
    documentSelector: [
      { scheme: 'file', language: 'wsd' },
      { scheme: 'untitled', language: 'wsd' },
    ],
    outputChannel: output,
    synchronize: {
      fileEvents: vscode.workspace.createFileSystemWatcher('**/*.{wsd,wsdi}'),
    },
  };
  return { client: new LanguageClient('wsd', 'wsd language server', serverOptions, clientOptions), command };
}

async function start() {
  const made = makeClient();
  client = made.client;
  try {
    await client.start();
  } catch (err) {
    const message = err && err.message ? err.message : String(err);
    vscode.window.showErrorMessage(
      `wsd: could not start "${made.command} lsp" (${message}). Set "wsd.path" to the wsd executable.`);
    client = undefined;
  }
}

async function stop() {
  if (!client) return;
  const running = client;
  client = undefined;
  try {
    await running.stop();
  } catch (_) {
    // A server that never started or already exited has nothing to stop.
  }
}

async function restart() {
  await stop();
  await start();
}

async function activate(context) {
  output = vscode.window.createOutputChannel('wsd');
  context.subscriptions.push(output);
  context.subscriptions.push(vscode.commands.registerCommand('wsd.restartServer', restart));
  context.subscriptions.push(
    vscode.workspace.onDidChangeConfiguration((event) => {
      if (event.affectsConfiguration('wsd.path')) restart();
    }));
  await start();
}

function deactivate() {
  return stop();
}

module.exports = { activate, deactivate };
