"""The abstract syntax tree of .cat files.

A faithful, typed record of what the user wrote, each node carrying its source
:class:`~catgrammar.span.Span`.  Nothing here is resolved or checked; the checker in
``catc.check`` turns it into the categorical IR.  Expressions keep one generic shape,
:class:`Call` (``(head args...)``), so the checker can say precisely what is wrong with an
unknown or misplaced operator.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Union

from catgrammar.span import Span


@dataclass(frozen=True, slots=True)
class Name:
    text: str
    span: Span


# ---------------------------------------------------------------- expressions


@dataclass(frozen=True, slots=True)
class Ref:
    name: str
    span: Span


@dataclass(frozen=True, slots=True)
class Num:
    value: Fraction
    text: str
    span: Span


@dataclass(frozen=True, slots=True)
class BoolLit:
    value: bool
    span: Span


@dataclass(frozen=True, slots=True)
class SetLit:
    elements: tuple["Expr", ...]
    span: Span


@dataclass(frozen=True, slots=True)
class Call:
    head: Name
    args: tuple["Expr", ...]
    span: Span


Expr = Union[Ref, Num, BoolLit, SetLit, Call]


# ---------------------------------------------------------------- types and options


@dataclass(frozen=True, slots=True)
class TypeName:
    """``real``, ``topic``, ... (resolved by the checker)."""

    name: Name
    span: Span


@dataclass(frozen=True, slots=True)
class SetType:
    element: Name
    span: Span


TypeExpr = Union[TypeName, SetType]


@dataclass(frozen=True, slots=True)
class Bounds:
    lower: Num | None  # None = unbounded ("*")
    upper: Num | None
    span: Span


@dataclass(frozen=True, slots=True)
class Opt:
    """One ``:key value`` option.  ``value`` depends on the key."""

    key: str
    value: object
    span: Span


# ---------------------------------------------------------------- declarations


@dataclass(frozen=True, slots=True)
class TypedGroup:
    names: tuple[Name, ...]
    type: Name | None  # None for an untyped tail
    span: Span


@dataclass(frozen=True, slots=True)
class EnumSpec:
    values: tuple[Name, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class SortGroup:
    names: tuple[Name, ...]
    parent: Name | EnumSpec | None  # None = symbol
    span: Span


@dataclass(frozen=True, slots=True)
class ResourceDecl:
    name: Name
    type: TypeExpr
    options: tuple[Opt, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class ParameterDecl:
    name: Name
    type: TypeExpr
    options: tuple[Opt, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class MorphismDecl:
    name: Name
    options: tuple[Opt, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class HoleDecl:
    name: Name
    options: tuple[Opt, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class ViewDecl:
    name: Name
    options: tuple[Opt, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class Requirements:
    flags: tuple[Name, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class Imports:
    names: tuple[Name, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class Sorts:
    groups: tuple[SortGroup, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class Constants:
    groups: tuple[TypedGroup, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class Resources:
    resources: tuple[ResourceDecl, ...]
    span: Span


DomainSection = Union[
    Requirements, Imports, Sorts, Constants, Resources, MorphismDecl, HoleDecl, ViewDecl
]


@dataclass(frozen=True, slots=True)
class Domain:
    name: Name
    sections: tuple[DomainSection, ...]
    span: Span


# ---------------------------------------------------------------- problem


@dataclass(frozen=True, slots=True)
class DomainRef:
    name: Name
    span: Span


@dataclass(frozen=True, slots=True)
class Objects:
    groups: tuple[TypedGroup, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class Init:
    literals: tuple[Expr, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class Goal:
    condition: Expr
    span: Span


@dataclass(frozen=True, slots=True)
class Horizon:
    steps: Num
    span: Span


@dataclass(frozen=True, slots=True)
class Soft:
    condition: Expr
    options: tuple[Opt, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class Objective:
    sense: Name  # minimize | maximize
    term: Expr
    span: Span


@dataclass(frozen=True, slots=True)
class Metric:
    mode: str  # "single" | "lex" | "pareto"
    objectives: tuple[Objective, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class Deployed:
    names: tuple[Name, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class ViewUse:
    name: Name
    span: Span


ProblemSection = Union[
    DomainRef, Requirements, Objects, Init, Goal, Horizon, Soft, Metric, Deployed, ViewUse
]


@dataclass(frozen=True, slots=True)
class Problem:
    name: Name
    sections: tuple[ProblemSection, ...]
    span: Span


Definition = Union[Domain, Problem]


@dataclass(frozen=True, slots=True)
class SourceFile:
    path: str
    definitions: tuple[Definition, ...]
