"""recompose: a new composition with the least weighted churn against the deployed one.

Churn (paper eq. churn) weighs every component added to or removed from the deployed
composition; the new composition minimises it lexicographically with the mission objective,
in either priority (eq. reconfigure): *stability* first (least churn, then the mission) or
*objective* first.
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Mapping, Sequence
from fractions import Fraction
from itertools import combinations
from typing import Any, NamedTuple

from catc import ir
from catc.present.console import Console, Table, counted
from catc.present.values import show_value, value_to_json
from catc.queries import optimize as opt
from catc.queries.base import (
    Kind,
    Option,
    Progress,
    Query,
    Result,
    certificate_option,
    diagram_artifact,
    diagram_option,
    json_option,
    timeout_option,
)
from catc.queries.churn_search import best_set
from catc.queries.optimize import DEFAULT_TACTICS, OptResult, OptStatus, Tactics, objectives_of, optimize
from catc.queries.optimum import _finish, _not_worse, _scores
from catc.semantics.horizon import horizon_of
from catc.semantics.plan import Plan
from catc.semantics.validate import validate
from catc.semantics.witness import _candidate
from catc.smt.consumption import FixedSet, init_value
from catgrammar.record import replace


class ChurnItem(NamedTuple):  # (not a dataclass: `catc recompose` does not import dataclasses)
    morphism: str
    change: str  # "added" | "removed"
    weight: Fraction


class Recomposition(Result):
    query = "recompose"
    __slots__ = ("result", "deployed", "priority", "churn", "items")

    def __init__(
        self,
        result: OptResult,  # the lexicographic optimisation
        deployed: tuple[str, ...],
        priority: str,  # "stability" (churn first) | "objective"
        churn: Fraction | None = None,
        items: list[ChurnItem] | None = None,
    ) -> None:
        self.result, self.deployed, self.priority, self.churn = result, deployed, priority, churn
        self.items: list[ChurnItem] = [] if items is None else items

    def __repr__(self) -> str:
        return (
            f"Recomposition(result={self.result!r}, deployed={self.deployed!r}, priority={self.priority!r}, "
            f"churn={self.churn!r}, items={self.items!r})"
        )

    @property
    def status(self) -> OptStatus:  # type: ignore[override]
        return self.result.status

    @property
    def timings(self) -> dict[str, float]:  # type: ignore[override]
        return self.result.timings

    @property
    def plan(self):
        return self.result.plan

    @property
    def states(self) -> tuple:
        return self.result.states


def recompose(
    inst: ir.Instance,
    *,
    deployed: Iterable[str] | None = None,
    priority: str = "stability",
    objectives: list[ir.Objective] | None = None,
    horizon: int | None = None,
    sequential: bool = False,
    timeout: float | None = None,
    progress: Progress | None = None,
    tactics: Tactics = DEFAULT_TACTICS,
) -> Recomposition:
    if deployed is not None:
        inst = ir.Instance(inst.domain, replace(inst.problem, deployed=tuple(deployed)), inst.view)
    mission = objectives_of(inst) if objectives is None else objectives
    mission = [o for o in mission if not isinstance(o.term, ir.TotalChurn)]
    churn = ir.Objective(ir.Sense.MINIMIZE, ir.TotalChurn())
    order = [churn] + mission if priority == "stability" else mission + [churn]
    result = None
    if priority == "stability" or not mission:
        t0 = time.perf_counter()
        result = _least_churn_by_sets(inst, order, horizon_of(inst, horizon), sequential)
        if result is not None:
            result.timings["total"] = time.perf_counter() - t0
    fallback = None  # the search's best composition when it could not prove it
    if result is None:
        t0 = time.perf_counter()
        deadline = None if timeout is None else time.monotonic() + timeout / 2
        result = _best_by_search(inst, order, horizon_of(inst, horizon), sequential, deadline)
        if result is not None:
            result.timings["total"] = time.perf_counter() - t0
            if result.status is not OptStatus.OPT:
                fallback, result = result, None
                if timeout is not None:
                    timeout = max(timeout - (time.perf_counter() - t0), 0.1)
    if result is None:
        result = optimize(
            inst,
            order,
            horizon=horizon,
            sequential=sequential,
            timeout=timeout,
            progress=progress,
            tactics=tactics,
            known=_deployed_plan(inst),
        )
        if result.plan is None and fallback is not None:
            result = fallback
    rec = Recomposition(result, inst.problem.deployed, priority)
    if result.plan is not None:
        used = result.plan.components
        old = set(inst.problem.deployed)
        rec.items = [
            ChurnItem(m, "added", inst.morphisms[m].churn) for m in inst.morphisms if m in used and m not in old
        ]
        rec.items += [
            ChurnItem(m, "removed", inst.morphisms[m].churn) for m in inst.morphisms if m in old and m not in used
        ]
        rec.churn = sum((i.weight for i in rec.items), Fraction(0))
    return rec


#: The most component sets :func:`_least_churn_by_sets` looks at before leaving it to the solver.
MAX_SETS = 20_000
#: The most components it adds or removes.
MAX_CHANGES = 3


def _least_churn_by_sets(
    inst: ir.Instance, objectives: list[ir.Objective], k: int, sequential: bool
) -> OptResult | None:
    """The least-churn recomposition without the solver (issue 24), or None (no claim).

    With every churn weight equal to ``w``, a composition of churn ``w·s`` uses the deployed
    set with ``s`` components added or removed.  The sets of ``s = 0, 1, …`` changes are
    enumerated until some pass the consumption abstraction for fixed sets
    (:class:`~catc.smt.consumption.FixedSet`); the component set of every composition
    passes, so none of fewer changes exists.  Each passing set's components, one per step in
    an order they can fire, θ at their lower bounds, must be accepted by the validator (else
    None), and the best of them by the mission objectives — each the maximum of a bounded
    resource that only decreases — must be at least as good as the abstraction's optimistic
    value (the initial value minus the set's least consumption) of every passing set: then
    no composition of the same churn does better.  No soft constraints."""
    churn, *mission = objectives
    if not isinstance(churn.term, ir.TotalChurn) or inst.problem.softs:
        return None
    weights = {m.churn for m in inst.morphisms.values()}
    if len(weights) != 1 or next(iter(weights)) <= 0:
        return None
    fixed = FixedSet(inst)
    names: list[str] = []  # the resources the mission maximises
    for o in mission:
        term = o.term
        if not (o.sense is ir.Sense.MAXIMIZE and isinstance(term, ir.ResourceRef) and term.name in fixed.decreasing):
            return None
        names.append(term.name)
    deployed = [m for m in inst.morphisms if m in set(inst.problem.deployed)]
    others = [m for m in inst.morphisms if m not in set(deployed)]
    seen = 0
    passing: list[list[str]] = []
    everything = fixed.spent(deployed)
    for size in range(MAX_CHANGES + 1):
        for removed in range(size + 1):
            for out in combinations(deployed, removed):
                base = [m for m in deployed if m not in out]
                spent = fixed.plus(everything, out, -1)
                if size > removed and not fixed.fits(base, spent):
                    continue  # additions only take more of every only-decreasing resource
                for added in combinations(others, size - removed):
                    seen += 1
                    if seen > MAX_SETS:
                        return None
                    order = fixed.order({*base, *added}, fixed.plus(spent, added))
                    if order is not None:
                        passing.append(order)
        if passing:
            break
    else:
        return None
    best: tuple[list, Plan] | None = None
    for order in passing:
        replayed = _replayed(inst, order, mission, k, sequential)
        if replayed is None:
            return None
        values, plan = replayed
        if best is None or (values != best[0] and _not_worse(values, best[0], mission)):
            best = (values, plan)
    assert best is not None
    for order in passing:  # the optimistic value of every passing set: its final values at best
        spent = fixed.spent(order)
        optimistic = [init_value(inst, r) - spent[r] for r in names]
        if not _not_worse(best[0], optimistic, mission):
            return None
    result = OptResult(OptStatus.OPT, k)
    _finish(inst, result, best[1], objectives, [], [("exact", None)] * len(objectives), k, sequential, True)
    return result


def _replayed(
    inst: ir.Instance, order: Sequence[str], objectives: list[ir.Objective], k: int, sequential: bool
) -> tuple[list, Plan] | None:
    """The composition of the components ``order`` (one step each, θ at their lower bounds)
    and its scores, when the validator replays it within ``k`` steps; else None."""
    bounds = frozenset(m.bound_label(p.name) for m in inst.morphisms.values() for p in m.params)
    plan = _candidate(inst, bounds, order, order)
    if plan is None or len(plan.steps) > k:
        return None
    report = validate(inst, plan, horizon=k, sequential=sequential)
    if not report.ok:
        return None
    return _scores(inst, plan, objectives, [], k, sequential, report), plan


def _deployed_plan(inst: ir.Instance) -> list[Plan]:
    """The deployed composition as it is written — its components one a step, in the order of
    ``(:deployed ...)``, θ at their lower bounds — for :func:`optimize` to compare its first
    composition with (``known``; the validator decides whether it is one)."""
    bounds = frozenset(m.bound_label(p.name) for m in inst.morphisms.values() for p in m.params)
    deployed = [m for m in inst.problem.deployed if m in inst.morphisms]
    plan = _candidate(inst, bounds, deployed, deployed) if deployed else None
    return [] if plan is None else [plan]


def _best_by_search(
    inst: ir.Instance, objectives: list[ir.Objective], k: int, sequential: bool, deadline: float | None = None
) -> OptResult | None:
    """The lexicographic optimum of churn and the mission objectives without the solver,
    in either priority (issue 24), or None (no claim): the passing component set of
    greatest optimistic key (:func:`catc.queries.churn_search.best_set`), replayed by the
    validator one step per component, θ at their lower bounds, must score exactly that key
    — then no composition does better, as every composition's key is at most its component
    set's optimistic key.  A search stopped early (``deadline``, a ``time.monotonic()``)
    gives its best composition as SUBOPT, for when the solver finds none.  No soft
    constraints."""
    if inst.problem.softs:
        return None
    found = best_set(inst, objectives, deadline=deadline)
    if found is None:
        return None
    order, key, proven = found
    replayed = _replayed(inst, order, objectives, k, sequential)
    if replayed is None:
        return None
    values, plan = replayed
    wanted = [-v if isinstance(o.term, ir.TotalChurn) else v for o, v in zip(objectives, key)]
    if values != wanted:
        return None
    if not proven:
        result = OptResult(OptStatus.SUBOPT, k, reason="the search for the best component set stopped early")
        _finish(inst, result, plan, objectives, [], [("exact", None)] * len(objectives), k, sequential, True)
        return result
    result = OptResult(OptStatus.OPT, k)
    _finish(inst, result, plan, objectives, [], [("exact", None)] * len(objectives), k, sequential, True)
    return result


# ====================================================================== output


def recompose_json(inst: ir.Instance, rec: Recomposition) -> dict:
    doc = opt.optimize_json(inst, rec.result)
    doc["schema"] = "catc.recompose/1"
    doc["priority"] = rec.priority
    doc["deployed"] = list(rec.deployed)
    doc["churn"] = value_to_json(rec.churn) if rec.churn is not None else None
    doc["changes"] = [
        {"morphism": i.morphism, "change": i.change, "weight": value_to_json(i.weight)} for i in rec.items
    ]
    return doc


def render(console: Console, inst: ir.Instance, rec: Recomposition, options: Mapping[str, Any] | None = None) -> None:
    res = rec.result
    if res.plan is None:
        opt.render(console, inst, res)
        return
    first = (
        "stability first (least churn, then the mission objective)"
        if rec.priority == "stability"
        else "objective first (the mission objective, then least churn)"
    )
    console.print(
        f"[bold green]{res.status.value.upper()}[/]  {first}: churn {show_value(rec.churn)} against the deployed "
        f"composition of {counted(len(rec.deployed), 'component')}"
    )
    if rec.items:
        table = Table("change", "component", "churn weight")
        for item in rec.items:
            table.add_row("+ added" if item.change == "added" else "- removed", item.morphism, show_value(item.weight))
        console.print(table)
    else:
        console.print("  no component changes")
    console.print()
    opt.render(console, inst, res)


def check(inst: ir.Instance, options: Mapping[str, Any]) -> str | None:
    if options.get("deployed") is None and not inst.problem.deployed:
        return "no deployed composition: add (:deployed ...) to the problem or pass --deployed"
    return None


QUERY = Query(
    "recompose",
    summary="A new composition with the least weighted churn against the deployed one.",
    description="Exit 0 optimum, 1 infeasible, 2 input error, 3 stopped early.",
    options=(
        Option(
            "deployed",
            ("--deployed",),
            Kind.COMPONENTS,
            "The deployed composition (comma-separated morphisms; default: the problem's (:deployed ...)).",
            metavar="COMPONENTS",
        ),
        Option(
            "priority",
            ("--priority",),
            Kind.CHOICE,
            "stability: least churn first, then the mission objective; objective: the reverse.",
            default="stability",
            choices=("stability", "objective"),
            show_default=True,
        ),
        timeout_option("Stop after this many seconds; the best composition so far is reported (exit 3)."),
        json_option("catc.recompose/1"),
        diagram_option(),
        certificate_option(),
    ),
    run=recompose,
    to_json=recompose_json,
    render=render,
    check=check,
    artifacts=diagram_artifact,
    progress=True,
)
