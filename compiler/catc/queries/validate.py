"""validate: replay a composition from elsewhere and report every violation.

The independent validator (:mod:`catc.semantics.validate`) replays the composition on exact
rationals; the composition comes as a :class:`~catc.semantics.plan.Plan` or as a
``catc.plan/1`` document (the steps of any ``--json`` answer).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from catc import ir
from catc.present.console import Console, counted, escape
from catc.present.values import state_json
from catc.queries.base import ExitCode, Kind, Option, Query, Result, Status, json_option
from catc.semantics.plan import Plan, read_plan
from catc.semantics.plan import param_sorts as param_sorts  # its old address (catc.interfaces.command)
from catc.semantics.validate import Report, validate


class ValidateStatus(Status):
    VALID = "valid", ExitCode.OK
    INVALID = "invalid", ExitCode.FAIL


class Validation(Result):
    """The answer of :func:`validate_plan` (a plain class, as every query's result: importing
    :mod:`dataclasses` costs about 7 ms of a command's start)."""

    query = "validate"
    __slots__ = ("status", "plan", "report", "timings")
    status: ValidateStatus

    def __init__(
        self, status: ValidateStatus, plan: Plan, report: Report, timings: dict[str, float] | None = None
    ) -> None:
        self.status = status
        self.plan = plan
        self.report = report
        self.timings: dict[str, float] = {} if timings is None else timings

    def __repr__(self) -> str:
        return f"Validation(status={self.status!r}, plan={self.plan!r}, report={self.report!r})"

    @property
    def ok(self) -> bool:
        return self.report.ok

    @property
    def violations(self) -> tuple:
        return tuple(self.report.violations)

    @property
    def states(self) -> tuple:
        return tuple(self.report.states)


def validate_plan(
    inst: ir.Instance,
    plan: Plan | Mapping[str, Any],
    *,
    horizon: int | None = None,
    sequential: bool = False,
) -> Validation:
    """Replay ``plan`` (a Plan or a ``catc.plan/1`` document; a malformed document raises
    :class:`catc.semantics.plan.PlanFormatError`) and collect every violation."""
    if not isinstance(plan, Plan):
        plan = read_plan(inst, plan)
    report = validate(inst, plan, horizon=horizon, sequential=sequential)
    return Validation(ValidateStatus.VALID if report.ok else ValidateStatus.INVALID, plan, report)


def validate_json(inst: ir.Instance, result: Validation) -> dict:
    report = result.report
    return {
        "schema": "catc.validate/1",
        "valid": report.ok,
        "violations": [
            {"kind": v.kind, "message": v.message, "step": v.step, "morphism": v.morphism, "label": v.label}
            for v in report.violations
        ],
        "final_state": state_json(report.states[-1]) if report.ok and report.states else None,
    }


def render(console: Console, inst: ir.Instance, result: Validation, options: Mapping[str, Any] | None = None) -> None:
    report = result.report
    if report.ok:
        console.print(
            f"valid: {counted(len(result.plan), 'step')} reach{'es' if len(result.plan) == 1 else ''} the goal of '{inst.problem.name}'"
        )
        return
    n = len(report.violations)
    console.print(f"invalid: {n} violation{'s' if n != 1 else ''}")
    for v in report.violations:
        where = f"step {v.step}: " if v.step is not None else ""
        console.print(f"  {where}{v.kind}: {escape(v.message)}")


QUERY = Query(
    "validate",
    summary="Replay a composition from elsewhere (a catc.plan/1 JSON file, or a solve/optimize/recompose --json answer) and report every violation.",
    description="PATHS is PROBLEM, or DOMAIN PROBLEM.  Exit 0 valid, 1 invalid, 2 input error.",
    options=(
        Option(
            "plan", ("PLAN_FILE",), Kind.PLAN_FILE, "The composition: a catc.plan/1 JSON document or a --json answer."
        ),
        json_option("catc.validate/1"),
    ),
    run=validate_plan,
    to_json=validate_json,
    render=render,
)
