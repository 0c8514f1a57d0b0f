// VS Code client for the catc language server (`catc lsp`, JSON-RPC over stdio).
// Plain JavaScript on purpose: the extension ships as is, with no build step.
'use strict';

const vscode = require('vscode');
const { LanguageClient, State } = require('vscode-languageclient/node');

/** @type {LanguageClient | undefined} */
let client;
/** @type {vscode.OutputChannel | undefined} */
let output;

/** The command line that starts the server, from the `catc.*` settings. */
function serverOptions() {
  const config = vscode.workspace.getConfiguration('catc');
  const command = (config.get('serverPath') || 'catc').trim() || 'catc';
  const args = config.get('serverArgs');
  const executable = {
    command,
    args: Array.isArray(args) ? args.map(String) : ['lsp'],
    options: { env: process.env },
  };
  // Same process for run and debug; stdio is the default transport of an Executable.
  return { run: executable, debug: executable };
}

async function startClient() {
  const options = serverOptions();
  client = new LanguageClient(
    'catc',
    'catc language server',
    options,
    {
      documentSelector: [
        { scheme: 'file', language: 'cat' },
        { scheme: 'untitled', language: 'cat' },
      ],
      outputChannel: output,
      synchronize: {
        // Domains import other domains: tell the server when any .cat file changes.
        fileEvents: vscode.workspace.createFileSystemWatcher('**/*.cat'),
      },
    },
  );
  try {
    await client.start();
  } catch (err) {
    const failed = client;
    client = undefined;
    if (failed && failed.state !== State.Stopped) {
      await failed.stop().catch(() => undefined);
    }
    const message =
      `Could not start the catc language server with "${options.run.command} ` +
      `${options.run.args.join(' ')}": ${err && err.message ? err.message : err}. ` +
      'Install catc or set "catc.serverPath".';
    const choice = await vscode.window.showErrorMessage(message, 'Open Settings');
    if (choice === 'Open Settings') {
      await vscode.commands.executeCommand('workbench.action.openSettings', 'catc.serverPath');
    }
  }
}

async function stopClient() {
  const running = client;
  client = undefined;
  if (running) {
    await running.stop();
  }
}

async function restartClient() {
  await stopClient();
  await startClient();
}

/** @param {vscode.ExtensionContext} context */
async function activate(context) {
  output = vscode.window.createOutputChannel('catc');
  context.subscriptions.push(output);
  context.subscriptions.push(vscode.commands.registerCommand('catc.restartServer', restartClient));
  context.subscriptions.push(
    vscode.workspace.onDidChangeConfiguration((event) => {
      if (event.affectsConfiguration('catc.serverPath') || event.affectsConfiguration('catc.serverArgs')) {
        restartClient();
      }
    }),
  );
  await startClient();
}

function deactivate() {
  return stopClient();
}

module.exports = { activate, deactivate };
