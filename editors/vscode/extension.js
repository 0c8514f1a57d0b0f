// VS Code client for the catc language server (`catc lsp`, JSON-RPC over stdio).
// Plain JavaScript on purpose: the extension ships as is, with no build step.
'use strict';

const vscode = require('vscode');
const { LanguageClient, State } = require('vscode-languageclient/node');

/** @type {LanguageClient | undefined} */
let client;
/** @type {vscode.OutputChannel | undefined} */
let output;
/** @type {vscode.OutputChannel | undefined} */
let answers;

/**
 * The editor commands that ask the server a query (`workspace/executeCommand catc.<query>`)
 * about the active .cat file and show the answer in the "catc answers" output channel.
 * Their ids differ from the server's `catc.solve`, ..., which vscode-languageclient
 * registers itself.
 */
const QUERY_COMMANDS = {
  'catc.runSolve': { query: 'catc.solve', title: 'Solve' },
  'catc.runDiagnose': { query: 'catc.diagnose', title: 'Diagnose' },
  'catc.runRelax': { query: 'catc.relax', title: 'Relax' },
};

/** A location of a catc.error/1 diagnostic as `file:line:col`. */
function where(location) {
  if (!location) {
    return '';
  }
  return `${location.file}:${location.line}:${location.column}: `;
}

/**
 * The text shown for an answer: a one-line summary (the status, or the errors of a
 * catc.error/1 document) and then the whole --json document.
 * @param {string} title @param {string} file @param {any} answer @returns {string}
 */
function formatAnswer(title, file, answer) {
  const lines = [`${title} ${file}`];
  if (answer && answer.schema === 'catc.error/1') {
    lines.push('error: the query could not run');
    for (const d of answer.diagnostics || []) {
      const code = d.code ? `[${d.code}] ` : '';
      lines.push(`  ${where(d.location)}${code}${d.message}`);
    }
  } else if (answer && typeof answer === 'object') {
    const bits = [`schema ${answer.schema}`];
    if (answer.status !== undefined) {
      bits.push(`status ${answer.status}`);
    }
    lines.push(bits.join(', '));
    lines.push(JSON.stringify(answer, null, 2));
  } else {
    lines.push(String(answer));
  }
  return lines.join('\n');
}

/** Run one query command on the active .cat file (saved first) and show its answer. */
async function runQuery(command) {
  const { query, title } = QUERY_COMMANDS[command];
  const editor = vscode.window.activeTextEditor;
  if (!editor || editor.document.languageId !== 'cat') {
    await vscode.window.showWarningMessage(`catc: ${title} needs an open .cat problem file.`);
    return undefined;
  }
  const document = editor.document;
  if (document.isUntitled || document.uri.scheme !== 'file') {
    await vscode.window.showWarningMessage(`catc: save the file before running ${title}.`);
    return undefined;
  }
  if (document.isDirty && !(await document.save())) {
    return undefined;
  }
  if (!client) {
    await vscode.window.showErrorMessage('catc: the language server is not running.');
    return undefined;
  }
  const file = vscode.workspace.asRelativePath(document.uri);
  answers.show(true);
  let text;
  try {
    const answer = await client.sendRequest('workspace/executeCommand', {
      command: query,
      arguments: [document.uri.toString()],
    });
    text = formatAnswer(title, file, answer);
  } catch (err) {
    text = `${title} ${file}\nerror: ${err && err.message ? err.message : err}`;
  }
  answers.appendLine(text);
  answers.appendLine('');
  return text;
}

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
  answers = vscode.window.createOutputChannel('catc answers');
  context.subscriptions.push(output, answers);
  context.subscriptions.push(vscode.commands.registerCommand('catc.restartServer', restartClient));
  for (const command of Object.keys(QUERY_COMMANDS)) {
    context.subscriptions.push(vscode.commands.registerCommand(command, () => runQuery(command)));
  }
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

module.exports = { activate, deactivate, formatAnswer, QUERY_COMMANDS };
