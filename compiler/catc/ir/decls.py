"""Declarations of a domain: constants, resources, parameters, labelled literals and
effects, morphisms, holes and views (re-exported by :mod:`catc.ir`)."""

from __future__ import annotations

from collections.abc import Mapping
from enum import Enum
from fractions import Fraction
from types import MappingProxyType
from typing import Never, TypeVar

from catc.ir.expr import Expr, resources_in
from catc.ir.grounding import Grounding
from catc.ir.label import Label
from catc.ir.sorts import Sort
from catgrammar.record import Record
from catgrammar.record import set_field as _set
from catgrammar.span import Span

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
