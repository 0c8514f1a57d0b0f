#!/usr/bin/env bash
# Install what the editor-support tests (pytest -m editors, tests/editors/) need:
#   vim with +syntax, emacs, node >= 20 with npm, and the npm packages of editors/vscode
#   (vscode-tmgrammar-test, @vscode/vsce, vscode-languageclient) from its package-lock.json.
#
# Idempotent: tools already present are left alone, apt-get runs only when something is
# missing, and `npm ci` runs only when editors/vscode/node_modules does not match the
# lock file.  Needs only the Debian and npm registries.  Usage: .ci/install-editors.sh
set -euo pipefail

cd "$(dirname "$0")/.."
VSCODE_DIR=editors/vscode

log() { printf 'install-editors: %s\n' "$*"; }

SUDO=()
if [ "$(id -u)" != 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO=(sudo); fi
fi

packages=()
if ! command -v vim >/dev/null 2>&1 || ! vim --version 2>/dev/null | grep -q '+syntax'; then
  packages+=(vim-nox)
fi
if ! command -v emacs >/dev/null 2>&1; then
  packages+=(emacs-nox)
fi
if ! command -v nvim >/dev/null 2>&1; then
  packages+=(neovim)
fi
if [ ! -d /usr/share/emacs/site-lisp/elpa-src ] || ! ls /usr/share/emacs/site-lisp/elpa-src | grep -q '^eglot'; then
  packages+=(elpa-eglot)
fi
if ! command -v node >/dev/null 2>&1; then
  packages+=(nodejs)
fi
if ! command -v npm >/dev/null 2>&1; then
  packages+=(npm)
fi

if [ "${#packages[@]}" -gt 0 ]; then
  log "apt-get install ${packages[*]}"
  export DEBIAN_FRONTEND=noninteractive
  "${SUDO[@]}" apt-get update -qq
  "${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${packages[@]}" >/dev/null
else
  log "vim, neovim, emacs (with eglot), node and npm are already installed"
fi

node_major=$(node -p 'process.versions.node.split(".")[0]')
if [ "$node_major" -lt 20 ]; then
  log "warning: node $(node --version) is older than 20, which @vscode/vsce 3.9.2 needs"
fi

# node_modules matches the lock file when `npm ls` is happy and the tools are there.
if [ -x "$VSCODE_DIR/node_modules/.bin/vsce" ] \
  && [ -x "$VSCODE_DIR/node_modules/.bin/vscode-tmgrammar-test" ] \
  && [ "$VSCODE_DIR/node_modules/.package-lock.json" -nt "$VSCODE_DIR/package-lock.json" ] \
  && (cd "$VSCODE_DIR" && npm ls --all >/dev/null 2>&1); then
  log "$VSCODE_DIR/node_modules is up to date"
else
  log "npm ci in $VSCODE_DIR"
  # No package needs its install scripts (vsce only packages, it never signs here).
  (cd "$VSCODE_DIR" && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error)
fi

log "vim: $(vim --version | head -n1)"
log "emacs: $(emacs --version | head -n1)"
log "node: $(node --version), npm: $(npm --version)"
