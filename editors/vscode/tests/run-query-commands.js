// Drives the query commands of extension.js outside VS Code:
//   node run-query-commands.js <extension.js> <file.cat> <answer.json>
// with stand-ins for the `vscode` module and for vscode-languageclient's LanguageClient
// (whose sendRequest answers <answer.json>).  Prints one JSON line: the commands the
// extension registered, the requests it sent and what it wrote to its output channels.
'use strict';

const Module = require('module');
const fs = require('fs');
const path = require('path');

const [extensionPath, catFile, answerFile] = process.argv.slice(2);
if (!answerFile) {
  console.error('usage: node run-query-commands.js <extension.js> <file.cat> <answer.json>');
  process.exit(2);
}
const answer = JSON.parse(fs.readFileSync(answerFile, 'utf8'));
const registered = new Map();
const requests = [];
const channels = {};
let saved = 0;

const uri = {
  scheme: 'file',
  fsPath: path.resolve(catFile),
  toString: () => 'file://' + path.resolve(catFile),
};
const document = {
  uri,
  languageId: 'cat',
  isUntitled: false,
  isDirty: true,
  save: async () => {
    saved += 1;
    document.isDirty = false;
    return true;
  },
};
const disposable = { dispose() {} };
const vscode = {
  window: {
    activeTextEditor: { document },
    createOutputChannel(name) {
      channels[name] = [];
      return { appendLine: (line) => channels[name].push(line), show() {}, dispose() {} };
    },
    showWarningMessage: async (m) => channels.warnings ? channels.warnings.push(m) : (channels.warnings = [m]),
    showErrorMessage: async (m) => (channels.errors = [...(channels.errors || []), m]),
  },
  commands: {
    registerCommand(name, fn) {
      registered.set(name, fn);
      return disposable;
    },
    executeCommand: async () => undefined,
  },
  workspace: {
    getConfiguration: () => ({ get: () => undefined }),
    createFileSystemWatcher: () => disposable,
    onDidChangeConfiguration: () => disposable,
    asRelativePath: (u) => path.relative(process.cwd(), u.fsPath),
  },
};

class LanguageClient {
  constructor(id, name, serverOptions) {
    this.serverOptions = serverOptions;
    this.state = 2;
  }
  async start() {}
  async stop() {}
  async sendRequest(method, params) {
    requests.push({ method, params });
    return answer;
  }
}

const load = Module._load;
Module._load = function (request, parent, isMain) {
  if (request === 'vscode') {
    return vscode;
  }
  if (request === 'vscode-languageclient/node') {
    return { LanguageClient, State: { Stopped: 1, Running: 2 } };
  }
  return load.call(this, request, parent, isMain);
};

(async () => {
  const extension = require(path.resolve(extensionPath));
  const context = { subscriptions: [] };
  await extension.activate(context);
  const results = {};
  for (const name of Object.keys(extension.QUERY_COMMANDS)) {
    results[name] = await registered.get(name)();
  }
  console.log(
    JSON.stringify({ registered: [...registered.keys()], requests, channels, saved, results }),
  );
})().catch((err) => {
  console.error(err && err.stack ? err.stack : err);
  process.exit(1);
});
