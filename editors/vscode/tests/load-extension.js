// Smoke test of a packaged extension: `node load-extension.js <dir>` where <dir> is the
// `extension/` folder of an unpacked .vsix.  Loads extension.js with a stand-in for the
// `vscode` module (which only exists inside VS Code), so every other require -- above all
// vscode-languageclient/node -- must be satisfied by what the .vsix itself ships.
'use strict';

const Module = require('module');
const path = require('path');

const dir = process.argv[2];
if (!dir) {
  console.error('usage: node load-extension.js <unpacked extension dir>');
  process.exit(2);
}

// Every member of the stand-in is an empty class: enough for module-level code such as
// `class X extends vscode.CompletionItem`; nothing is called before activate().
const members = new Map();
const vscodeStub = new Proxy(
  {},
  {
    get(_target, name) {
      if (name === '__esModule' || typeof name === 'symbol') {
        return undefined;
      }
      if (!members.has(name)) {
        members.set(name, class {});
      }
      return members.get(name);
    },
  },
);
const load = Module._load;
Module._load = function (request, parent, isMain) {
  if (request === 'vscode') {
    return vscodeStub;
  }
  return load.call(this, request, parent, isMain);
};

const manifest = require(path.join(dir, 'package.json'));
const extension = require(path.resolve(dir, manifest.main));
for (const name of ['activate', 'deactivate']) {
  if (typeof extension[name] !== 'function') {
    console.error(`${manifest.main} does not export a function '${name}'`);
    process.exit(1);
  }
}
// The bundle carries vscode-languageclient: nothing outside the package may be required.
const outside = Object.keys(require.cache).filter((f) => !f.startsWith(path.resolve(dir) + path.sep));
const ours = outside.filter((f) => !f.endsWith('load-extension.js'));
if (ours.length) {
  console.error(`the extension required files outside the package: ${ours.join(', ')}`);
  process.exit(1);
}
console.log(`loaded ${manifest.publisher}.${manifest.name}@${manifest.version}: ${manifest.main}`);
