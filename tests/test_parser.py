"""Parsing: exact numbers, source spans, the shape of every construct."""

from __future__ import annotations

from fractions import Fraction

import pytest
from conftest import ROOT

from catgrammar import ast
from catgrammar.diagnostics import Diagnostics
from catgrammar.limits import DEFAULT
from catgrammar.parser import parse_text


def parse_ok(text: str) -> ast.SourceFile:
    diags = Diagnostics()
    sf = parse_text(text, "t.cat", diags)
    assert sf is not None and not diags.has_errors, [d.message for d in diags]
    return sf


def number(text: str) -> ast.Num:
    sf = parse_ok(f"(define (problem p) (:domain d) (:init (= x {text})))")
    (prob,) = sf.definitions
    init = next(s for s in prob.sections if isinstance(s, ast.Init))
    return init.literals[0].args[1]


@pytest.mark.parametrize(
    "text, value",
    [
        ("0.1", Fraction(1, 10)),
        ("22.73", Fraction(2273, 100)),
        ("-0.5", Fraction(-1, 2)),
        (".25", Fraction(1, 4)),
        ("3.", Fraction(3)),
        ("1e3", Fraction(1000)),
        ("2.5e-3", Fraction(1, 400)),
        ("72.875", Fraction(583, 8)),
        (
            "123456789012345678901234567890.000000000000000000001",
            Fraction(123456789012345678901234567890000000000000000000001, 10**21),
        ),
    ],
)
def test_numbers_are_exact_rationals(text, value):
    n = number(text)
    assert isinstance(n.value, Fraction) and n.value == value and n.text == text


def test_decimal_sum_is_exact():
    # 0.1 + 0.2 == 0.3 holds for the language's numbers (it does not for floats).
    assert number("0.1").value + number("0.2").value == number("0.3").value


def test_spans_point_at_the_source():
    text = "(define (domain d)\n  (:resources\n    (ram real :unit GB)))"
    sf = parse_ok(text)
    (dom,) = sf.definitions
    (res_sec,) = dom.sections
    (ram,) = res_sec.resources
    assert (ram.name.span.line, ram.name.span.column) == (3, 6)
    assert text[ram.name.span.start : ram.name.span.end] == "ram"
    assert text[ram.span.start : ram.span.end] == "(ram real :unit GB)"
    unit = ram.options[0]
    assert unit.key == ":unit" and unit.value.text == "GB"


def test_every_construct_parses():
    sf = parse_ok((ROOT / "tests" / "fixtures" / "valid" / "every-construct.cat").read_text())
    dom, prob = sf.definitions
    kinds = {type(s).__name__ for s in dom.sections}
    assert kinds == {
        "Requirements",
        "Imports",
        "Sorts",
        "Constants",
        "Resources",
        "MorphismDecl",
        "HoleDecl",
        "ViewDecl",
    }
    pkinds = {type(s).__name__ for s in prob.sections}
    assert pkinds == {
        "DomainRef",
        "Requirements",
        "Objects",
        "Init",
        "Goal",
        "Horizon",
        "Soft",
        "Metric",
        "Deployed",
        "ViewUse",
    }


def test_metric_modes():
    for mode, body in [
        ("single", "minimize (total-cost)"),
        ("lex", "lex (minimize (total-churn)) (maximize x)"),
        ("pareto", "pareto (maximize a) (minimize b)"),
    ]:
        sf = parse_ok(f"(define (problem p) (:domain d) (:metric {body}))")
        metric = next(s for s in sf.definitions[0].sections if isinstance(s, ast.Metric))
        assert metric.mode == mode


def test_unbounded_bound_is_none():
    sf = parse_ok("(define (domain d) (:resources (x real :bounds (0 *))))")
    b = sf.definitions[0].sections[0].resources[0].options[0].value
    assert b.lower.value == 0 and b.upper is None


def test_keywords_need_a_word_boundary():
    diags = Diagnostics()
    assert parse_text("(define (domain d) (:morphism m :uses1 :effect (assign b true)))", "t.cat", diags) is None
    assert [d.code for d in diags] == ["E0106"]


def test_depth_limit_is_exact():
    MAX_DEPTH = DEFAULT.nesting
    ok = (
        "(define (domain d) (:morphism m :precondition "
        + "(not " * (MAX_DEPTH - 4)
        + "b"
        + ")" * (MAX_DEPTH - 4)
        + "))"
    )
    parse_ok(ok)
    diags = Diagnostics()
    deep = "(define (domain d) (:morphism m :precondition " + "(not " * MAX_DEPTH + "b" + ")" * MAX_DEPTH + "))"
    assert parse_text(deep, "t.cat", diags) is None
    assert [d.code for d in diags] == ["E0104"]


def test_parentheses_inside_comments_and_strings_do_not_count():
    parse_ok('(define (domain d) ; an unbalanced ( in a comment\n (:resources (x bool :doc "a ) in a string")))')
