"""The categorical IR: the checked, typed, immutable model every later stage consumes.

Objects of the category are tensor products of resources (:class:`Resource`); generators
are :class:`Morphism` s with typed preconditions and effects; a :class:`View` is a
monoidal functor that sends dropped resources to the unit (see :mod:`catc.view`).  The IR
knows nothing of the parse tree; spans are kept only so that answers and diagnostics can
point back at the source.

Numbers are :class:`fractions.Fraction` everywhere.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum
from fractions import Fraction
from types import MappingProxyType
from typing import Mapping, Union

from catgrammar.span import Span

# ---------------------------------------------------------------- sorts


class SortKind(str, Enum):
    BOOL = "bool"
    INT = "int"
    REAL = "real"
    SYMBOL = "symbol"  # open symbolic sort (grounded per problem, Proposition 1)
    ENUM = "enum"  # closed enumeration
    SET = "set"


@dataclass(frozen=True, slots=True)
class Sort:
    kind: SortKind
    name: str
    parent: str | None = None  # symbolic sorts: the declared super-sort
    values: tuple[str, ...] = ()  # enumerations: the values, in order
    element: "Sort | None" = None  # sets: the element sort
    span: Span | None = field(default=None, compare=False, repr=False)

    @property
    def is_numeric(self) -> bool:
        return self.kind in (SortKind.INT, SortKind.REAL)

    @property
    def is_symbolic(self) -> bool:
        return self.kind in (SortKind.SYMBOL, SortKind.ENUM)

    def __str__(self) -> str:
        return f"(set {self.element})" if self.kind is SortKind.SET else self.name


BOOL = Sort(SortKind.BOOL, "bool")
INT = Sort(SortKind.INT, "int")
REAL = Sort(SortKind.REAL, "real")


def set_of(element: Sort) -> Sort:
    return Sort(SortKind.SET, f"(set {element.name})", element=element)


# ---------------------------------------------------------------- expressions


@dataclass(frozen=True, slots=True)
class Const:
    """A literal: Fraction for numbers, bool, or the name of a symbolic constant."""

    value: Fraction | bool | str
    sort: Sort
    span: Span | None = None


@dataclass(frozen=True, slots=True)
class ResourceRef:
    name: str
    sort: Sort
    span: Span | None = None


@dataclass(frozen=True, slots=True)
class ParamRef:
    """A morphism's free parameter θ (inside that morphism's conditions and effects)."""

    name: str
    sort: Sort
    span: Span | None = None


@dataclass(frozen=True, slots=True)
class SetLit:
    elements: tuple["Expr", ...]
    sort: Sort
    span: Span | None = None


class ArithOp(str, Enum):
    ADD = "+"
    SUB = "-"
    MUL = "*"
    DIV = "/"
    MIN = "min"
    MAX = "max"


@dataclass(frozen=True, slots=True)
class Arith:
    """n-ary arithmetic; ``(- x)`` is negation."""

    op: ArithOp
    args: tuple["Expr", ...]
    sort: Sort
    span: Span | None = None


class CmpOp(str, Enum):
    EQ = "="
    LT = "<"
    LE = "<="
    GT = ">"
    GE = ">="


@dataclass(frozen=True, slots=True)
class Compare:
    op: CmpOp
    left: "Expr"
    right: "Expr"
    span: Span | None = None
    sort: Sort = BOOL


class BoolOpKind(str, Enum):
    AND = "and"
    OR = "or"
    NOT = "not"
    IMPLY = "imply"


@dataclass(frozen=True, slots=True)
class BoolOp:
    op: BoolOpKind
    args: tuple["Expr", ...]
    span: Span | None = None
    sort: Sort = BOOL


@dataclass(frozen=True, slots=True)
class Ite:
    cond: "Expr"
    then: "Expr"
    orelse: "Expr"
    sort: Sort
    span: Span | None = None


@dataclass(frozen=True, slots=True)
class Member:
    element: "Expr"
    set: "Expr"
    span: Span | None = None
    sort: Sort = BOOL


# objective-only terms ------------------------------------------------------


@dataclass(frozen=True, slots=True)
class TotalChurn:
    """Weighted symmetric difference against the deployed composition (paper eq. churn)."""

    span: Span | None = None
    sort: Sort = REAL


@dataclass(frozen=True, slots=True)
class TotalCost:
    """Sum of the costs of every activation."""

    span: Span | None = None
    sort: Sort = REAL


@dataclass(frozen=True, slots=True)
class Uses:
    """How many times a morphism is activated."""

    morphism: str
    span: Span | None = None
    sort: Sort = INT


@dataclass(frozen=True, slots=True)
class ParamValue:
    """The value of a morphism's θ (fixed, or used at most once)."""

    morphism: str
    param: str
    sort: Sort
    span: Span | None = None


Expr = Union[
    Const, ResourceRef, ParamRef, SetLit, Arith, Compare, BoolOp, Ite, Member,
    TotalChurn, TotalCost, Uses, ParamValue,
]


def children(expr: Expr) -> tuple[Expr, ...]:
    """Immediate sub-expressions (for generic walks)."""
    if isinstance(expr, (Arith, BoolOp)):
        return expr.args
    if isinstance(expr, SetLit):
        return expr.elements
    if isinstance(expr, Compare):
        return (expr.left, expr.right)
    if isinstance(expr, Member):
        return (expr.element, expr.set)
    if isinstance(expr, Ite):
        return (expr.cond, expr.then, expr.orelse)
    return ()


def walk(expr: Expr):
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


# ---------------------------------------------------------------- declarations


@dataclass(frozen=True, slots=True)
class Constant:
    name: str
    sort: Sort
    span: Span | None = None


@dataclass(frozen=True, slots=True)
class Resource:
    """An atomic object of the category."""

    name: str
    sort: Sort
    group: str | None = None
    unit: str | None = None
    lower: Fraction | None = None  # invariant bounds, numeric resources only
    upper: Fraction | None = None
    doc: str | None = None
    span: Span | None = None


@dataclass(frozen=True, slots=True)
class Param:
    """A free parameter θ of a morphism."""

    name: str
    sort: Sort
    lower: Fraction | None = None
    upper: Fraction | None = None
    fixed: bool = False  # one value for the whole composition (else per activation)
    span: Span | None = None
    bounds_span: Span | None = None


@dataclass(frozen=True, slots=True)
class Literal:
    """One labelled conjunct (a precondition, goal or soft literal).

    ``label`` names the source construct for unsat cores, e.g. ``pre/lidar-driver/2``."""

    expr: Expr
    label: str
    span: Span | None = None


class EffectKind(str, Enum):
    ASSIGN = "assign"
    INCREASE = "increase"
    DECREASE = "decrease"
    ADD = "add"
    REMOVE = "remove"

    @property
    def commutative(self) -> bool:
        """Effects of this kind from parallel morphisms on one resource commute."""
        return self is not EffectKind.ASSIGN


@dataclass(frozen=True, slots=True)
class Effect:
    kind: EffectKind
    resource: str
    value: Expr  # the new value, the amount, or the element
    label: str
    span: Span | None = None


class MorphismKind(str, Enum):
    HARDWARE = "hardware"
    SOFTWARE = "software"
    BEHAVIOR = "behavior"


@dataclass(frozen=True, slots=True)
class Morphism:
    """A generator of the category: a component with pre- and postconditions."""

    name: str
    kind: MorphismKind
    params: tuple[Param, ...]
    pre: tuple[Literal, ...]
    effects: tuple[Effect, ...]
    churn: Fraction = Fraction(1)
    uses: int | None = None  # None = unlimited
    cost: Expr | None = None  # None = 1 per activation
    doc: str | None = None
    span: Span | None = None

    def param(self, name: str) -> Param | None:
        for p in self.params:
            if p.name == name:
                return p
        return None

    @property
    def reads(self) -> frozenset[str]:
        """Resources whose pre-state value this morphism depends on."""
        out: set[str] = set()
        for lit in self.pre:
            out |= resources_in(lit.expr)
        for eff in self.effects:
            out |= resources_in(eff.value)
        return frozenset(out)

    @property
    def writes(self) -> frozenset[str]:
        return frozenset(e.resource for e in self.effects)


@dataclass(frozen=True, slots=True)
class Hole:
    """A structural free variable μ: a missing morphism ranging over one view's resources."""

    name: str
    view: str | None
    max_effects: int | None = None
    max_preconditions: int | None = None
    span: Span | None = None


@dataclass(frozen=True, slots=True)
class View:
    """A projection functor F_v: resources outside ``kept`` are sent to the unit I."""

    name: str
    kept: frozenset[str]
    dropped: frozenset[str]
    span: Span | None = None


def _ro(mapping: Mapping | None = None) -> Mapping:
    return MappingProxyType(dict(mapping or {}))


@dataclass(frozen=True)
class Domain:
    name: str
    requirements: frozenset[str]
    sorts: Mapping[str, Sort] = field(default_factory=_ro)
    constants: Mapping[str, Constant] = field(default_factory=_ro)
    resources: Mapping[str, Resource] = field(default_factory=_ro)
    morphisms: Mapping[str, Morphism] = field(default_factory=_ro)
    holes: Mapping[str, Hole] = field(default_factory=_ro)
    views: Mapping[str, View] = field(default_factory=_ro)
    imports: tuple[str, ...] = ()
    span: Span | None = None


@dataclass(frozen=True, slots=True)
class InitValue:
    resource: str
    value: Const | SetLit
    label: str
    span: Span | None = None


@dataclass(frozen=True, slots=True)
class Soft:
    expr: Expr
    weight: Fraction
    label: str
    span: Span | None = None


class Sense(str, Enum):
    MINIMIZE = "minimize"
    MAXIMIZE = "maximize"


@dataclass(frozen=True, slots=True)
class Objective:
    sense: Sense
    term: Expr
    span: Span | None = None


class MetricMode(str, Enum):
    SINGLE = "single"
    LEX = "lex"
    PARETO = "pareto"


@dataclass(frozen=True, slots=True)
class Metric:
    mode: MetricMode
    objectives: tuple[Objective, ...]
    span: Span | None = None


@dataclass(frozen=True)
class Problem:
    name: str
    domain: str
    requirements: frozenset[str]
    objects: Mapping[str, Constant] = field(default_factory=_ro)
    init: Mapping[str, InitValue] = field(default_factory=_ro)
    goal: tuple[Literal, ...] = ()
    horizon: int | None = None
    softs: tuple[Soft, ...] = ()
    metric: Metric | None = None
    deployed: tuple[str, ...] = ()
    view: str | None = None
    span: Span | None = None
    horizon_span: Span | None = None


@dataclass(frozen=True)
class Instance:
    """A domain and one of its problems, checked together: the input of every query.

    ``view`` names the projection functor already applied (None = the full category)."""

    domain: Domain
    problem: Problem
    view: str | None = None

    @property
    def resources(self) -> Mapping[str, Resource]:
        return self.domain.resources

    @property
    def morphisms(self) -> Mapping[str, Morphism]:
        return self.domain.morphisms

    def constants(self) -> dict[str, Constant]:
        """Domain constants, enumeration values and problem objects."""
        out = dict(self.domain.constants)
        out.update(self.problem.objects)
        return out

    def subsorts(self, sort: Sort) -> set[str]:
        """Names of ``sort`` and every symbolic sort below it."""
        names = {sort.name}
        changed = True
        while changed:
            changed = False
            for s in self.domain.sorts.values():
                if s.parent in names and s.name not in names:
                    names.add(s.name)
                    changed = True
        return names

    def constants_of(self, sort: Sort) -> list[str]:
        """The known constants of a symbolic sort (its own and its subsorts'), in order."""
        if sort.kind is SortKind.ENUM:
            return list(sort.values)
        names = self.subsorts(sort)
        return [c.name for c in self.constants().values() if c.sort.name in names]
