"""One vocabulary: the grammar, the checker and the docs agree with catgrammar.symbols."""

from __future__ import annotations

import re
from importlib import resources

from conftest import ROOT, run_catc

from catgrammar import symbols
from catgrammar.diagnostics import CODES

GRAMMAR = resources.files("catgrammar").joinpath("cat.lark").read_text()


def grammar_terminals() -> set[str]:
    declared = set()
    for line in GRAMMAR.splitlines():
        if line.startswith("%declare"):
            declared |= set(line.split()[1:])
    return declared


def used_terminals() -> set[str]:
    rules = "\n".join(l for l in GRAMMAR.splitlines() if not l.lstrip().startswith(("//", "%")))
    return set(re.findall(r"\b_?[A-Z][A-Z_]*\b", rules))


def test_every_keyword_terminal_is_declared_and_used():
    from catgrammar.tokens import COLON_KEYWORDS, PUNCTUATION, WORDS

    produced = set(COLON_KEYWORDS.values()) | set(WORDS.values()) | set(PUNCTUATION.values())
    produced |= {"OPSYM", "NAME", "NUMBER", "STRING", "FLAG"}
    assert grammar_terminals() == produced
    assert used_terminals() == produced


def test_colon_keywords_are_exactly_sections_and_options():
    from catgrammar.tokens import COLON_KEYWORDS

    assert set(COLON_KEYWORDS) == {s.value for s in symbols.Section} | {o.value for o in symbols.Option}


def test_reserved_words_are_declared_symbols():
    from catgrammar.tokens import WORDS

    kw = symbols.all_keywords()
    declared = set(kw["structure"]) | set(kw["type"]) | set(kw["constant"]) | set(kw["metric"])
    assert set(WORDS) <= declared, set(WORDS) - declared
    assert set(WORDS) <= symbols.RESERVED_NAMES


def test_every_operator_is_known_to_the_checker():
    from catc.frontend import typecheck

    heads = {op.value for op in symbols.EXPRESSION_OPERATORS} | {op.value for op in symbols.OBJECTIVE_OPERATORS}
    assert heads == {op.value for op in symbols.Operator} - {"assign", "increase", "decrease", "add", "remove"}
    handled = (
        set(typecheck._ARITH)
        | set(typecheck._CMP)
        | set(typecheck._BOOL)
        | {"if", "member"}
        | typecheck._OBJECTIVE_HEADS
    )
    assert heads == handled


def test_requirement_implications_are_closed():
    everything = symbols.expand_requirements({symbols.Requirement.ALL})
    assert everything == frozenset(symbols.Requirement)
    assert symbols.Requirement.SYMBOLS in symbols.expand_requirements({symbols.Requirement.SETS})
    assert symbols.Requirement.NUMERIC in symbols.expand_requirements({symbols.Requirement.RECOMPOSITION})


def test_every_error_code_is_documented():
    doc = (ROOT / "docs" / "errors.md").read_text()
    for code, info in CODES.items():
        assert f"`{code}`" in doc, f"{code} missing from docs/errors.md"
        assert info.name in doc


def test_every_error_code_is_exercised_by_a_test():
    texts = "\n".join(
        p.read_text(errors="replace")
        for p in (ROOT / "tests").rglob("*")
        if p.is_file() and p.suffix in {".py", ".cat"}
    )
    for code in CODES:
        assert code in texts, f"no test mentions {code}"


def test_every_keyword_is_documented_in_the_language_reference():
    doc = (ROOT / "docs" / "language.md").read_text()
    for category, words in symbols.all_keywords().items():
        for w in words:
            assert f"`{w}" in doc or f"{w}`" in doc or f"({w}" in doc, (
                f"{category} keyword {w!r} not in docs/language.md"
            )


def test_version_flag():
    res = run_catc("--version")
    assert res.exit_code == 0 and "catc" in res.stdout
