"""Fuzzing the front end: mutated valid files give diagnostics or success, never a crash.

Mutations start from every valid .cat file in the repository: deleting, inserting, replacing
and duplicating spans of text, with characters that matter to the grammar (parentheses,
braces, quotes, colons, digits, signs, non-ASCII letters).  Any exception escaping
``check_files`` fails the test; so does an error diagnostic without a location inside the
file, or an empty diagnostic message.
"""

from __future__ import annotations

import os

import pytest
from conftest import repo_cat_files
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from catc.frontend.session import check_files
from catgrammar.diagnostics import Diagnostics

CORPUS = [p.read_text() for p in repo_cat_files() if "editors" not in p.parts]
ALPHABET = '()(){}":;-+*/<=>.0123456789 \n\tabcxyz?!é∘⊗\x00\x7f'
TOKENS = [
    "(",
    ")",
    "(and",
    ":precondition",
    ":effect",
    "(define",
    "{",
    "}",
    "-",
    "1e99",
    "0.1",
    '"',
    "(member",
    ":uses",
    "(:morphism m",
    "(assign",
    "ram",
    "true",
    "(= x",
    ":bounds (1 0)",
    "symbol",
]


@st.composite
def mutated(draw):
    text = draw(st.sampled_from(CORPUS))
    for _ in range(draw(st.integers(1, 4))):
        n = len(text)
        i = draw(st.integers(0, n))
        j = draw(st.integers(i, min(n, i + 40)))
        op = draw(st.sampled_from(["delete", "insert", "replace", "duplicate", "token", "truncate"]))
        if op == "delete":
            text = text[:i] + text[j:]
        elif op == "insert":
            text = text[:i] + draw(st.text(ALPHABET, min_size=1, max_size=6)) + text[i:]
        elif op == "replace":
            text = text[:i] + draw(st.text(ALPHABET, max_size=6)) + text[j:]
        elif op == "duplicate":
            text = text[:j] + text[i:j] + text[j:]
        elif op == "token":
            text = text[:i] + " " + draw(st.sampled_from(TOKENS)) + " " + text[i:]
        else:
            text = text[:i]
    return text


def _check(tmp_path, text: str) -> Diagnostics:
    path = tmp_path / "fuzz.cat"
    path.write_bytes(text.encode("utf-8", "surrogatepass"))
    diags = Diagnostics()
    check_files([str(path)], diags)
    for d in diags:
        assert d.message.strip()
        if d.span is not None:
            assert d.span.line >= 1 and d.span.column >= 1
    return diags


@settings(
    max_examples=int(os.environ.get("CATC_FUZZ_EXAMPLES", "150")),
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(text=mutated())
def test_mutated_files_never_crash(tmp_path, text):
    _check(tmp_path, text)


@pytest.mark.slow
@settings(
    max_examples=3000, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow]
)
@given(text=mutated())
def test_mutated_files_never_crash_at_scale(tmp_path, text):
    _check(tmp_path, text)


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.binary(max_size=300))
def test_arbitrary_bytes_never_crash(tmp_path, data):
    path = tmp_path / "bytes.cat"
    path.write_bytes(data)
    diags = Diagnostics()
    check_files([str(path)], diags)
