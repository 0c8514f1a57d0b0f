"""Neovim's built-in LSP client (Debian's neovim, headless) against ``catc lsp``, set up by
``editors/neovim/catc.lua`` exactly as docs/editors.md tells a user to: diagnostics of the
file, hover and definition, and diagnostics that follow an unsaved edit."""

from __future__ import annotations

import json
import shutil
import sys

import pytest

from ._tools import EDITORS, ROOT, explain, run, tool

SCRIPT = ROOT / "tests" / "editors" / "scripts" / "neovim_lsp.lua"
FIXTURE = ROOT / "tests" / "fixtures" / "lsp" / "detection"


@pytest.mark.editors
def test_neovim_gets_diagnostics_hover_and_definition(tmp_path):
    nvim = tool("nvim")
    folder = tmp_path / "detection"
    shutil.copytree(FIXTURE, folder)
    domain = folder / "domain.cat"
    text = domain.read_text()
    broken = text.replace(
        "(>= ram ram-req))\n    :effect (and (add topics out)",
        "(>= rma ram-req))\n    :effect (and (add topics out)",
        1,
    )
    assert broken != text
    domain.write_text(broken)
    lines = broken.split("\n")
    hover_line = next(i for i, line in enumerate(lines) if "(>= rma ram-req)" in line)
    hover_col = lines[hover_line].index("ram-req")
    out = tmp_path / "out.json"
    env = {"CAT_NEOVIM_RTP": str(EDITORS / "neovim"), "CAT_VIM_RTP": str(EDITORS / "vim"), "CAT_FILE": str(domain),
           "CAT_OUT": str(out), "CAT_PYTHON": sys.executable, "CAT_HOVER_LINE": str(hover_line),
           "CAT_HOVER_COL": str(hover_col), "XDG_CONFIG_HOME": str(tmp_path / "config"),
           "XDG_DATA_HOME": str(tmp_path / "data"), "XDG_STATE_HOME": str(tmp_path / "state")}  # fmt: skip
    result = run([nvim, "--headless", "--clean", "-c", f"luafile {SCRIPT}"], env=env, timeout=300, cwd=folder)
    assert result.returncode == 0 and out.exists(), explain(result)
    doc = json.loads(out.read_text())
    assert doc["filetype"] == "cat" and doc["attached"] and doc["client"] == "catc", doc
    (diag,) = [d for d in doc["diagnostics"] if "rma" in d["message"]]
    assert diag["lnum"] == hover_line and diag["col"] == lines[hover_line].index("rma"), diag
    assert "did you mean 'ram'" in diag["message"] and diag["code"].startswith("E02"), diag
    assert "ram-req" in doc["hover"] and "GB" in doc["hover"], doc["hover"]
    assert doc["definition"]["uri"].endswith("domain.cat") and doc["definition"]["line"] < hover_line, doc
    assert any(d["lnum"] == 0 for d in doc["after_edit"]), doc["after_edit"]  # the edit is checked unsaved
