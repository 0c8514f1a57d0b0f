"""``catc optimize``: the query — its options, JSON and rendering.  The search for the optimum
is :mod:`catc.queries.optimum` (its public names are re-exported here).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from catc import ir
from catc.ir.numbers import decimal_text, fraction_text
from catc.ir.text import to_text
from catc.present.composition import print_composition, where_text
from catc.present.console import Console, Table, counted
from catc.present.values import parameter_units_json, show_value, state_json, steps_json, timings_json, units_json
from catc.queries.base import (
    Kind,
    Option,
    Query,
    certificate_option,
    diagram_artifact,
    diagram_option,
    json_option,
    objectives_option,
    timeout_option,
)
from catc.queries.optimum import (
    DEEPEN_FROM,
    DEFAULT_TACTICS,
    STRATEGIES,
    ObjectiveValue,
    OptResult,
    OptStatus,
    SoftOutcome,
    Tactics,
    objectives_of,
    optimize,
)
from catc.semantics.plan import value_to_json

__all__ = [
    "DEEPEN_FROM",
    "DEFAULT_TACTICS",
    "QUERY",
    "STRATEGIES",
    "ObjectiveValue",
    "OptResult",
    "OptStatus",
    "SoftOutcome",
    "Tactics",
    "objectives_of",
    "optimize",
    "optimize_json",
    "render",
]


# ====================================================================== output


def optimize_json(inst: ir.Instance, result: OptResult) -> dict:
    doc = {
        "schema": "catc.optimize/1",
        "status": result.status.value,
        "problem": inst.problem.name,
        "domain": inst.domain.name,
        "view": inst.view,
        "horizon": result.horizon,
        "objectives": [
            {
                "sense": ov.objective.sense.value,
                "term": to_text(ov.objective.term),
                "value": value_to_json(ov.value) if ov.value is not None else None,
                "decimal": decimal_text(ov.value) if ov.value is not None else None,
                "attained": ov.attained,
                "bound": ov.bound,
            }
            for ov in result.values
        ],
        "soft": [
            {
                "label": o.soft.label,
                "constraint": to_text(o.soft.expr),
                "weight": value_to_json(o.soft.weight),
                "violated": o.violated,
            }
            for o in result.softs
        ],
        "steps": None,
        "fresh": None,
        "final_state": None,
        "reason": result.reason,
        "timings": timings_json(result.timings),
    }
    if result.plan is not None:
        doc["steps"] = steps_json(inst, result.plan)
        doc["fresh"] = dict(result.plan.fresh)
        if result.states:
            doc["final_state"] = state_json(result.states[-1])
            doc["units"] = units_json(inst)
            if parameter_units := parameter_units_json(inst):  # only when some parameter declares one
                doc["parameter_units"] = parameter_units
    return doc


def _objective_rows(inst: ir.Instance, result: OptResult) -> list[tuple[str, str, str, str]]:
    rows = []
    for i, ov in enumerate(result.values, 1):
        term = to_text(ov.objective.term)
        if i == 1 and inst.problem.softs:
            term += " with soft penalties"
        if ov.bound is not None and not ov.attained:
            value = ov.bound + (f" (composition shown: {show_value(ov.value)})" if ov.value is not None else "")
        elif ov.value is None:
            value = "undefined"
        else:
            value = show_value(ov.value)
            if ov.value.denominator != 1:
                value += f"  [{fraction_text(ov.value)}]"
        rows.append((str(i), ov.objective.sense.value, term, value))
    return rows


_COLOUR = {"OPT": "green", "SUBOPT": "yellow", "UNSAT": "red", "UNKNOWN": "yellow", "UNBOUNDED": "red"}
_WHAT = {"OPT": "proven optimal", "UNBOUNDED": "the objective is unbounded"}
_BEST_SO_FAR = {
    "timeout": "best found before the time limit (not proven optimal)",
    "interrupted": "best found before the run was interrupted (not proven optimal)",
}


def render(console: Console, inst: ir.Instance, result: OptResult, options: Mapping[str, Any] | None = None) -> None:
    status = result.status.value.upper()
    head = f"[bold {_COLOUR[status]}]{status}[/]"
    where = where_text(inst)
    if result.status is OptStatus.UNSAT:
        console.print(f"{head}  no composition within {counted(result.horizon, 'step')} ({where})")
        return
    if result.plan is None:
        why = (
            "interrupted before a composition was found"
            if result.reason == "interrupted"
            else f"the solver gave up ({result.reason})"
        )
        console.print(f"{head}  {why} for {where}")
        return
    what = _WHAT.get(status) or _BEST_SO_FAR.get(
        result.reason or "", f"best found before the solver stopped ({result.reason})"
    )
    console.print(f"{head}  {what} for {where}")
    table = Table("#", "sense", "objective", "value", right=(0,))
    for row in _objective_rows(inst, result):
        table.add_row(*row)
    console.print(table)
    if result.softs:
        console.print()
        st = Table("soft constraint", "weight", "outcome")
        for o in result.softs:
            st.add_row(to_text(o.soft.expr), show_value(o.soft.weight), "violated" if o.violated else "satisfied")
        console.print(st)
    console.print()
    print_composition(console, inst, result.plan, result.states)
    t = result.timings
    console.print(
        f"[dim]time: encode {t.get('encode', 0) * 1000:.0f} ms, optimise {t.get('solve', 0) * 1000:.0f} ms, "
        f"validate {t.get('validate', 0) * 1000:.0f} ms; horizon {result.horizon}[/]"
    )


def check(inst: ir.Instance, options: Mapping[str, Any]) -> str | None:
    if options.get("objectives") is None and not objectives_of(inst) and not inst.problem.softs:
        return "nothing to optimise: the problem has no (:metric ...) or (:soft ...); give --minimize or --maximize"
    return None


QUERY = Query(
    "optimize",
    summary="Find the best composition for the problem's (:metric ...) and soft constraints.",
    description=(
        "PATHS is PROBLEM, or DOMAIN PROBLEM.  --minimize/--maximize replace the metric.  Exit 0 "
        "optimum (OPT), 1 infeasible or unbounded, 2 input error, 3 stopped early (best-so-far "
        "reported as SUBOPT) or unknown."
    ),
    options=(
        objectives_option(
            "Minimise this term (repeatable; with --maximize, in the order given: lexicographic).",
            "Maximise this term (repeatable).",
        ),
        timeout_option("Stop after this many seconds; the best composition so far is reported (exit 3)."),
        json_option("catc.optimize/1"),
        diagram_option(),
        Option(
            "strategy",
            ("--strategy",),
            Kind.CHOICE,
            "deepen: optimise over the shortest feasible horizon, then prove nothing longer is better; "
            "single: one encoding of the whole horizon.",
            default="deepen",
            choices=STRATEGIES,
            show_default=True,
        ),
        certificate_option(),
    ),
    run=optimize,
    to_json=optimize_json,
    render=render,
    check=check,
    artifacts=diagram_artifact,
    progress=True,
)
