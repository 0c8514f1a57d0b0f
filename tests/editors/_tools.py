"""Helpers shared by the editor-support tests."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

from catgrammar.symbols import all_keywords

ROOT = Path(__file__).resolve().parents[2]
EDITORS = ROOT / "editors"
VSCODE = EDITORS / "vscode"
INSTALL_HINT = "run .ci/install-editors.sh (installs vim, emacs, node and the npm packages of editors/vscode)"

#: Where each keyword category is checked, ``%s`` standing for the word.  The same
#: contexts are used by editors/vim/test/test.vim and editors/emacs/cat-mode-tests.el.
CONTEXTS = {
    "structure": "(%s x)",
    "section": "(%s x)",
    "option": "(x %s y)",
    "requirement": "(:requirements %s)",
    "operator": "(%s x y)",
    "symbol-operator": "(%s x y)",
    "type": "(x %s)",
    "constant": "(= x %s)",
    "kind": "(x :kind %s)",
    "metric": "(:metric %s x)",
}


def glued(word: str) -> list[str]:
    """Names that contain ``word`` but are not it: never highlighted as the keyword."""
    if not word[0].isalpha() and not (word[0] == ":" and word[1:2].isalpha()):
        return []  # symbol operators cannot be glued into a name
    names = [f"{word}-zz"]
    if word[0] != ":":
        names.append(f"zz-{word}")
    return names


def tool(name: str, *, path: Path | None = None) -> str:
    """The executable ``name`` (on PATH, or at ``path``), or fail/skip the test."""
    found = str(path) if path is not None and path.exists() else (None if path is not None else shutil.which(name))
    if found:
        return found
    where = f"{path.relative_to(ROOT)}" if path is not None else f"'{name}' on PATH"
    message = f"{where} is missing: {INSTALL_HINT}"
    if os.environ.get("CATC_SKIP_EDITOR_TOOLS") == "1":
        pytest.skip(f"CATC_SKIP_EDITOR_TOOLS=1 and {message}")
    pytest.fail(message, pytrace=False)


def node_bin(name: str) -> str:
    """An executable installed by ``npm ci`` in editors/vscode (needs node too)."""
    tool("node")
    return tool(name, path=VSCODE / "node_modules" / ".bin" / name)


def run(cmd: list[str], *, cwd: Path = ROOT, env: dict[str, str] | None = None, timeout: float = 300):
    """Run ``cmd``; the result carries stdout and stderr as text."""
    return subprocess.run(
        cmd,
        cwd=cwd,
        env={**os.environ, **(env or {})},
        capture_output=True,
        text=True,
        timeout=timeout,
        stdin=subprocess.DEVNULL,
    )


def explain(result: subprocess.CompletedProcess) -> str:
    return f"exit {result.returncode}\n--- stdout\n{result.stdout[-6000:]}\n--- stderr\n{result.stderr[-6000:]}"


def write_keywords_json(directory: Path) -> Path:
    """``all_keywords()`` as JSON, for the Vim and Emacs keyword sweeps."""
    path = directory / "keywords.json"
    path.write_text(json.dumps({k: list(v) for k, v in all_keywords().items()}), encoding="utf-8")
    return path
