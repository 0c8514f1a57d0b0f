"""recompose: a new composition with the least weighted churn against the deployed one.

Churn (paper eq. churn) weighs every component added to or removed from the deployed
composition; the new composition minimises it lexicographically with the mission objective,
in either priority (eq. reconfigure): *stability* first (least churn, then the mission) or
*objective* first.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace
from fractions import Fraction

from catc import ir
from catc.queries.optimize import objectives_of, optimize


@dataclass
class ChurnItem:
    morphism: str
    change: str  # "added" | "removed"
    weight: Fraction


@dataclass
class Recomposition:
    result: object  # the OptResult of the lexicographic optimisation
    deployed: tuple[str, ...]
    priority: str  # "stability" (churn first) | "objective"
    churn: Fraction | None = None
    items: list[ChurnItem] = field(default_factory=list)


def recompose(
    inst: ir.Instance,
    *,
    deployed: Iterable[str] | None = None,
    priority: str = "stability",
    objectives: list[ir.Objective] | None = None,
    horizon: int | None = None,
    sequential: bool = False,
    timeout: float | None = None,
    progress: Callable[[str], None] | None = None,
) -> Recomposition:
    if deployed is not None:
        inst = ir.Instance(inst.domain, replace(inst.problem, deployed=tuple(deployed)), inst.view)
    mission = objectives_of(inst) if objectives is None else objectives
    mission = [o for o in mission if not isinstance(o.term, ir.TotalChurn)]
    churn = ir.Objective(ir.Sense.MINIMIZE, ir.TotalChurn())
    order = [churn] + mission if priority == "stability" else mission + [churn]
    result = optimize(inst, order, horizon=horizon, sequential=sequential, timeout=timeout, progress=progress)
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
