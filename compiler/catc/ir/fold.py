"""Constant folding: the one place arithmetic on constants is defined.

:func:`fold` evaluates every subexpression whose operands are constants — after replacing
the parameters θ bound in ``theta`` — and leaves the rest as it was, so it serves the
checker (initial values, costs), the PDDL export (θ fixed per ground action) and anyone
else who needs an expression simplified.  :func:`arith` is the arithmetic of the language on
exact rationals: ``(- x)`` negates, ``(- a b c)`` is a − b − c, ``(/ a b)`` is exact division,
``min``/``max`` take any number of arguments.  Division by zero is a :class:`FoldError`,
never a Python exception escaping to the user.

Every value :func:`fold` computes is bounded: a numerator or denominator of more digits than
the constant-digits limit (:mod:`catgrammar.limits`), also in a partial result of an n-ary
operation, is a :class:`ConstantTooLarge` — so a checked model holds no constant that the
writers of SMT-LIB2 and PDDL, or Python's own integer conversions, cannot take.
"""

from __future__ import annotations

import operator
from collections.abc import Callable, Mapping
from fractions import Fraction
from typing import assert_never

from catc.ir.nodes import (
    BOOL,
    Arith,
    ArithOp,
    BoolOp,
    BoolOpKind,
    CmpOp,
    Compare,
    Const,
    Expr,
    Ite,
    Member,
    ParamRef,
    ParamValue,
    ResourceRef,
    SetLit,
    TotalChurn,
    TotalCost,
    Uses,
)
from catgrammar import limits


class FoldError(ValueError):
    """A constant expression that has no value (division by zero)."""

    def __init__(self, message: str, expr: Expr) -> None:
        super().__init__(message)
        self.expr = expr


class ConstantTooLarge(FoldError):
    """A constant whose numerator or denominator has more digits than the constant-digits limit."""

    def __init__(self, expr: Expr, digits: int) -> None:
        limit = limits.BY_NAME["constant-digits"]
        super().__init__(
            f"the value of this constant expression has more than {digits} digits in its numerator or denominator "
            f"(the constant-digits limit); {limit.how_to_raise}",
            expr,
        )


def _too_large(v: Fraction, digits: int) -> bool:
    return limits.digits_over(v.numerator, digits) or limits.digits_over(v.denominator, digits)


def bounded_arith(op: ArithOp, values: list[Fraction], expr: Expr) -> Fraction:
    """:func:`arith`, one operand at a time, raising :class:`ConstantTooLarge` as soon as a
    partial result is larger than the constant-digits limit allows (never computing a
    product of thousands of digits first); ``ZeroDivisionError`` for a zero divisor."""
    if op in (ArithOp.MIN, ArithOp.MAX):
        return arith(op, values)
    digits = limits.current().constant_digits
    out = -values[0] if op is ArithOp.SUB and len(values) == 1 else values[0]
    step = _STEP[op]
    for x in values[1:]:
        out = step(out, x)
        if _too_large(out, digits):
            raise ConstantTooLarge(expr, digits)
    if _too_large(out, digits):
        raise ConstantTooLarge(expr, digits)
    return out


_STEP: dict[ArithOp, Callable[[Fraction, Fraction], Fraction]] = {
    ArithOp.ADD: operator.add,
    ArithOp.SUB: operator.sub,
    ArithOp.MUL: operator.mul,
    ArithOp.DIV: operator.truediv,
}


def arith(op: ArithOp, values: list[Fraction]) -> Fraction:
    """The value of ``(op v1 v2 ...)``; ``ZeroDivisionError`` for a zero divisor."""
    if op is ArithOp.ADD:
        return sum(values, Fraction(0))
    if op is ArithOp.SUB:
        return -values[0] if len(values) == 1 else values[0] - sum(values[1:], Fraction(0))
    if op is ArithOp.MUL:
        out = Fraction(1)
        for x in values:
            out *= x
        return out
    if op is ArithOp.DIV:
        out = values[0]
        for x in values[1:]:
            out /= x
        return out
    return min(values) if op is ArithOp.MIN else max(values)


_ORDER = {
    CmpOp.LT: lambda a, b: a < b,
    CmpOp.LE: lambda a, b: a <= b,
    CmpOp.GT: lambda a, b: a > b,
    CmpOp.GE: lambda a, b: a >= b,
}


def fold(e: Expr, theta: Mapping[str, object] | None = None) -> Expr:
    """``e`` with the parameters in ``theta`` replaced by their values and every constant
    subexpression evaluated.  Raises :class:`FoldError` on division by zero, and
    :class:`ConstantTooLarge` for a value past the constant-digits limit."""
    theta = theta or {}
    match e:
        case ParamRef():
            # a value of theta is a parameter's value, or a placeholder a caller carries through
            # (the PDDL+ export's dial marker): not only Fraction, bool or str
            return Const(theta[e.name], e.sort, e.span) if e.name in theta else e  # type: ignore[arg-type]
        case Arith():
            return _fold_arith(e, theta)
        case Compare():
            left, right = fold(e.left, theta), fold(e.right, theta)
            if isinstance(left, Const) and isinstance(right, Const):
                a, b = left.value, right.value
                value = a == b if e.op is CmpOp.EQ else _ORDER[e.op](a, b)
                return Const(value, BOOL, e.span)
            return Compare(e.op, left, right, e.span)
        case BoolOp():
            return _fold_bool(e, theta)
        case Ite():
            cond = fold(e.cond, theta)
            if isinstance(cond, Const):
                return fold(e.then if cond.value else e.orelse, theta)
            return Ite(cond, fold(e.then, theta), fold(e.orelse, theta), e.sort, e.span)
        case Member():
            return Member(fold(e.element, theta), fold(e.set, theta), e.span)
        case SetLit():
            return SetLit(tuple(fold(a, theta) for a in e.elements), e.sort, e.span)
        case Const() | ResourceRef() | TotalChurn() | TotalCost() | Uses() | ParamValue():
            return e
        case _:
            assert_never(e)


def _fold_arith(e: Arith, theta: Mapping[str, object]) -> Expr:
    args = tuple(fold(a, theta) for a in e.args)
    if not all(isinstance(a, Const) for a in args):
        return Arith(e.op, args, e.sort, e.span)
    try:
        # every argument is a Const (checked above) of a numeric sort
        value = bounded_arith(e.op, [a.value for a in args], e)  # type: ignore[union-attr,misc]
    except ZeroDivisionError:
        raise FoldError("division by zero", e) from None
    return Const(Fraction(value), e.sort, e.span)


def _fold_bool(e: BoolOp, theta: Mapping[str, object]) -> Expr:
    args = tuple(fold(a, theta) for a in e.args)
    if e.op is BoolOpKind.NOT:
        if isinstance(args[0], Const):
            return Const(not args[0].value, BOOL, e.span)
    elif e.op in (BoolOpKind.AND, BoolOpKind.OR):
        absorbing = e.op is BoolOpKind.OR  # false absorbs an and, true an or
        if any(isinstance(a, Const) and a.value is absorbing for a in args):
            return Const(absorbing, BOOL, e.span)
        args = tuple(a for a in args if not isinstance(a, Const))
        if not args:
            return Const(not absorbing, BOOL, e.span)
    else:  # imply
        a, b = args
        if isinstance(a, Const):
            return b if a.value else Const(True, BOOL, e.span)
    return BoolOp(e.op, args, e.span)


def fold_constant(expr: Expr) -> Const | SetLit | None:
    """The value of an expression built from constants only (initial values, bounds,
    costs), or None when it depends on something else.  Raises :class:`FoldError`."""
    folded = fold(expr)
    if isinstance(folded, Const):
        return folded
    if isinstance(folded, SetLit) and all(isinstance(x, Const) for x in folded.elements):
        return folded
    return None
