"""The Emacs mode (editors/emacs): ERT tests and a warning-free byte-compilation."""

from __future__ import annotations

import re

import pytest

from ._tools import EDITORS, explain, run, tool, write_keywords_json

EMACS_DIR = EDITORS / "emacs"
SOURCES = ("cat-mode.el", "cat-mode-tests.el")


def _ert(env: dict[str, str]):
    emacs = tool("emacs")
    command = [emacs, "--batch", "-Q", "-L", str(EMACS_DIR), "-l", str(EMACS_DIR / "cat-mode-tests.el")]
    return run([*command, "-f", "ert-run-tests-batch-and-exit"], env=env, timeout=120)


@pytest.mark.editors
def test_ert_suite_passes_with_every_keyword(tmp_path):
    result = _ert({"CAT_KEYWORDS_JSON": str(write_keywords_json(tmp_path))})
    output = result.stdout + result.stderr
    assert result.returncode == 0, explain(result)
    match = re.search(r"Ran (\d+) tests?, (\d+) results? as expected, 0 unexpected", output)
    assert match and match.group(1) == match.group(2) and int(match.group(1)) >= 8, explain(result)
    assert "skipped" not in output, explain(result)  # the keyword sweep ran


@pytest.mark.editors
def test_ert_keyword_sweep_can_fail(tmp_path):
    path = tmp_path / "keywords.json"
    path.write_text('{"operator": ["nand"], "no-such-category": ["x"]}')
    result = _ert({"CAT_KEYWORDS_JSON": str(path)})
    output = result.stdout + result.stderr
    assert result.returncode != 0, explain(result)
    assert "cat-mode-test-every-keyword" in output and "no face known for keyword category" in output


@pytest.mark.editors
@pytest.mark.parametrize("source", SOURCES)
def test_byte_compiles_without_warnings(source, tmp_path):
    emacs = tool("emacs")
    elc = tmp_path / (source + "c")
    program = (
        "(progn (setq byte-compile-error-on-warn t)"
        f" (setq byte-compile-dest-file-function (lambda (_) {_elisp_string(str(elc))}))"
        f" (unless (byte-compile-file {_elisp_string(str(EMACS_DIR / source))}) (kill-emacs 1)))"
    )
    result = run([emacs, "--batch", "-Q", "-L", str(EMACS_DIR), "--eval", program], timeout=120)
    assert result.returncode == 0, explain(result)
    assert elc.is_file()
    assert not list(EMACS_DIR.glob("*.elc"))


def _elisp_string(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def test_ert_sample_is_the_vim_sample():
    """Both editors are tested on the same text (which passes `catc check`)."""
    source = (EMACS_DIR / "cat-mode-tests.el").read_text(encoding="utf-8")
    literal = re.search(r'\(defconst cat-mode-test-sample\n  "((?:[^"\\]|\\.)*)"', source)
    assert literal, "no cat-mode-test-sample string"
    text = re.sub(r"\\(.)", r"\1", literal.group(1), flags=re.S)
    assert text == (EDITORS / "vim" / "test" / "sample.cat").read_text(encoding="utf-8")


@pytest.mark.editors
@pytest.mark.parametrize("flush", ["0", "1"], ids=["as-is", "flushed-left"])
def test_emacs_indents_every_repository_file_as_catc_fmt(flush):
    """`indent-region' changes no line of any .cat file of the repository (all in catc fmt's
    layout) and restores every file from its lines flushed left."""
    from conftest import repo_cat_files

    files = [str(p) for p in repo_cat_files()]
    env = {"CAT_EMACS_DIR": str(EDITORS / "emacs"), "CAT_FILES": "\n".join(files), "CAT_FLUSH": flush}
    script = EDITORS.parent / "tests" / "editors" / "scripts" / "reindent.el"
    result = run([tool("emacs"), "--batch", "-Q", "-l", str(script)], env=env, timeout=600)
    assert result.returncode == 0, explain(result)
    assert len(files) > 50 and result.stdout.strip().endswith("0 differ"), result.stdout


@pytest.mark.editors
def test_eglot_gets_diagnostics_and_hover(tmp_path):
    """Emacs's eglot (Debian's elpa-eglot on Emacs 28; built into Emacs 29) with cat-mode and
    `catc lsp`, configured as docs/editors.md says."""
    import shutil
    import sys

    from ._tools import ROOT

    folder = tmp_path / "detection"
    shutil.copytree(ROOT / "tests" / "fixtures" / "lsp" / "detection", folder)
    domain = folder / "domain.cat"
    text = domain.read_text().replace("(>= ram ram-req))", "(>= rma ram-req))", 1)
    domain.write_text(text)
    lines = text.split("\n")
    line = next(i for i, t in enumerate(lines) if "(>= rma ram-req)" in t)
    env = {"CAT_EMACS_DIR": str(EDITORS / "emacs"), "CAT_PYTHON": sys.executable, "CAT_FILE": str(domain),
           "CAT_HOVER_LINE": str(line + 1), "CAT_HOVER_COL": str(lines[line].index("ram-req"))}  # fmt: skip
    script = ROOT / "tests" / "editors" / "scripts" / "eglot_lsp.el"
    result = run([tool("emacs"), "--batch", "-q", "-l", str(script)], env=env, timeout=300, cwd=folder)
    assert result.returncode == 0, explain(result)
    diags = [t for t in result.stdout.splitlines() if t.startswith("DIAG ")]
    assert f"DIAG {line + 1} {lines[line].index('rma')} catc [E0202]: unknown name 'rma'; did you mean 'ram'?" in diags
    hover = next(t for t in result.stdout.splitlines() if t.startswith("HOVER "))
    assert "ram-req" in hover and "GB" in hover, hover
