"""Operations on compositions that keep them valid: pruning and naming fresh values.

Both are checked by the independent validator, never trusted: :func:`prune_plan` keeps an
activation unless the replay still accepts the composition without it, and
:func:`canonical_fresh` only renames reserve values, which are interchangeable.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

from catc import ir
from catc.semantics.plan import Activation, Plan, fresh_name
from catc.semantics.validate import ValidationFailure, validate
from catgrammar import limits


def drop_idle_steps(
    inst: ir.Instance,
    plan: Plan,
    horizon: int,
    sequential: bool,
    accept: Callable[[Plan], bool] | None = None,
) -> Plan:
    """Drop the steps that change nothing (the state after the step is the state before it:
    a ``transfer c c``, a move to where the robot is).  Every later step then sees the states
    it saw, so the composition stays valid; ``accept(candidate)`` (optimisation: no objective
    worse) decides, as for :func:`prune_plan`.  Cheap: one replay, then one check per idle
    step; not bounded by the command's time, so an answer never keeps a step that does
    nothing because pruning ran out of time."""
    report = validate(inst, plan, horizon=horizon, sequential=sequential)
    if not report.ok:
        return plan
    steps = list(plan.steps)
    for i in range(len(steps) - 1, -1, -1):
        if report.states[i] != report.states[i + 1]:
            continue
        candidate = Plan(tuple(steps[:i] + steps[i + 1 :]), plan.fresh)
        if validate(inst, candidate, horizon=horizon, sequential=sequential).ok and (
            accept is None or accept(candidate)
        ):
            steps = list(candidate.steps)
    return Plan(tuple(steps), plan.fresh)


def prune_plan(
    inst: ir.Instance,
    plan: Plan,
    horizon: int,
    sequential: bool,
    accept: Callable[[Plan], bool] | None = None,
) -> Plan:
    """Drop activations the composition does not need.

    The solver's model may switch on harmless extra morphisms (a step of length 0, a spare
    driver); each activation, last first, is removed when the validator still accepts the
    composition without it (and ``accept(candidate)`` agrees — optimisation passes a check
    that no objective gets worse), and emptied steps disappear.  The result is valid, no
    longer than the input, and irredundant: removing any single activation breaks it —
    unless the command's time is up (or it is interrupted) first: then pruning stops, and the
    composition pruned so far, still valid, is returned."""
    steps = [list(s) for s in plan.steps]
    changed = True
    while changed:
        changed = False
        for i in range(len(steps) - 1, -1, -1):
            for j in range(len(steps[i]) - 1, -1, -1):
                trial = [list(s) for s in steps]
                del trial[i][j]
                candidate = Plan(tuple(tuple(s) for s in trial if s), plan.fresh)
                if limits.expired():
                    return Plan(tuple(tuple(s) for s in steps), plan.fresh)
                try:
                    fits = validate(inst, candidate, horizon=horizon, sequential=sequential).ok and (
                        accept is None or accept(candidate)
                    )
                except limits.Stopped:
                    return Plan(tuple(tuple(s) for s in steps), plan.fresh)
                if fits:
                    steps = [s for s in trial if s]
                    changed = True
                    break
            if changed:
                break
    return Plan(tuple(tuple(s) for s in steps), plan.fresh)


def canonical_fresh(plan: Plan) -> Plan:
    """Rename fresh values by first appearance (topic#1, topic#2, ...) and forget unused ones.
    Fresh values are interchangeable (Proposition 1: any injection fixing the constants
    preserves every atom), so this changes nothing but the names."""
    rename: dict[str, str] = {}
    counters: dict[str, int] = {}
    for _, act in plan.activations:
        for v in act.params.values():
            if isinstance(v, str) and v in plan.fresh and v not in rename:
                sort = plan.fresh[v]
                counters[sort] = counters.get(sort, 0) + 1
                rename[v] = fresh_name(sort, counters[sort])
    steps = tuple(
        tuple(
            Activation(a.morphism, {k: rename.get(v, v) if isinstance(v, str) else v for k, v in a.params.items()})
            for a in step
        )
        for step in plan.steps
    )
    return Plan(steps, {rename[v]: plan.fresh[v] for v in rename})


def checked(
    inst: ir.Instance, plan: Plan, horizon: int, sequential: bool, what: str
) -> tuple[Mapping[str, object], ...]:
    """The replay's states of a composition the solver returned, or :class:`ValidationFailure`
    (a bug in catc: an answer is never shown unvalidated)."""
    report = validate(inst, plan, horizon=horizon, sequential=sequential)
    if not report.ok:
        problems = "; ".join(v.message for v in report.violations[:5])
        raise ValidationFailure(f"the independent validator rejected {what}: {problems}")
    return report.states
