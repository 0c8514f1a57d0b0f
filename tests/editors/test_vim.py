"""The Vim support (editors/vim), driven headless through editors/vim/test/test.vim.

test.vim checks the filetype detection, the ftplugin options, the syntax group at sample
positions of editors/vim/test/sample.cat, indentation, and -- given CAT_KEYWORDS_JSON --
every word of ``catgrammar.symbols.all_keywords()``.
"""

from __future__ import annotations

import re

import pytest

from catgrammar.symbols import all_keywords

from ._tools import EDITORS, explain, glued, run, tool, write_keywords_json

TEST_VIM = EDITORS / "vim" / "test" / "test.vim"


def _run_test_vim(env: dict[str, str]):
    vim = tool("vim")
    version = run([vim, "--version"])
    if "+syntax" not in version.stdout:
        pytest.fail(f"{vim} is built without +syntax (vim-tiny?): install vim-nox", pytrace=False)
    return run([vim, "-Nu", "NONE", "-n", "-es", "-S", str(TEST_VIM)], env=env, timeout=120)


@pytest.mark.editors
def test_vim_syntax_ftplugin_indent_and_every_keyword(tmp_path):
    result = _run_test_vim({"CAT_KEYWORDS_JSON": str(write_keywords_json(tmp_path))})
    assert result.returncode == 0, explain(result)
    match = re.search(r"vim: all checks passed \((\d+) keyword checks\)", result.stdout)
    assert match, explain(result)
    expected = sum(1 + len(glued(w)) for words in all_keywords().values() for w in words)
    assert int(match.group(1)) == expected, explain(result)


@pytest.mark.editors
def test_vim_test_fails_on_a_wrong_expectation(tmp_path):
    """The sweep reports a keyword that is not highlighted (here: an unknown category)."""
    path = tmp_path / "keywords.json"
    path.write_text('{"section": [":morphism"], "no-such-category": ["x"], "operator": ["nand"]}')
    result = _run_test_vim({"CAT_KEYWORDS_JSON": str(path)})
    assert result.returncode != 0, explain(result)
    assert "no syntax group for keyword category 'no-such-category'" in result.stderr, explain(result)
    assert "operator 'nand' in '(nand x y)': expected 'catOperator', got ''" in result.stderr, explain(result)


def repo_cat_files_for_indent() -> list[str]:
    """Every valid .cat file of the repository (each is in catc fmt's layout: CI checks it)."""
    from conftest import repo_cat_files

    return [str(p) for p in repo_cat_files()]


def _reindent(files: list[str], out, syntax: str, flush: str):
    env = {"CAT_VIM_RTP": str(EDITORS / "vim"), "CAT_FILES": "\n".join(files), "CAT_OUT": str(out),
           "CAT_SYNTAX": syntax, "CAT_FLUSH": flush}  # fmt: skip
    script = EDITORS.parent / "tests/editors/scripts/reindent.vim"
    return run([tool("vim"), "-Nu", "NONE", "-n", "-es", "-S", str(script)], env=env, timeout=600)


@pytest.mark.editors
def test_reindent_is_not_stopped_by_another_vims_swap_file(tmp_path):
    """The four variants below run in parallel on the same files: a swap file another Vim
    left next to a file (E325 on `:edit') must not fail the sweep (it did in CI, exit 1)."""
    sample = tmp_path / "sample.cat"
    sample.write_text((EDITORS / "vim" / "test" / "sample.cat").read_text())
    (tmp_path / ".sample.cat.swp").write_bytes(b"")  # what E325 meets, as a live one does
    out = tmp_path / "out.txt"
    result = _reindent([str(sample)], out, "0", "1")
    assert result.returncode == 0, explain(result)
    assert out.read_text() == "", out.read_text()


@pytest.mark.editors
@pytest.mark.parametrize("syntax", ["0", "1"], ids=["syntax-off", "syntax-on"])
@pytest.mark.parametrize("flush", ["0", "1"], ids=["as-is", "flushed-left"])
def test_vim_indents_every_repository_file_as_catc_fmt(tmp_path, syntax, flush):
    """`gg=G` changes no line of any .cat file of the repository (all in catc fmt's layout),
    with syntax highlighting on or off (a bracket in a comment or a string never counts), and
    restores every file from its lines flushed left."""
    out = tmp_path / "out.txt"
    files = repo_cat_files_for_indent()
    result = _reindent(files, out, syntax, flush)
    assert result.returncode == 0, explain(result)
    assert len(files) > 50
    assert out.read_text() == "", out.read_text()
