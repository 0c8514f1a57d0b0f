"""Cores of catalog-scale infeasibility for diagnose (issue 24).

Global budget, power, RAM and GPU conflicts across competing alternatives are invisible to
relaxed reachability and cost the step encoding seconds per check.  The horizon-free
consumption abstraction (:mod:`catc.smt.consumption`) proves them in milliseconds on one
incremental solver with assumption literals; its irreducible core is a core of the full
semantics (the abstraction only says less), and diagnose's deletion pass then checks that
each member is needed in the full semantics — those checks are feasible ones, which the
relaxation's witness or the solver settle quickly — and shrinks further where the
abstraction was too weak.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from typing import Protocol

from catc import ir
from catc.semantics.plan import Activation, Plan
from catc.semantics.validate import validate
from catc.semantics.witness import BIG, _candidate, _restricted
from catc.smt.backend import Check
from catc.smt.consumption import Consumption
from catgrammar import limits
from catgrammar.record import replace


class _Model(Protocol):
    inst: ir.Instance
    labels: list[str]
    components: tuple[str, ...] | None


class AbstractCores:
    """The abstraction of one labelled model, built on first use and kept for every test."""

    def __init__(self, model: _Model) -> None:
        self.model = model
        self._abstraction: Consumption | None = None
        self.found = 0  # subsets the abstraction proved infeasible

    @property
    def abstraction(self) -> Consumption:
        if self._abstraction is None:
            m = self.model
            self._abstraction = Consumption(m.inst, m.components, known=m.labels)
        return self._abstraction

    def core(self, labels: Sequence[str]) -> list[str] | None:
        """An irreducible core of ``labels`` for the abstraction, or None (it cannot refute
        them, or the time ran out)."""
        limits.check_time("diagnosing")
        a = self.abstraction
        if not a.labels:
            return None
        wanted = set(a.labels)
        relevant = [label for label in labels if label in wanted]
        core = a.irreducible(relevant, limits.for_check())
        if core is None:
            return None
        self.found += 1
        keep = set(core)
        return [label for label in labels if label in keep]

    def witnessed(self, labels: Sequence[str], horizon: int, extended: int) -> bool:
        """Whether the abstraction's model of ``labels`` gives a composition (the supporting
        components in rank order, one per step) that the independent validator accepts on
        the instance enforcing exactly ``labels`` — then ``labels`` are feasible."""
        limits.check_time("diagnosing")
        if self.model.components is not None:  # a fixed composition: diagnose's own witness
            return False
        a = self.abstraction
        r, _ = a.check(labels, limits.for_check())
        if r is not Check.SAT:
            return False
        order = a.support(labels)
        if order is None:
            return False
        enforced = frozenset(labels)
        steps = horizon if "horizon" in enforced else extended
        if len(order) > steps:
            return False
        plan = _candidate(self.model.inst, enforced, order, order)
        if plan is None:
            return False
        inst = self.model.inst
        for candidate in (plan, _unbounded(inst, plan, enforced)):
            for big in (False, True):
                if validate(_freed(_restricted(inst, enforced, big), enforced), candidate, horizon=steps).ok:
                    return True
        return False


def _unbounded(inst: ir.Instance, plan: Plan, enforced: frozenset[str]) -> Plan:
    """The plan with every numeric θ whose bound is dropped at -10⁹ (a decrease by it then
    gives the resource back: one of the values the solver may choose)."""

    def params(a: Activation) -> dict:
        m = inst.morphisms[a.morphism]
        out = dict(a.params)
        for p in m.params:
            if p.sort.is_numeric and f"bound/{m.name}/{p.name}" not in enforced:
                out[p.name] = -BIG
        return out

    return Plan([[Activation(a.morphism, params(a)) for a in step] for step in plan.steps], plan.fresh)


def _freed(inst: ir.Instance, enforced: frozenset[str]) -> ir.Instance:
    """The instance enforcing exactly ``enforced`` as the solver reads it: a dropped effect
    may or may not happen — here a dropped decrease, increase, removal or numeric assignment
    does not, a dropped addition or Boolean set true does — and a dropped initial value is free: here every fact
    holds initially."""
    morphisms = {}
    for name, m in inst.morphisms.items():
        effects = tuple(eff for eff in m.effects if eff.label in enforced or _gives(inst, eff))
        morphisms[name] = replace(m, effects=effects)
    init = dict(inst.problem.init)
    for name, given in inst.problem.init.items():  # a dropped initial value is free: the facts hold
        sort = inst.resources[name].sort if name in inst.resources else None
        if given.label in enforced or sort is None:
            continue
        if sort.kind is ir.SortKind.BOOL:
            init[name] = replace(given, value=ir.Const(True, sort))
        elif sort.kind is ir.SortKind.SET and sort.element is not None:
            values = tuple(ir.Const(c, sort.element) for c in inst.constants_of(sort.element))
            init[name] = replace(given, value=ir.SetLit(values, sort))
    problem = replace(inst.problem, init=ir.frozen(init))
    return ir.Instance(replace(inst.domain, morphisms=ir.frozen(morphisms)), problem, inst.view)


def consumption_refutation(inst: ir.Instance, components: Collection[str] | None = None) -> list[str] | None:
    """The labels of an irreducible abstract core when the abstraction refutes ``inst``
    with every label enforced (no composition of any length exists), else None."""
    a = Consumption(inst, components)
    return a.irreducible(a.labels, limits.for_check())


def _gives(inst: ir.Instance, eff: ir.Effect) -> bool:
    """An addition to a set, or a Boolean set true (a dropped one happens in the witness)."""
    if eff.kind is ir.EffectKind.ADD:
        return True
    res = inst.resources.get(eff.resource)
    return (
        res is not None
        and res.sort.kind is ir.SortKind.BOOL
        and eff.kind is ir.EffectKind.ASSIGN
        and isinstance(eff.value, ir.Const)
        and eff.value.value is True
    )
