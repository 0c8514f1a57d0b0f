"""The abstract syntax tree of .cat files.

A faithful, typed record of what the user wrote, each node carrying its source
:class:`~catgrammar.span.Span`.  Nothing here is resolved or checked; the checker in
``catc.frontend.check`` turns it into the categorical IR.  Expressions keep one generic shape,
:class:`Call` (``(head args...)``), so the checker can say precisely what is wrong with an
unknown or misplaced operator.
"""

from __future__ import annotations

from fractions import Fraction

from catgrammar.record import Record, set_field
from catgrammar.span import Span

_set = set_field
_Node = Record  # the base of every node


class Name(_Node):
    __slots__ = ("text", "span")
    text: str
    span: Span

    def __init__(self, text: str, span: Span) -> None:
        _set(self, "text", text)
        _set(self, "span", span)


# ---------------------------------------------------------------- expressions


class Ref(_Node):
    __slots__ = ("name", "span")
    name: str
    span: Span

    def __init__(self, name: str, span: Span) -> None:
        _set(self, "name", name)
        _set(self, "span", span)


class Num(_Node):
    __slots__ = ("value", "text", "span")
    value: Fraction
    text: str
    span: Span

    def __init__(self, value: Fraction, text: str, span: Span) -> None:
        _set(self, "value", value)
        _set(self, "text", text)
        _set(self, "span", span)


class BoolLit(_Node):
    __slots__ = ("value", "span")
    value: bool
    span: Span

    def __init__(self, value: bool, span: Span) -> None:
        _set(self, "value", value)
        _set(self, "span", span)


class SetLit(_Node):
    __slots__ = ("elements", "span")
    elements: tuple[Expr, ...]
    span: Span

    def __init__(self, elements: tuple[Expr, ...], span: Span) -> None:
        _set(self, "elements", elements)
        _set(self, "span", span)


class Call(_Node):
    __slots__ = ("head", "args", "span")
    head: Name
    args: tuple[Expr, ...]
    span: Span

    def __init__(self, head: Name, args: tuple[Expr, ...], span: Span) -> None:
        _set(self, "head", head)
        _set(self, "args", args)
        _set(self, "span", span)


class Quantity(_Node):
    """A number with a unit, ``512 MB``: the parser reads it as a number and a name (the
    grammar cannot tell ``(* 2 MB)`` from ``(* 2 x)`` without the declarations); the checker
    forms this node where the name is no declared name but a unit (docs/language.md §Units)."""

    __slots__ = ("number", "unit", "span")
    number: Num
    unit: Name
    span: Span

    def __init__(self, number: Num, unit: Name, span: Span) -> None:
        _set(self, "number", number)
        _set(self, "unit", unit)
        _set(self, "span", span)


Expr = Ref | Num | BoolLit | SetLit | Call | Quantity


# ---------------------------------------------------------------- types and options


class TypeName(_Node):
    """``real``, ``topic``, ... (resolved by the checker)."""

    __slots__ = ("name", "span")
    name: Name
    span: Span

    def __init__(self, name: Name, span: Span) -> None:
        _set(self, "name", name)
        _set(self, "span", span)


class SetType(_Node):
    __slots__ = ("element", "span")
    element: Name
    span: Span

    def __init__(self, element: Name, span: Span) -> None:
        _set(self, "element", element)
        _set(self, "span", span)


TypeExpr = TypeName | SetType


class Bounds(_Node):
    __slots__ = ("lower", "upper", "span")
    lower: Num | None  # None = unbounded ("*")
    upper: Num | None
    span: Span

    def __init__(self, lower: Num | None, upper: Num | None, span: Span) -> None:
        _set(self, "lower", lower)
        _set(self, "upper", upper)
        _set(self, "span", span)


class Opt(_Node):
    """One ``:key value`` option.  ``value`` depends on the key."""

    __slots__ = ("key", "value", "span")
    key: str
    value: object
    span: Span

    def __init__(self, key: str, value: object, span: Span) -> None:
        _set(self, "key", key)
        _set(self, "value", value)
        _set(self, "span", span)


# ---------------------------------------------------------------- declarations


class TypedGroup(_Node):
    __slots__ = ("names", "type", "span")
    names: tuple[Name, ...]
    type: Name | None  # None for an untyped tail
    span: Span

    def __init__(self, names: tuple[Name, ...], type: Name | None, span: Span) -> None:
        _set(self, "names", names)
        _set(self, "type", type)
        _set(self, "span", span)


class EnumSpec(_Node):
    __slots__ = ("values", "span")
    values: tuple[Name, ...]
    span: Span

    def __init__(self, values: tuple[Name, ...], span: Span) -> None:
        _set(self, "values", values)
        _set(self, "span", span)


class SortGroup(_Node):
    __slots__ = ("names", "parent", "span")
    names: tuple[Name, ...]
    parent: Name | EnumSpec | None  # None = symbol
    span: Span

    def __init__(self, names: tuple[Name, ...], parent: Name | EnumSpec | None, span: Span) -> None:
        _set(self, "names", names)
        _set(self, "parent", parent)
        _set(self, "span", span)


class ResourceDecl(_Node):
    __slots__ = ("name", "type", "options", "span")
    name: Name
    type: TypeExpr
    options: tuple[Opt, ...]
    span: Span

    def __init__(self, name: Name, type: TypeExpr, options: tuple[Opt, ...], span: Span) -> None:
        _set(self, "name", name)
        _set(self, "type", type)
        _set(self, "options", options)
        _set(self, "span", span)


class ParameterDecl(_Node):
    __slots__ = ("name", "type", "options", "span")
    name: Name
    type: TypeExpr
    options: tuple[Opt, ...]
    span: Span

    def __init__(self, name: Name, type: TypeExpr, options: tuple[Opt, ...], span: Span) -> None:
        _set(self, "name", name)
        _set(self, "type", type)
        _set(self, "options", options)
        _set(self, "span", span)


class MorphismDecl(_Node):
    __slots__ = ("name", "options", "span")
    name: Name
    options: tuple[Opt, ...]
    span: Span

    def __init__(self, name: Name, options: tuple[Opt, ...], span: Span) -> None:
        _set(self, "name", name)
        _set(self, "options", options)
        _set(self, "span", span)


class HoleDecl(_Node):
    __slots__ = ("name", "options", "span")
    name: Name
    options: tuple[Opt, ...]
    span: Span

    def __init__(self, name: Name, options: tuple[Opt, ...], span: Span) -> None:
        _set(self, "name", name)
        _set(self, "options", options)
        _set(self, "span", span)


class ViewDecl(_Node):
    __slots__ = ("name", "options", "span")
    name: Name
    options: tuple[Opt, ...]
    span: Span

    def __init__(self, name: Name, options: tuple[Opt, ...], span: Span) -> None:
        _set(self, "name", name)
        _set(self, "options", options)
        _set(self, "span", span)


class Str(_Node):
    """A string datum of a grounding block (its text unescaped)."""

    __slots__ = ("text", "span")
    text: str
    span: Span

    def __init__(self, text: str, span: Span) -> None:
        _set(self, "text", text)
        _set(self, "span", span)


class DatumList(_Node):
    """``(datum ...)`` in a grounding block."""

    __slots__ = ("items", "span")
    items: tuple[Datum, ...]
    span: Span

    def __init__(self, items: tuple[Datum, ...], span: Span) -> None:
        _set(self, "items", items)
        _set(self, "span", span)


Datum = Name | Num | Str | BoolLit | DatumList


class Ground(_Node):
    """``(KIND :key datum ...)``: a morphism's grounding block; ``pairs`` are Opts whose
    value is a :data:`Datum`."""

    __slots__ = ("kind", "pairs", "span")
    kind: Name
    pairs: tuple[Opt, ...]
    span: Span

    def __init__(self, kind: Name, pairs: tuple[Opt, ...], span: Span) -> None:
        _set(self, "kind", kind)
        _set(self, "pairs", pairs)
        _set(self, "span", span)


class DeploymentDecl(_Node):
    """``(:deployment :project NAME :executor "image")``."""

    __slots__ = ("pairs", "span")
    pairs: tuple[Opt, ...]
    span: Span

    def __init__(self, pairs: tuple[Opt, ...], span: Span) -> None:
        _set(self, "pairs", pairs)
        _set(self, "span", span)


class Requirements(_Node):
    __slots__ = ("flags", "span")
    flags: tuple[Name, ...]
    span: Span

    def __init__(self, flags: tuple[Name, ...], span: Span) -> None:
        _set(self, "flags", flags)
        _set(self, "span", span)


class Imports(_Node):
    __slots__ = ("names", "span")
    names: tuple[Name, ...]
    span: Span

    def __init__(self, names: tuple[Name, ...], span: Span) -> None:
        _set(self, "names", names)
        _set(self, "span", span)


class Sorts(_Node):
    __slots__ = ("groups", "span")
    groups: tuple[SortGroup, ...]
    span: Span

    def __init__(self, groups: tuple[SortGroup, ...], span: Span) -> None:
        _set(self, "groups", groups)
        _set(self, "span", span)


class Constants(_Node):
    __slots__ = ("groups", "span")
    groups: tuple[TypedGroup, ...]
    span: Span

    def __init__(self, groups: tuple[TypedGroup, ...], span: Span) -> None:
        _set(self, "groups", groups)
        _set(self, "span", span)


class Resources(_Node):
    __slots__ = ("resources", "span")
    resources: tuple[ResourceDecl, ...]
    span: Span

    def __init__(self, resources: tuple[ResourceDecl, ...], span: Span) -> None:
        _set(self, "resources", resources)
        _set(self, "span", span)


DomainSection = (
    Requirements | Imports | Sorts | Constants | Resources | MorphismDecl | HoleDecl | ViewDecl | DeploymentDecl
)


class Domain(_Node):
    __slots__ = ("name", "sections", "span")
    name: Name
    sections: tuple[DomainSection, ...]
    span: Span

    def __init__(self, name: Name, sections: tuple[DomainSection, ...], span: Span) -> None:
        _set(self, "name", name)
        _set(self, "sections", sections)
        _set(self, "span", span)


# ---------------------------------------------------------------- problem


class DomainRef(_Node):
    __slots__ = ("name", "span")
    name: Name
    span: Span

    def __init__(self, name: Name, span: Span) -> None:
        _set(self, "name", name)
        _set(self, "span", span)


class Objects(_Node):
    __slots__ = ("groups", "span")
    groups: tuple[TypedGroup, ...]
    span: Span

    def __init__(self, groups: tuple[TypedGroup, ...], span: Span) -> None:
        _set(self, "groups", groups)
        _set(self, "span", span)


class Init(_Node):
    __slots__ = ("literals", "span")
    literals: tuple[Expr, ...]
    span: Span

    def __init__(self, literals: tuple[Expr, ...], span: Span) -> None:
        _set(self, "literals", literals)
        _set(self, "span", span)


class Goal(_Node):
    __slots__ = ("condition", "span")
    condition: Expr
    span: Span

    def __init__(self, condition: Expr, span: Span) -> None:
        _set(self, "condition", condition)
        _set(self, "span", span)


class Horizon(_Node):
    __slots__ = ("steps", "span")
    steps: Num
    span: Span

    def __init__(self, steps: Num, span: Span) -> None:
        _set(self, "steps", steps)
        _set(self, "span", span)


class Soft(_Node):
    __slots__ = ("condition", "options", "span")
    condition: Expr
    options: tuple[Opt, ...]
    span: Span

    def __init__(self, condition: Expr, options: tuple[Opt, ...], span: Span) -> None:
        _set(self, "condition", condition)
        _set(self, "options", options)
        _set(self, "span", span)


class Objective(_Node):
    __slots__ = ("sense", "term", "span")
    sense: Name  # minimize | maximize
    term: Expr
    span: Span

    def __init__(self, sense: Name, term: Expr, span: Span) -> None:
        _set(self, "sense", sense)
        _set(self, "term", term)
        _set(self, "span", span)


class Metric(_Node):
    __slots__ = ("mode", "objectives", "span")
    mode: str  # "single" | "lex" | "pareto"
    objectives: tuple[Objective, ...]
    span: Span

    def __init__(self, mode: str, objectives: tuple[Objective, ...], span: Span) -> None:
        _set(self, "mode", mode)
        _set(self, "objectives", objectives)
        _set(self, "span", span)


class Deployed(_Node):
    __slots__ = ("names", "span")
    names: tuple[Name, ...]
    span: Span

    def __init__(self, names: tuple[Name, ...], span: Span) -> None:
        _set(self, "names", names)
        _set(self, "span", span)


class ViewUse(_Node):
    __slots__ = ("name", "span")
    name: Name
    span: Span

    def __init__(self, name: Name, span: Span) -> None:
        _set(self, "name", name)
        _set(self, "span", span)


ProblemSection = DomainRef | Requirements | Objects | Init | Goal | Horizon | Soft | Metric | Deployed | ViewUse


class Problem(_Node):
    __slots__ = ("name", "sections", "span")
    name: Name
    sections: tuple[ProblemSection, ...]
    span: Span

    def __init__(self, name: Name, sections: tuple[ProblemSection, ...], span: Span) -> None:
        _set(self, "name", name)
        _set(self, "sections", sections)
        _set(self, "span", span)


Definition = Domain | Problem


class SourceFile(_Node):
    __slots__ = ("path", "definitions")
    path: str
    definitions: tuple[Definition, ...]

    def __init__(self, path: str, definitions: tuple[Definition, ...]) -> None:
        _set(self, "path", path)
        _set(self, "definitions", definitions)
