"""Sorts and expression types (catc.frontend.typecheck), with expectations from docs/language.md.

The sort relations are checked on hand-built sorts (a symbol hierarchy
``camera < sensor < symbol``, an enumeration, sets); the expression checker on small models,
reading the sorts it gives the IR and the located errors it reports.
"""

from __future__ import annotations

from fractions import Fraction

import pytest

from catc import ir
from catc.frontend.session import load_texts
from catc.frontend.typecheck import assignable, compatible, const_number, describe, is_subsort, numeric_join, root_of
from catgrammar import codes
from catgrammar.diagnostics import Diagnostics

SYM = ir.SortKind.SYMBOL
SENSOR = ir.Sort(SYM, "sensor")
CAMERA = ir.Sort(SYM, "camera", parent="sensor")
TOPIC = ir.Sort(SYM, "topic")
MODE = ir.Sort(ir.SortKind.ENUM, "mode", values=("idle", "busy"))
SORTS = {"sensor": SENSOR, "camera": CAMERA, "topic": TOPIC, "mode": MODE}


def test_subsorts_follow_declared_parents():
    assert is_subsort(CAMERA, SENSOR, SORTS)
    assert is_subsort(CAMERA, CAMERA, SORTS)
    assert not is_subsort(SENSOR, CAMERA, SORTS)  # upwards only
    assert not is_subsort(TOPIC, SENSOR, SORTS)
    assert root_of(CAMERA, SORTS) == "sensor"


@pytest.mark.parametrize(
    "target, value, ok",
    [
        (ir.REAL, ir.INT, True),  # an integer is a real
        (ir.INT, ir.REAL, False),  # not the other way
        (ir.BOOL, ir.INT, False),
        (SENSOR, CAMERA, True),  # a camera is stored where a sensor is expected
        (CAMERA, SENSOR, False),
        (MODE, MODE, True),
        (ir.set_of(SENSOR), ir.set_of(CAMERA), True),  # element-wise
        (ir.set_of(CAMERA), ir.set_of(SENSOR), False),
    ],
)
def test_assignable(target, value, ok):
    assert assignable(target, value, SORTS) is ok


@pytest.mark.parametrize(
    "a, b, ok",
    [
        (ir.INT, ir.REAL, True),  # numbers compare across int and real
        (ir.BOOL, ir.INT, False),
        (CAMERA, SENSOR, True),  # one root
        (CAMERA, TOPIC, False),  # two roots
        (MODE, SENSOR, False),  # an enumeration compares with itself only
    ],
)
def test_compatible_for_equality(a, b, ok):
    assert compatible(a, b, SORTS) is ok
    assert compatible(b, a, SORTS) is ok  # symmetric


def test_numbers_take_the_narrowest_numeric_sort():
    assert const_number(Fraction(3)).sort == ir.INT
    assert const_number(Fraction(1, 2)).sort == ir.REAL
    ints = [ir.Const(Fraction(1), ir.INT), ir.Const(Fraction(2), ir.INT)]
    assert numeric_join(ints) == ir.INT
    assert numeric_join([*ints, ir.Const(Fraction(1, 2), ir.REAL)]) == ir.REAL
    assert describe(ir.set_of(CAMERA)) != describe(CAMERA)


MODEL = """(define (domain d) (:requirements :numeric)
  (:resources (n int) (x real) (ok bool))
  (:morphism m :precondition PRE :effect EFF))
(define (problem p) (:domain d) (:init (= n 0) (= x 0)) (:goal ok))
"""


def check(pre: str, eff: str = "(assign ok true)") -> tuple[ir.Instance | None, Diagnostics]:
    diags = Diagnostics()
    inst = load_texts({"m.cat": MODEL.replace("PRE", pre).replace("EFF", eff)}, "m.cat", diags)
    return inst, diags


def test_checked_expressions_carry_their_sorts():
    inst, diags = check("(and (>= (+ n 1) 2) (< (* x 2) 3) ok)", "(increase x (/ n 2))")
    assert inst is not None, [d.message for d in diags]
    pre = inst.morphisms["m"].pre
    assert [lit.label for lit in pre] == ["pre/m/1", "pre/m/2", "pre/m/3"]  # the top conjunction, split
    first, second, third = (lit.expr for lit in pre)
    assert isinstance(first, ir.Compare) and first.op is ir.CmpOp.GE
    assert isinstance(first.left, ir.Arith) and first.left.sort == ir.INT  # int + int
    assert isinstance(second, ir.Compare) and isinstance(second.left, ir.Arith)
    assert second.left.sort == ir.REAL  # real · int
    assert isinstance(third, ir.ResourceRef) and (third.name, third.sort) == ("ok", ir.BOOL)
    (eff,) = inst.morphisms["m"].effects
    assert eff.kind is ir.EffectKind.INCREASE and eff.value.sort == ir.REAL  # int / int is real


@pytest.mark.parametrize(
    "pre, eff, code",
    [
        ("(+ n 1)", "(assign ok true)", codes.TYPE_MISMATCH),  # a number is no condition
        ("(>= ok 1)", "(assign ok true)", codes.TYPE_MISMATCH),  # a Boolean is no number
        ("ok", "(assign n 1.5)", codes.TYPE_MISMATCH),  # a real into an int
        ("(>= nn 1)", "(assign ok true)", codes.UNKNOWN_NAME),
        ("(frob n)", "(assign ok true)", codes.UNKNOWN_OPERATOR),
        ("(not ok ok)", "(assign ok true)", codes.ARITY),
    ],
)
def test_ill_typed_expressions_are_located_errors(pre, eff, code):
    inst, diags = check(pre, eff)
    assert inst is None
    found = [d for d in diags if d.code == code]
    assert found, [(d.code, d.message) for d in diags]
    span = found[0].span
    assert span is not None and span.file == "m.cat" and span.line == 3  # on the morphism's line
