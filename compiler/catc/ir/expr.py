"""Expressions of the IR: the :data:`Expr` union, and the generic walks over it.

A function over expressions matches the union and ends in ``case _: assert_never(e)``
(:func:`children` here, :func:`catc.ir.text.to_text`, :func:`catc.ir.fold.fold`), so mypy
names every function a new node must be added to.
"""

from __future__ import annotations

from collections.abc import Iterator
from enum import Enum
from fractions import Fraction
from typing import assert_never

from catc.ir.sorts import BOOL, INT, REAL, Sort
from catgrammar.record import Record
from catgrammar.record import set_field as _set
from catgrammar.span import Span

# ---------------------------------------------------------------- expressions


class Const(Record):
    """A literal: Fraction for numbers, bool, or the name of a symbolic constant."""

    __slots__ = ("value", "sort", "span")
    value: Fraction | bool | str
    sort: Sort
    span: Span | None

    def __init__(self, value: Fraction | bool | str, sort: Sort, span: Span | None = None) -> None:
        _set(self, "value", value)
        _set(self, "sort", sort)
        _set(self, "span", span)


class ResourceRef(Record):
    __slots__ = ("name", "sort", "span")
    name: str
    sort: Sort
    span: Span | None

    def __init__(self, name: str, sort: Sort, span: Span | None = None) -> None:
        _set(self, "name", name)
        _set(self, "sort", sort)
        _set(self, "span", span)


class ParamRef(Record):
    """A morphism's free parameter θ (inside that morphism's conditions and effects)."""

    __slots__ = ("name", "sort", "span")
    name: str
    sort: Sort
    span: Span | None

    def __init__(self, name: str, sort: Sort, span: Span | None = None) -> None:
        _set(self, "name", name)
        _set(self, "sort", sort)
        _set(self, "span", span)


class SetLit(Record):
    __slots__ = ("elements", "sort", "span")
    elements: tuple[Expr, ...]
    sort: Sort
    span: Span | None

    def __init__(self, elements: tuple[Expr, ...], sort: Sort, span: Span | None = None) -> None:
        _set(self, "elements", elements)
        _set(self, "sort", sort)
        _set(self, "span", span)


class ArithOp(str, Enum):
    ADD = "+"
    SUB = "-"
    MUL = "*"
    DIV = "/"
    MIN = "min"
    MAX = "max"


class Arith(Record):
    """n-ary arithmetic; ``(- x)`` is negation."""

    __slots__ = ("op", "args", "sort", "span")
    op: ArithOp
    args: tuple[Expr, ...]
    sort: Sort
    span: Span | None

    def __init__(self, op: ArithOp, args: tuple[Expr, ...], sort: Sort, span: Span | None = None) -> None:
        _set(self, "op", op)
        _set(self, "args", args)
        _set(self, "sort", sort)
        _set(self, "span", span)


class CmpOp(str, Enum):
    EQ = "="
    LT = "<"
    LE = "<="
    GT = ">"
    GE = ">="


class Compare(Record):
    __slots__ = ("op", "left", "right", "span", "sort")
    op: CmpOp
    left: Expr
    right: Expr
    span: Span | None
    sort: Sort

    def __init__(
        self,
        op: CmpOp,
        left: Expr,
        right: Expr,
        span: Span | None = None,
        sort: Sort = BOOL,
    ) -> None:
        _set(self, "op", op)
        _set(self, "left", left)
        _set(self, "right", right)
        _set(self, "span", span)
        _set(self, "sort", sort)


class BoolOpKind(str, Enum):
    AND = "and"
    OR = "or"
    NOT = "not"
    IMPLY = "imply"


class BoolOp(Record):
    __slots__ = ("op", "args", "span", "sort")
    op: BoolOpKind
    args: tuple[Expr, ...]
    span: Span | None
    sort: Sort

    def __init__(
        self,
        op: BoolOpKind,
        args: tuple[Expr, ...],
        span: Span | None = None,
        sort: Sort = BOOL,
    ) -> None:
        _set(self, "op", op)
        _set(self, "args", args)
        _set(self, "span", span)
        _set(self, "sort", sort)


class Ite(Record):
    __slots__ = ("cond", "then", "orelse", "sort", "span")
    cond: Expr
    then: Expr
    orelse: Expr
    sort: Sort
    span: Span | None

    def __init__(
        self,
        cond: Expr,
        then: Expr,
        orelse: Expr,
        sort: Sort,
        span: Span | None = None,
    ) -> None:
        _set(self, "cond", cond)
        _set(self, "then", then)
        _set(self, "orelse", orelse)
        _set(self, "sort", sort)
        _set(self, "span", span)


class Member(Record):
    __slots__ = ("element", "set", "span", "sort")
    element: Expr
    set: Expr
    span: Span | None
    sort: Sort

    def __init__(self, element: Expr, set: Expr, span: Span | None = None, sort: Sort = BOOL) -> None:
        _set(self, "element", element)
        _set(self, "set", set)
        _set(self, "span", span)
        _set(self, "sort", sort)


# objective-only terms ------------------------------------------------------


class TotalChurn(Record):
    """Weighted symmetric difference against the deployed composition (paper eq. churn)."""

    __slots__ = ("span", "sort")
    span: Span | None
    sort: Sort

    def __init__(self, span: Span | None = None, sort: Sort = REAL) -> None:
        _set(self, "span", span)
        _set(self, "sort", sort)


class TotalCost(Record):
    """Sum of the costs of every activation."""

    __slots__ = ("span", "sort")
    span: Span | None
    sort: Sort

    def __init__(self, span: Span | None = None, sort: Sort = REAL) -> None:
        _set(self, "span", span)
        _set(self, "sort", sort)


class Uses(Record):
    """How many times a morphism is activated."""

    __slots__ = ("morphism", "span", "sort")
    morphism: str
    span: Span | None
    sort: Sort

    def __init__(self, morphism: str, span: Span | None = None, sort: Sort = INT) -> None:
        _set(self, "morphism", morphism)
        _set(self, "span", span)
        _set(self, "sort", sort)


class ParamValue(Record):
    """The value of a morphism's θ (fixed, or used at most once)."""

    __slots__ = ("morphism", "param", "sort", "span")
    morphism: str
    param: str
    sort: Sort
    span: Span | None

    def __init__(self, morphism: str, param: str, sort: Sort, span: Span | None = None) -> None:
        _set(self, "morphism", morphism)
        _set(self, "param", param)
        _set(self, "sort", sort)
        _set(self, "span", span)


Expr = (
    Const
    | ResourceRef
    | ParamRef
    | SetLit
    | Arith
    | Compare
    | BoolOp
    | Ite
    | Member
    | TotalChurn
    | TotalCost
    | Uses
    | ParamValue
)


def children(expr: Expr) -> tuple[Expr, ...]:
    """Immediate sub-expressions (for generic walks)."""
    match expr:
        case Arith() | BoolOp():
            return expr.args
        case SetLit():
            return expr.elements
        case Compare():
            return (expr.left, expr.right)
        case Member():
            return (expr.element, expr.set)
        case Ite():
            return (expr.cond, expr.then, expr.orelse)
        case Const() | ResourceRef() | ParamRef() | TotalChurn() | TotalCost() | Uses() | ParamValue():
            return ()
        case _:
            assert_never(expr)


def walk(expr: Expr) -> Iterator[Expr]:
    """Every sub-expression, pre-order, without recursion."""
    stack = [expr]
    while stack:
        e = stack.pop()
        yield e
        stack.extend(reversed(children(e)))


def resources_in(expr: Expr) -> frozenset[str]:
    return frozenset(e.name for e in walk(expr) if isinstance(e, ResourceRef))


def params_in(expr: Expr) -> frozenset[str]:
    return frozenset(e.name for e in walk(expr) if isinstance(e, ParamRef))
