"""A checked domain, a problem over it, and their instance (re-exported by :mod:`catc.ir`)."""

from __future__ import annotations

from collections.abc import Mapping
from enum import Enum
from fractions import Fraction

from catc.ir.decls import EMPTY, Constant, Hole, Literal, Morphism, Resource, View
from catc.ir.expr import Const, Expr, SetLit
from catc.ir.grounding import Deployment
from catc.ir.sorts import Sort, SortKind
from catgrammar.record import Record
from catgrammar.record import set_field as _set
from catgrammar.span import Span


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
