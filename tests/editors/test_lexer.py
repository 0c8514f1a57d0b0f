"""The Pygments lexer (catgrammar/lexer.py).

The golden token file ``tests/editors/golden/sample.tokens`` holds the token stream of
``tests/editors/samples/warehouse.cat``.  After an intended change of the lexer,
regenerate it and review the diff::

    CATC_UPDATE_GOLDEN=1 python3 -m pytest tests/editors/test_lexer.py -k golden
"""

from __future__ import annotations

import os
import subprocess
import sys
from importlib import metadata

import pytest
from pygments.lexers import get_lexer_by_name, get_lexer_for_filename
from pygments.token import Comment, Error, Keyword, Name, Number, Operator, Punctuation, String, Whitespace
from pygments.util import ClassNotFound

from catgrammar.lexer import CatLexer

from ._tools import ROOT

SAMPLES = ROOT / "tests" / "editors" / "samples"
GOLDEN = ROOT / "tests" / "editors" / "golden" / "sample.tokens"
GOLDEN_INPUT = SAMPLES / "warehouse.cat"


def repository_cat_files(*, invalid: bool) -> list[str]:
    """Tracked .cat files (``git ls-files``), valid ones or those under ``/invalid/``,
    plus this folder's samples (valid) even before they are committed."""
    try:
        listed = (
            subprocess.run(["git", "ls-files", "-z", "*.cat"], cwd=ROOT, capture_output=True, check=True)
            .stdout.decode()
            .split("\0")
        )
    except (OSError, subprocess.CalledProcessError):  # not a git checkout: walk the tree
        listed = [str(p.relative_to(ROOT)) for p in ROOT.rglob("*.cat") if "node_modules" not in p.parts]
    files = {f for f in listed if f and ("/invalid/" in f"/{f}") == invalid}
    if not invalid:
        files |= {str(p.relative_to(ROOT)) for p in SAMPLES.glob("*.cat")}
    return sorted(files)


def tokens(text: str) -> list[tuple]:
    return list(CatLexer().get_tokens(text))


def significant(text: str) -> list[tuple]:
    return [(t, v) for t, v in tokens(text) if t not in Whitespace]


def token_of(text: str, word: str) -> object:
    """The token type of the first token whose text is ``word``."""
    for t, v in tokens(text):
        if v == word:
            return t
    raise AssertionError(f"no token {word!r} in {text!r}: {significant(text)}")


@pytest.mark.parametrize("path", repository_cat_files(invalid=False))
def test_valid_file_has_no_error_token(path):
    text = (ROOT / path).read_text(encoding="utf-8")
    toks = tokens(text)
    errors = [(i, v) for i, (t, v) in enumerate(toks) if t in Error]
    assert not errors, f"{path}: Error tokens {errors[:10]}"
    # Lossless: the tokens spell the file (Pygments adds a final newline if missing).
    assert "".join(v for _, v in toks) == (text if text.endswith("\n") else text + "\n")


@pytest.mark.parametrize("path", repository_cat_files(invalid=True))
def test_invalid_file_is_lexed_losslessly(path):
    text = (ROOT / path).read_text(encoding="utf-8")
    assert "".join(v for _, v in tokens(text)) == (text if text.endswith("\n") else text + "\n")


def test_the_corpus_is_not_empty():
    assert len(repository_cat_files(invalid=False)) >= 2


def format_tokens(text: str) -> str:
    return "".join(f"{t!s}\t{v!r}\n" for t, v in tokens(text))


def test_golden_tokens():
    got = (
        f"# Pygments tokens of {GOLDEN_INPUT.relative_to(ROOT)} (catgrammar.lexer.CatLexer).\n"
        "# Regenerate: CATC_UPDATE_GOLDEN=1 python3 -m pytest tests/editors/test_lexer.py -k golden\n"
        + format_tokens(GOLDEN_INPUT.read_text(encoding="utf-8"))
    )
    if os.environ.get("CATC_UPDATE_GOLDEN") == "1":
        GOLDEN.parent.mkdir(parents=True, exist_ok=True)
        GOLDEN.write_text(got, encoding="utf-8")
        pytest.skip(f"regenerated {GOLDEN.relative_to(ROOT)}")
    assert GOLDEN.exists(), f"{GOLDEN.relative_to(ROOT)} is missing: run with CATC_UPDATE_GOLDEN=1"
    expected = GOLDEN.read_text(encoding="utf-8")
    if got != expected:
        import difflib

        diff = "".join(difflib.unified_diff(expected.splitlines(True), got.splitlines(True), "golden", "lexer", n=1))
        pytest.fail(f"token stream differs from the golden file (CATC_UPDATE_GOLDEN=1 updates it):\n{diff[:4000]}")


def test_view_is_a_section_after_a_paren_and_an_option_elsewhere():
    assert token_of("(:view software :drop (x))", ":view") is Keyword.Declaration
    assert token_of("( :view software)", ":view") is Keyword.Declaration
    assert token_of("(:hole mu :view software)", ":view") is Name.Attribute


def test_hyphenated_names_hold_no_keyword_or_operator():
    text = "(:constants and-gate not-ready total-churn-x x-or camera2 realistic - class)"
    names = [v for t, v in significant(text) if t is Name]
    assert names == ["and-gate", "not-ready", "total-churn-x", "x-or", "camera2", "realistic", "class"]
    assert token_of(text, "-") is Operator


def test_unknown_colon_word_is_a_plain_name():
    assert significant("(x :kind-of :viewer)")[2:4] == [(Name, ":kind-of"), (Name, ":viewer")]


def test_numbers():
    text = "(+ 3 -2 0.5 .5 4. 1e-3 -1.5E+2 (- x 1))"
    assert [(t, v) for t, v in significant(text) if t in Number] == [
        (Number.Integer, "3"),
        (Number.Integer, "-2"),
        (Number.Float, "0.5"),
        (Number.Float, ".5"),
        (Number.Float, "4."),
        (Number.Float, "1e-3"),
        (Number.Float, "-1.5E+2"),
        (Number.Integer, "1"),
    ]
    assert token_of(text, "-") is Operator


def test_strings_and_comments():
    text = '(:doc "a \\"quoted\\" ; word") ; a comment (define'
    toks = significant(text)
    assert (String.Escape, '\\"') in toks
    assert (String.Double, " ; word") in toks
    assert toks[-1] == (Comment.Single, "; a comment (define")


def test_unterminated_string_ends_at_the_line_end():
    toks = significant('(:doc "open\n(and x))')
    assert (String.Double, "open") in toks
    assert (Keyword, "and") in toks
    assert not [v for t, v in toks if t in Error]


def test_punctuation():
    assert [v for t, v in significant("(= s {a b})") if t is Punctuation] == ["(", "{", "}", ")"]


def test_analyse_text_recognises_cat_files():
    assert CatLexer.analyse_text("; x\n(define (domain d)\n  (:requirements))") > 0.5
    assert CatLexer.analyse_text("(defun f (x) x)") == 0.0


def test_lexer_metadata():
    assert CatLexer.name == "Cat"
    assert CatLexer.aliases == ["cat", "catc"]
    assert CatLexer.filenames == ["*.cat"]
    assert CatLexer.mimetypes == ["text/x-cat"]


def _entry_point_installed() -> bool:
    return any(
        ep.value.replace(" ", "") == "catgrammar.lexer:CatLexer"
        for ep in metadata.entry_points(group="pygments.lexers")
    )


def test_registered_as_pygments_plugin():
    if not _entry_point_installed():
        pytest.skip(
            'the "pygments.lexers" entry point cat = "catgrammar.lexer:CatLexer" is not installed '
            "(add it to pyproject.toml and reinstall the package: pip install -e .)"
        )
    assert isinstance(get_lexer_by_name("cat"), CatLexer)
    assert isinstance(get_lexer_by_name("catc"), CatLexer)
    assert isinstance(get_lexer_for_filename("robot.cat"), CatLexer)
    result = subprocess.run(
        [sys.executable, "-m", "pygments", "-l", "cat", "-f", "raw", str(GOLDEN_INPUT)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    assert "Token.Keyword.Declaration\t':morphism'" in result.stdout


def test_without_plugin_lookup_fails_cleanly_or_finds_cat():
    # Either the plugin is installed (and found) or Pygments reports no such lexer: a
    # broken entry point (wrong module path) would raise something else.
    try:
        lexer = get_lexer_by_name("cat")
    except ClassNotFound:
        assert not _entry_point_installed()
    else:
        assert isinstance(lexer, CatLexer)
