"""Terms the queries add on top of an encoding: bounds on objectives, skeletons, blocking
clauses.

A :data:`Term` is SMT-LIB text (what the encoder writes, a :class:`~catc.smt.script.Symbol`
included), an exact number (:class:`~fractions.Fraction`, a Real), a Boolean, an
:class:`App` of an SMT-LIB operator to terms, or a term a backend has :class:`Interned`.  Backends translate an ``App`` with their own
API (Z3 builds ``z3.And``, ``<``, ... directly; text backends print it), so numbers cross
into the solver as exact rationals and no query writes solver calls or SMT-LIB syntax.
"""

from __future__ import annotations

from fractions import Fraction
from typing import TypeAlias

from catc.smt.script import real_literal
from catgrammar.record import Record, set_field


class App(Record):
    """``(op arg ...)`` for an SMT-LIB core or arithmetic operator."""

    __slots__ = ("op", "args")
    op: str
    args: tuple[Term, ...]

    def __init__(self, op: str, args: tuple[Term, ...]) -> None:
        if op not in OPERATORS:
            raise ValueError(f"not a term operator: {op!r}")
        set_field(self, "op", op)
        set_field(self, "args", args)


class Interned(Record):
    """A term a backend has prepared for repeated use (:meth:`Backend.intern
    <catc.smt.backend.Backend.intern>`): ``native`` is that backend's own form of ``term``."""

    __slots__ = ("term", "native", "owner")
    term: Term
    native: object
    owner: object

    def __init__(self, term: Term, native: object, owner: object) -> None:
        set_field(self, "term", term)
        set_field(self, "native", native)
        set_field(self, "owner", owner)


Term: TypeAlias = "str | Fraction | bool | App | Interned"

#: The operators an :class:`App` may apply; every backend translates each of them.
OPERATORS = frozenset({"and", "or", "not", "=>", "=", "<", "<=", ">", ">=", "+", "-", "*", "ite", "to_real"})


def and_(*args: Term) -> App:
    return App("and", args)


def or_(*args: Term) -> App:
    return App("or", args)


def not_(arg: Term) -> App:
    return App("not", (arg,))


def implies(a: Term, b: Term) -> App:
    return App("=>", (a, b))


def ite(cond: Term, then: Term, orelse: Term) -> App:
    return App("ite", (cond, then, orelse))


def plus(*args: Term) -> App:
    return App("+", args)


def minus(*args: Term) -> App:
    return App("-", args)


def times(*args: Term) -> App:
    return App("*", args)


def to_real(arg: Term) -> App:
    """An Int term as a Real."""
    return App("to_real", (arg,))


def eq(a: Term, b: Term) -> App:
    return App("=", (a, b))


def lt(a: Term, b: Term) -> App:
    return App("<", (a, b))


def le(a: Term, b: Term) -> App:
    return App("<=", (a, b))


def gt(a: Term, b: Term) -> App:
    return App(">", (a, b))


def ge(a: Term, b: Term) -> App:
    return App(">=", (a, b))


def better(term: Term, value: Fraction, minimize: bool, strict: bool = True) -> App:
    """``term`` is (strictly) better than ``value`` for an objective of that sense."""
    if minimize:
        return lt(term, value) if strict else le(term, value)
    return gt(term, value) if strict else ge(term, value)


def to_text(term: Term) -> str:
    """The term as SMT-LIB2 text."""
    if isinstance(term, bool):
        return "true" if term else "false"
    if isinstance(term, str):
        return term
    if isinstance(term, Fraction):
        return real_literal(term)
    if isinstance(term, Interned):
        return to_text(term.term)
    return f"({term.op} {' '.join(to_text(a) for a in term.args)})"
