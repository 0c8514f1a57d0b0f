"""The categorical IR: the checked, typed, immutable model every later stage consumes.

Objects of the category are tensor products of resources (:class:`Resource`); generators
are :class:`Morphism` s with typed preconditions and effects; a :class:`View` is a
monoidal functor that sends dropped resources to the unit (see :mod:`catc.ir.views`).  The IR
knows nothing of the parse tree; spans are kept only so that answers and diagnostics can
point back at the source.

Numbers are :class:`fractions.Fraction` everywhere.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from enum import Enum
from fractions import Fraction
from types import MappingProxyType
from typing import Never, TypeVar

from catc.ir.grounding import Deployment, Grounding
from catc.ir.labels import Label, LabelKind
from catgrammar.record import Record
from catgrammar.record import set_field as _set
from catgrammar.span import Span

__all__ = [
    "BOOL",
    "EMPTY",
    "INT",
    "REAL",
    "Arith",
    "ArithOp",
    "BoolOp",
    "BoolOpKind",
    "CmpOp",
    "Compare",
    "Const",
    "Constant",
    "Domain",
    "Effect",
    "EffectKind",
    "Expr",
    "Hole",
    "InitValue",
    "Instance",
    "Ite",
    "Label",
    "LabelKind",
    "Literal",
    "Member",
    "Metric",
    "MetricMode",
    "Morphism",
    "MorphismKind",
    "Objective",
    "Param",
    "ParamRef",
    "ParamValue",
    "Problem",
    "Resource",
    "ResourceRef",
    "Sense",
    "SetLit",
    "Soft",
    "Sort",
    "SortKind",
    "TotalChurn",
    "TotalCost",
    "Uses",
    "View",
    "children",
    "frozen",
    "params_in",
    "resources_in",
    "set_of",
    "walk",
]

# ---------------------------------------------------------------- sorts


class SortKind(str, Enum):
    BOOL = "bool"
    INT = "int"
    REAL = "real"
    SYMBOL = "symbol"  # open symbolic sort (grounded per problem, Proposition 1)
    ENUM = "enum"  # closed enumeration
    SET = "set"


class Sort(Record):
    __slots__ = ("kind", "name", "parent", "values", "element", "span")
    _compared = ("kind", "name", "parent", "values", "element")
    kind: SortKind
    name: str
    parent: str | None  # symbolic sorts: the declared super-sort
    values: tuple[str, ...]  # enumerations: the values, in order
    element: Sort | None  # sets: the element sort
    span: Span | None

    def __init__(
        self,
        kind: SortKind,
        name: str,
        parent: str | None = None,
        values: tuple[str, ...] = (),
        element: Sort | None = None,
        span: Span | None = None,
    ) -> None:
        _set(self, "kind", kind)
        _set(self, "name", name)
        _set(self, "parent", parent)
        _set(self, "values", values)
        _set(self, "element", element)
        _set(self, "span", span)

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


# ---------------------------------------------------------------- declarations


class Constant(Record):
    __slots__ = ("name", "sort", "span")
    name: str
    sort: Sort
    span: Span | None

    def __init__(self, name: str, sort: Sort, span: Span | None = None) -> None:
        _set(self, "name", name)
        _set(self, "sort", sort)
        _set(self, "span", span)


class Resource(Record):
    """An atomic object of the category."""

    __slots__ = ("name", "sort", "group", "unit", "lower", "upper", "doc", "span")
    name: str
    sort: Sort
    group: str | None
    unit: str | None
    lower: Fraction | None  # invariant bounds, numeric resources only
    upper: Fraction | None
    doc: str | None
    span: Span | None

    def __init__(
        self,
        name: str,
        sort: Sort,
        group: str | None = None,
        unit: str | None = None,
        lower: Fraction | None = None,
        upper: Fraction | None = None,
        doc: str | None = None,
        span: Span | None = None,
    ) -> None:
        _set(self, "name", name)
        _set(self, "sort", sort)
        _set(self, "group", group)
        _set(self, "unit", unit)
        _set(self, "lower", lower)
        _set(self, "upper", upper)
        _set(self, "doc", doc)
        _set(self, "span", span)

    @property
    def bounds_label(self) -> Label:
        """The label of this resource's bounds (``bounds/r``)."""
        return Label.bounds(self.name)

    @property
    def init_label(self) -> Label:
        """The label of this resource's initial value (``init/r``)."""
        return Label.init(self.name)


class Param(Record):
    """A free parameter θ of a morphism."""

    __slots__ = ("name", "sort", "lower", "upper", "fixed", "span", "bounds_span", "unit")
    name: str
    sort: Sort
    lower: Fraction | None
    upper: Fraction | None
    fixed: bool  # one value for the whole composition (else per activation)
    span: Span | None
    bounds_span: Span | None
    unit: str | None  # as declared (:unit); values and bounds are in this unit

    def __init__(
        self,
        name: str,
        sort: Sort,
        lower: Fraction | None = None,
        upper: Fraction | None = None,
        fixed: bool = False,
        span: Span | None = None,
        bounds_span: Span | None = None,
        unit: str | None = None,
    ) -> None:
        _set(self, "name", name)
        _set(self, "sort", sort)
        _set(self, "lower", lower)
        _set(self, "upper", upper)
        _set(self, "fixed", fixed)
        _set(self, "span", span)
        _set(self, "bounds_span", bounds_span)
        _set(self, "unit", unit)


class Literal(Record):
    """One labelled conjunct (a precondition, goal or soft literal).

    ``label`` names the source construct for unsat cores, e.g. ``pre/lidar-driver/2``."""

    __slots__ = ("expr", "label", "span")
    expr: Expr
    label: str
    span: Span | None

    def __init__(self, expr: Expr, label: str, span: Span | None = None) -> None:
        _set(self, "expr", expr)
        _set(self, "label", label)
        _set(self, "span", span)


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


class Effect(Record):
    __slots__ = ("kind", "resource", "value", "label", "span")
    kind: EffectKind
    resource: str
    value: Expr  # the new value, the amount, or the element
    label: str
    span: Span | None

    def __init__(
        self,
        kind: EffectKind,
        resource: str,
        value: Expr,
        label: str,
        span: Span | None = None,
    ) -> None:
        _set(self, "kind", kind)
        _set(self, "resource", resource)
        _set(self, "value", value)
        _set(self, "label", label)
        _set(self, "span", span)


class MorphismKind(str, Enum):
    HARDWARE = "hardware"
    SOFTWARE = "software"
    BEHAVIOR = "behavior"


class Morphism(Record):
    """A generator of the category: a component with pre- and postconditions."""

    __slots__ = (
        "name", "kind", "params", "pre", "effects", "churn", "uses", "cost", "doc", "grounding", "span", "_reads"
    )  # fmt: skip
    _fields = ("name", "kind", "params", "pre", "effects", "churn", "uses", "cost", "doc", "grounding", "span")
    name: str
    kind: MorphismKind
    params: tuple[Param, ...]
    pre: tuple[Literal, ...]
    effects: tuple[Effect, ...]
    churn: Fraction
    uses: int | None  # None = unlimited
    cost: Expr | None  # None = 1 per activation
    doc: str | None
    grounding: Grounding | None  # what it becomes on the robot (catc.ir.grounding)
    span: Span | None
    _reads: frozenset[str] | None

    def __init__(
        self,
        name: str,
        kind: MorphismKind,
        params: tuple[Param, ...],
        pre: tuple[Literal, ...],
        effects: tuple[Effect, ...],
        churn: Fraction = Fraction(1),
        uses: int | None = None,
        cost: Expr | None = None,
        doc: str | None = None,
        grounding: Grounding | None = None,
        span: Span | None = None,
    ) -> None:
        _set(self, "name", name)
        _set(self, "kind", kind)
        _set(self, "params", params)
        _set(self, "pre", pre)
        _set(self, "effects", effects)
        _set(self, "churn", churn)
        _set(self, "uses", uses)
        _set(self, "cost", cost)
        _set(self, "doc", doc)
        _set(self, "grounding", grounding)
        _set(self, "span", span)
        _set(self, "_reads", None)  # a cache, not a field: computed on first use

    def param(self, name: str) -> Param | None:
        for p in self.params:
            if p.name == name:
                return p
        return None

    @property
    def reads(self) -> frozenset[str]:
        """Resources whose pre-state value this morphism depends on."""
        cached: frozenset[str] | None = self._reads
        if cached is None:
            out: set[str] = set()
            for lit in self.pre:
                out |= resources_in(lit.expr)
            for eff in self.effects:
                out |= resources_in(eff.value)
            cached = frozenset(out)
            _set(self, "_reads", cached)
        return cached

    @property
    def writes(self) -> frozenset[str]:
        return frozenset(e.resource for e in self.effects)

    @property
    def uses_label(self) -> Label:
        """The label of this morphism's use limit (``uses/m``)."""
        return Label.uses(self.name)

    def bound_label(self, param: str) -> Label:
        """The label of one parameter's bounds (``bound/m/p``)."""
        return Label.bound(self.name, param)


class Hole(Record):
    """A structural free variable μ: a missing morphism ranging over one view's resources."""

    __slots__ = ("name", "view", "max_effects", "max_preconditions", "span")
    name: str
    view: str | None
    max_effects: int | None
    max_preconditions: int | None
    span: Span | None

    def __init__(
        self,
        name: str,
        view: str | None,
        max_effects: int | None = None,
        max_preconditions: int | None = None,
        span: Span | None = None,
    ) -> None:
        _set(self, "name", name)
        _set(self, "view", view)
        _set(self, "max_effects", max_effects)
        _set(self, "max_preconditions", max_preconditions)
        _set(self, "span", span)


class View(Record):
    """A projection functor F_v: resources outside ``kept`` are sent to the unit I."""

    __slots__ = ("name", "kept", "dropped", "span")
    name: str
    kept: frozenset[str]
    dropped: frozenset[str]
    span: Span | None

    def __init__(
        self,
        name: str,
        kept: frozenset[str],
        dropped: frozenset[str],
        span: Span | None = None,
    ) -> None:
        _set(self, "name", name)
        _set(self, "kept", kept)
        _set(self, "dropped", dropped)
        _set(self, "span", span)


_K = TypeVar("_K")
_V = TypeVar("_V")


def frozen(mapping: Mapping[_K, _V] | None = None) -> Mapping[_K, _V]:
    return MappingProxyType(dict(mapping or {}))


EMPTY: Mapping[str, Never] = frozen()  # the default of a record's mapping fields (read-only, so shareable)


class Domain(Record):
    __slots__ = (
        "name",
        "requirements",
        "sorts",
        "constants",
        "resources",
        "morphisms",
        "holes",
        "views",
        "imports",
        "deployment",
        "span",
    )
    name: str
    requirements: frozenset[str]
    sorts: Mapping[str, Sort]
    constants: Mapping[str, Constant]
    resources: Mapping[str, Resource]
    morphisms: Mapping[str, Morphism]
    holes: Mapping[str, Hole]
    views: Mapping[str, View]
    imports: tuple[str, ...]
    deployment: Deployment | None  # how compositions are deployed (catc.ir.grounding)
    span: Span | None

    def __init__(
        self,
        name: str,
        requirements: frozenset[str],
        sorts: Mapping[str, Sort] = EMPTY,
        constants: Mapping[str, Constant] = EMPTY,
        resources: Mapping[str, Resource] = EMPTY,
        morphisms: Mapping[str, Morphism] = EMPTY,
        holes: Mapping[str, Hole] = EMPTY,
        views: Mapping[str, View] = EMPTY,
        imports: tuple[str, ...] = (),
        deployment: Deployment | None = None,
        span: Span | None = None,
    ) -> None:
        _set(self, "name", name)
        _set(self, "requirements", requirements)
        _set(self, "sorts", sorts)
        _set(self, "constants", constants)
        _set(self, "resources", resources)
        _set(self, "morphisms", morphisms)
        _set(self, "holes", holes)
        _set(self, "views", views)
        _set(self, "imports", imports)
        _set(self, "deployment", deployment)
        _set(self, "span", span)


class InitValue(Record):
    __slots__ = ("resource", "value", "label", "span")
    resource: str
    value: Const | SetLit
    label: str
    span: Span | None

    def __init__(self, resource: str, value: Const | SetLit, label: str, span: Span | None = None) -> None:
        _set(self, "resource", resource)
        _set(self, "value", value)
        _set(self, "label", label)
        _set(self, "span", span)


class Soft(Record):
    __slots__ = ("expr", "weight", "label", "span")
    expr: Expr
    weight: Fraction
    label: str
    span: Span | None

    def __init__(self, expr: Expr, weight: Fraction, label: str, span: Span | None = None) -> None:
        _set(self, "expr", expr)
        _set(self, "weight", weight)
        _set(self, "label", label)
        _set(self, "span", span)


class Sense(str, Enum):
    MINIMIZE = "minimize"
    MAXIMIZE = "maximize"


class Objective(Record):
    __slots__ = ("sense", "term", "span")
    sense: Sense
    term: Expr
    span: Span | None

    def __init__(self, sense: Sense, term: Expr, span: Span | None = None) -> None:
        _set(self, "sense", sense)
        _set(self, "term", term)
        _set(self, "span", span)


class MetricMode(str, Enum):
    SINGLE = "single"
    LEX = "lex"
    PARETO = "pareto"


class Metric(Record):
    __slots__ = ("mode", "objectives", "span")
    mode: MetricMode
    objectives: tuple[Objective, ...]
    span: Span | None

    def __init__(self, mode: MetricMode, objectives: tuple[Objective, ...], span: Span | None = None) -> None:
        _set(self, "mode", mode)
        _set(self, "objectives", objectives)
        _set(self, "span", span)


class Problem(Record):
    __slots__ = (
        "name",
        "domain",
        "requirements",
        "objects",
        "init",
        "goal",
        "horizon",
        "softs",
        "metric",
        "deployed",
        "view",
        "span",
        "horizon_span",
    )
    name: str
    domain: str
    requirements: frozenset[str]
    objects: Mapping[str, Constant]
    init: Mapping[str, InitValue]
    goal: tuple[Literal, ...]
    horizon: int | None
    softs: tuple[Soft, ...]
    metric: Metric | None
    deployed: tuple[str, ...]
    view: str | None
    span: Span | None
    horizon_span: Span | None

    def __init__(
        self,
        name: str,
        domain: str,
        requirements: frozenset[str],
        objects: Mapping[str, Constant] = EMPTY,
        init: Mapping[str, InitValue] = EMPTY,
        goal: tuple[Literal, ...] = (),
        horizon: int | None = None,
        softs: tuple[Soft, ...] = (),
        metric: Metric | None = None,
        deployed: tuple[str, ...] = (),
        view: str | None = None,
        span: Span | None = None,
        horizon_span: Span | None = None,
    ) -> None:
        _set(self, "name", name)
        _set(self, "domain", domain)
        _set(self, "requirements", requirements)
        _set(self, "objects", objects)
        _set(self, "init", init)
        _set(self, "goal", goal)
        _set(self, "horizon", horizon)
        _set(self, "softs", softs)
        _set(self, "metric", metric)
        _set(self, "deployed", deployed)
        _set(self, "view", view)
        _set(self, "span", span)
        _set(self, "horizon_span", horizon_span)


class Instance(Record):
    """A domain and one of its problems, checked together: the input of every query.

    ``view`` names the projection functor already applied (None = the full category)."""

    __slots__ = ("domain", "problem", "view")
    domain: Domain
    problem: Problem
    view: str | None

    def __init__(self, domain: Domain, problem: Problem, view: str | None = None) -> None:
        _set(self, "domain", domain)
        _set(self, "problem", problem)
        _set(self, "view", view)

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
