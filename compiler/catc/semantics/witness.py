"""Feasibility witnesses for subsets of labels, found without a solver and proven by the
independent validator.

``catc diagnose`` must show that a core minus any one member is feasible.  For a small
subset of labels most constraints are dropped, and a composition is easy to write down: each
component of the fixed composition once, one per step, in the order the relaxed reachability
analysis first lets them fire (or, with no composition fixed, the empty composition).  This
module builds the instance that enforces exactly the given labels — a dropped precondition,
goal literal, bound or use limit is left out; a dropped initial value is free (tried at its
written value, then numbers at 10⁹); a dropped effect may happen, and does — and replays the
candidate on it with :func:`catc.semantics.validate.validate`.  When the validator accepts
one, the subset is feasible: that composition satisfies every enforced construct.  Otherwise
nothing is concluded (the solver decides).
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from fractions import Fraction

from catc import ir
from catc.semantics.plan import Activation, Plan, Value
from catc.semantics.relaxed import RelaxedAnalysis
from catc.semantics.validate import validate
from catgrammar.record import replace

#: The value a free numeric initial value takes in the second try.
BIG = Fraction(10**9)


def witnessed(
    inst: ir.Instance,
    enforced: Collection[str],
    components: Collection[str] | None,
    horizon: int,
    extended: int,
    order: Sequence[str] | None = None,
) -> bool:
    """Whether a composition satisfying exactly the ``enforced`` labels (relative to
    ``components``) was found and accepted by the validator.  ``order``: the morphisms in the
    order the relaxation of the same labels first lets them fire (computed when not given)."""
    return witness_plan(inst, enforced, components, horizon, extended, order) is not None


def witness_plan(
    inst: ir.Instance,
    enforced: Collection[str],
    components: Collection[str] | None,
    horizon: int,
    extended: int,
    order: Sequence[str] | None = None,
) -> tuple[Plan, bool] | None:
    """The composition :func:`witnessed` found, and whether the free initial values were
    set to :data:`BIG` (see :func:`_restricted`); None when none was found."""
    if order is None:
        order = list(RelaxedAnalysis(inst, enforced, components).fired)
    plan = _candidate(inst, enforced, components, order)
    if plan is None:
        return None
    steps = horizon if ir.Label.horizon() in enforced else extended
    if len(plan.steps) > steps:
        return None
    for big in (False, True):
        if validate(_restricted(inst, enforced, big), plan, horizon=steps).ok:
            return plan, big
    return None


def _candidate(
    inst: ir.Instance, enforced: Collection[str], components: Collection[str] | None, order: Sequence[str]
) -> Plan | None:
    if components is None:
        return Plan([])
    names = [m for m in order if m in components]
    names += [m for m in inst.morphisms if m in components and m not in names]
    steps = []
    for name in names:
        params = _params(inst, inst.morphisms[name], enforced)
        if params is None:
            return None
        steps.append([Activation(name, params)])
    return Plan(steps)


def _params(inst: ir.Instance, m: ir.Morphism, enforced: Collection[str]) -> dict[str, Value] | None:
    """A value for each θ: within its bounds when they are enforced (else 0), true, or the
    first constant of its sort."""
    out: dict[str, Value] = {}
    for p in m.params:
        kind = p.sort.kind
        if p.sort.is_numeric:
            bounded = m.bound_label(p.name) in enforced
            v = (p.lower if p.lower is not None else p.upper) if bounded else None
            v = Fraction(0) if v is None else v
            if kind is ir.SortKind.INT and v.denominator != 1:
                return None
            out[p.name] = v
        elif kind is ir.SortKind.BOOL:
            out[p.name] = True
        elif p.sort.is_symbolic:
            constants = inst.constants_of(p.sort)
            if not constants:
                return None
            out[p.name] = constants[0]
        else:
            return None
    return out


def _restricted(inst: ir.Instance, enforced: Collection[str], big: bool) -> ir.Instance:
    """The instance whose constraints are exactly the ``enforced`` labels."""
    morphisms: dict[str, ir.Morphism] = {}
    for m in inst.morphisms.values():
        params = tuple(p if m.bound_label(p.name) in enforced else replace(p, lower=None, upper=None) for p in m.params)
        morphisms[m.name] = replace(
            m,
            pre=tuple(lit for lit in m.pre if lit.label in enforced),
            params=params,
            uses=m.uses if m.uses_label in enforced else None,
        )
    resources = {  # an unbounded resource as it is (no label to make)
        r.name: r
        if (r.lower is None and r.upper is None) or r.bounds_label in enforced
        else replace(r, lower=None, upper=None)
        for r in inst.resources.values()
    }
    init: dict[str, ir.InitValue] = {}
    for name, given in inst.problem.init.items():
        free = given.label not in enforced and isinstance(given.value, ir.Const) and given.value.sort.is_numeric
        init[name] = replace(given, value=ir.Const(BIG, given.value.sort)) if big and free else given
    domain = replace(inst.domain, morphisms=ir.frozen(morphisms), resources=ir.frozen(resources))
    problem = replace(
        inst.problem, init=ir.frozen(init), goal=tuple(lit for lit in inst.problem.goal if lit.label in enforced)
    )
    return ir.Instance(domain, problem, inst.view)


#: The instance whose constraints are exactly the enforced labels (a witness is replayed on it).
restricted = _restricted
