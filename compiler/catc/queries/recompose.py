"""recompose: a new composition with the least weighted churn against the deployed one.

Churn (paper eq. churn) weighs every component added to or removed from the deployed
composition; the new composition minimises it lexicographically with the mission objective,
in either priority (eq. reconfigure): *stability* first (least churn, then the mission) or
*objective* first.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import Any

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
from catc.queries.optimize import DEFAULT_TACTICS, OptResult, OptStatus, Tactics, objectives_of, optimize


@dataclass
class ChurnItem:
    morphism: str
    change: str  # "added" | "removed"
    weight: Fraction


@dataclass
class Recomposition(Result):
    query = "recompose"
    result: OptResult  # the lexicographic optimisation
    deployed: tuple[str, ...]
    priority: str  # "stability" (churn first) | "objective"
    churn: Fraction | None = None
    items: list[ChurnItem] = field(default_factory=list)

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
    result = optimize(
        inst, order, horizon=horizon, sequential=sequential, timeout=timeout, progress=progress, tactics=tactics
    )
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
