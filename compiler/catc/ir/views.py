"""Views as functors on the IR.

A view ``v`` is the strict monoidal functor ``F_v`` that sends every dropped resource to the
unit ``I`` and every other resource to itself (paper §IV-B).  On the IR this means: the
dropped resources disappear from the object, and every literal over them — preconditions,
effects, initial values, goal and soft literals — disappears from the morphisms and the
problem.  Morphisms keep their names, parameters and weights, so a composition found in
the view is a composition of the same components.

``apply_view`` is functorial: applying the identity view changes nothing, and applying
``v`` then ``w`` equals applying the view that keeps the intersection (tested).
"""

from __future__ import annotations

from catc import ir
from catgrammar.record import replace
from catgrammar.span import Span


class ViewError(Exception):
    """A problem cannot be projected (its objective mentions a dropped resource)."""

    def __init__(self, message: str, span: Span | None = None) -> None:
        super().__init__(message)
        self.span = span


def _keeps(expr: ir.Expr, kept: frozenset[str]) -> bool:
    return ir.resources_in(expr) <= kept


def project_domain(domain: ir.Domain, kept: frozenset[str]) -> ir.Domain:
    """F_v on the domain: resources outside ``kept`` ↦ I."""
    resources = {n: r for n, r in domain.resources.items() if n in kept}
    morphisms = {}
    for name, m in domain.morphisms.items():
        pre = tuple(lit for lit in m.pre if _keeps(lit.expr, kept))
        effects = tuple(e for e in m.effects if e.resource in kept and _keeps(e.value, kept))
        morphisms[name] = replace(m, pre=pre, effects=effects)
    views = {
        n: ir.View(v.name, v.kept & kept, v.dropped | (frozenset(domain.resources) - kept), v.span)
        for n, v in domain.views.items()
    }
    return replace(domain, resources=ir.frozen(resources), morphisms=ir.frozen(morphisms), views=ir.frozen(views))


def project_instance(inst: ir.Instance, kept: frozenset[str], view_name: str | None) -> ir.Instance:
    kept = kept & frozenset(inst.domain.resources)
    domain = project_domain(inst.domain, kept)
    p = inst.problem
    if p.metric is not None:
        for obj in p.metric.objectives:
            lost = ir.resources_in(obj.term) - kept
            if lost:
                names = ", ".join(sorted(lost))
                raise ViewError(f"the objective reads {names}, which view '{view_name}' drops", obj.span)
    problem = replace(
        p,
        init=ir.frozen({n: v for n, v in p.init.items() if n in kept}),
        goal=tuple(lit for lit in p.goal if _keeps(lit.expr, kept)),
        softs=tuple(s for s in p.softs if _keeps(s.expr, kept)),
    )
    return ir.Instance(domain, problem, view_name if view_name else inst.view)


def apply_view(inst: ir.Instance, view: str | None) -> ir.Instance:
    """Apply the named view of the domain (None = the problem's own ``(:view ...)``,
    and no view at all when the problem names none)."""
    name = view if view is not None else inst.problem.view
    if name is None:
        return inst
    v = inst.domain.views.get(name)
    if v is None:
        raise ViewError(f"unknown view '{name}'")
    return project_instance(inst, v.kept, name)
