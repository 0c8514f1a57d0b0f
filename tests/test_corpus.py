"""The fixture corpus: every invalid file states its expected diagnostics inline.

A comment ``;! CODE ["substring"] [CODE ...]`` at the end of a line expects one diagnostic
with that code on that line (and, if given, a message containing the substring).  The
check is exact both ways: every expected diagnostic is reported and nothing else is.
"""

from __future__ import annotations

import re
from collections import Counter
from pathlib import Path

import pytest
from conftest import FIXTURES, repo_cat_files, run_catc

from catc.frontend.session import check_files
from catgrammar.diagnostics import Diagnostics

_EXPECT = re.compile(r";!\s*(.*)$")
_ITEM = re.compile(r'([EW]\d{4})(?:\s+"([^"]*)")?')


def expectations(path: Path) -> list[tuple[int, str, str | None]]:
    out = []
    for lineno, line in enumerate(path.read_text().splitlines(), 1):
        m = _EXPECT.search(line)
        if m:
            for code, text in _ITEM.findall(m.group(1)):
                out.append((lineno, code, text or None))
    return out


INVALID = sorted((FIXTURES / "invalid").glob("*.cat"))


@pytest.mark.parametrize("path", INVALID, ids=lambda p: p.name)
def test_invalid_fixture_reports_exactly_the_expected_diagnostics(path: Path):
    expected = expectations(path)
    assert expected, f"{path.name} states no expectations"
    diags = Diagnostics()
    check_files([str(path)], diags)
    got = [
        (d.span.line if d.span else 0, d.code, d.message) for d in diags if d.span is None or d.span.file == str(path)
    ]
    got_keys = Counter((line, code) for line, code, _ in got)
    want_keys = Counter((line, code) for line, code, _ in expected)
    missing = want_keys - got_keys
    extra = got_keys - want_keys
    assert not missing and not extra, f"\nmissing: {sorted(missing.elements())}\nunexpected: " + "\n".join(
        f"{l}: {c} {m}" for l, c, m in got if (l, c) in extra
    )
    for line, code, text in expected:
        if text is not None:
            messages = [m for l, c, m in got if l == line and c == code]
            assert any(text in m for m in messages), f"line {line} {code}: no message contains {text!r}: {messages}"


@pytest.mark.parametrize("path", repo_cat_files(), ids=lambda p: str(p.relative_to(FIXTURES.parent.parent)))
def test_every_repository_cat_file_checks_clean(path: Path):
    res = run_catc("check", "--strict", str(path))
    assert res.exit_code == 0, res.output


def test_valid_corpus_is_not_empty():
    # A guard for the parametrised test above: an empty corpus would pass vacuously.
    assert len(repo_cat_files()) >= 15
    assert len(INVALID) >= 8
