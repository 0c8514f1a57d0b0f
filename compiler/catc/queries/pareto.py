"""Pareto fronts: every non-dominated composition for two or more objectives (paper §V-A).

The guided improvement algorithm (Rayside et al., "The guided improvement algorithm for
exact, general-purpose, many-objective combinatorial optimization", 2009) needs nothing but
satisfiability checks, so it works for nonlinear objectives such as MMMU·(1 − WER):

1. find any composition not dominated by a front point found so far;
2. while some composition dominates it, move to that one;
3. it is Pareto-optimal: record it, and from then on require every answer to be strictly
   better than it in at least one objective.

Every recorded point is replayed by the independent validator, which recomputes its
objective values exactly.  ``max_points``/``timeout`` bound fronts that are infinite
(continuous θ) or large; the result says whether the front is complete.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir.numbers import decimal_text
from catc.ir.text import to_text
from catc.present.console import Console, Table
from catc.present.plot import ascii_plot, draw_front
from catc.present.values import show_value, steps_json, timings_json
from catc.queries.base import (
    ExitCode,
    InputError,
    Kind,
    Option,
    Query,
    Result,
    Status,
    Use,
    json_option,
    objectives_option,
    timeout_option,
)
from catc.semantics.compositions import canonical_fresh
from catc.semantics.horizon import default_horizon
from catc.semantics.plan import Plan, value_to_json
from catc.semantics.validate import ValidationFailure, objective_value, validate
from catc.smt.backend import DEFAULT_BACKEND, Check, open_backend
from catc.smt.encoder import Encoder
from catc.smt.readback import read_plan
from catc.smt.terms import App, and_, better, or_
from catgrammar import codes


@dataclass
class ParetoPoint:
    values: tuple[Fraction, ...]
    plan: Plan
    states: tuple = ()


class ParetoStatus(Status):
    FRONT = "front", ExitCode.OK
    UNSAT = "unsat", ExitCode.FAIL
    UNKNOWN = "unknown", ExitCode.UNKNOWN


@dataclass
class ParetoResult(Result):
    query = "pareto"
    status: ParetoStatus
    objectives: list[ir.Objective]
    points: list[ParetoPoint] = field(default_factory=list)
    complete: bool = True
    horizon: int = 0
    checks: int = 0
    timings: dict[str, float] = field(default_factory=dict)

    @property
    def settled(self) -> bool:
        return self.complete


def pareto(
    inst: ir.Instance,
    objectives: list[ir.Objective] | None = None,
    *,
    horizon: int | None = None,
    sequential: bool = False,
    max_points: int = 100,
    timeout: float | None = None,
) -> ParetoResult:
    if objectives is None:
        metric = inst.problem.metric
        objectives = list(metric.objectives) if metric else []
    if len(objectives) < 2:
        raise ValueError("a Pareto front needs at least two objectives")
    start = time.perf_counter()
    k = default_horizon(inst) if horizon is None else horizon
    search = _Guided(inst, objectives, k, sequential, start + timeout if timeout else None)
    result = search.result
    result.timings["encode"] = time.perf_counter() - start
    while len(result.points) < max_points:
        found = search.next_point()
        if found is None:
            break
        values, plan = found
        report = validate(inst, plan, horizon=k, sequential=sequential)
        if not report.ok:
            raise ValidationFailure(
                "the independent validator rejected a Pareto point: "
                + "; ".join(v.message for v in report.violations[:5])
            )
        recomputed = tuple(objective_value(inst, plan, o.term, report.states[-1]) for o in objectives)
        if recomputed != values:
            raise ValidationFailure(f"Pareto point values {values} differ from the composition's {recomputed}")
        result.points.append(ParetoPoint(values, canonical_fresh(plan), report.states))
        # Every later answer must be strictly better than this point in some objective.
        search.solver.assert_term(search.improving(values))
    else:
        result.complete = False
    if result.points:
        result.status = ParetoStatus.FRONT
    elif result.complete:
        result.status = ParetoStatus.UNSAT
    result.points.sort(key=lambda p: p.values)
    result.timings["total"] = time.perf_counter() - start
    return result


class _Guided:
    """The guided improvement algorithm over one solver: any composition not dominated by a
    point found so far, then ever better ones until nothing dominates it."""

    def __init__(
        self, inst: ir.Instance, objectives: list[ir.Objective], k: int, sequential: bool, deadline: float | None
    ) -> None:
        self.k, self.deadline = k, deadline
        self.enc = enc = Encoder(inst, k, sequential=sequential)
        enc.unroll(k)
        texts = [enc.objective(o.term, k) for o in objectives]
        self.solver = open_backend(DEFAULT_BACKEND)
        self.solver.add(*enc.script.take())
        self.terms = [self.solver.intern(t) for t in texts]
        self.minimizing = [o.sense is ir.Sense.MINIMIZE for o in objectives]
        self.result = ParetoResult(ParetoStatus.UNKNOWN, objectives, horizon=k)

    def as_good(self, values: tuple[Fraction, ...]) -> App:
        """At least as good as ``values`` in every objective."""
        return and_(*[better(t, v, m, strict=False) for t, v, m in zip(self.terms, values, self.minimizing)])

    def improving(self, values: tuple[Fraction, ...]) -> App:
        """Strictly better than ``values`` in some objective."""
        return or_(*[better(t, v, m) for t, v, m in zip(self.terms, values, self.minimizing)])

    def check(self) -> Check:
        if self.deadline is not None:
            self.solver.set_timeout(max(0.001, self.deadline - time.perf_counter()))
        self.result.checks += 1
        return self.solver.check()

    def values_now(self) -> tuple[Fraction, ...]:
        out = []
        for t in self.terms:
            v = self.solver.value(t)
            assert not isinstance(v, bool)
            out.append(v)
        return tuple(out)

    def next_point(self) -> tuple[tuple[Fraction, ...], Plan] | None:
        """The next Pareto-optimal point and its composition; None when the front is done
        (or, with ``result.complete`` false, when the solver gave up)."""
        r = self.check()
        if r is not Check.SAT:
            self.result.complete = r is Check.UNSAT
            return None
        values, plan = self.values_now(), read_plan(self.solver, self.enc, self.k)
        while True:  # improve until nothing dominates it
            self.solver.push()
            self.solver.assert_term(self.as_good(values))  # a point that dominates this one
            self.solver.assert_term(self.improving(values))
            r = self.check()
            if r is Check.SAT:
                values, plan = self.values_now(), read_plan(self.solver, self.enc, self.k)
                self.solver.pop()
                continue
            self.solver.pop()
            if r is Check.UNKNOWN:
                self.result.complete = False
                return None
            return values, plan


def dominates(a: tuple, b: tuple, objectives: list[ir.Objective]) -> bool:
    """a is at least as good as b everywhere and strictly better somewhere."""
    at_least, strictly = True, False
    for x, y, o in zip(a, b, objectives):
        good, strict = (x <= y, x < y) if o.sense is ir.Sense.MINIMIZE else (x >= y, x > y)
        at_least &= good
        strictly |= strict
    return at_least and strictly


# ====================================================================== output


def objective_labels(objectives: list[ir.Objective]) -> list[str]:
    return [f"{o.sense.value} {to_text(o.term)}" for o in objectives]


def pareto_json(inst: ir.Instance, result: ParetoResult) -> dict:
    return {
        "schema": "catc.pareto/1",
        "status": result.status.value,
        "complete": result.complete,
        "objectives": [{"sense": o.sense.value, "term": to_text(o.term)} for o in result.objectives],
        "points": [
            {
                "values": [value_to_json(v) for v in p.values],
                "decimals": [decimal_text(v) for v in p.values],
                "components": sorted(p.plan.components),
                "steps": steps_json(inst, p.plan, kinds=False),
            }
            for p in result.points
        ],
        "timings": timings_json(result.timings),
    }


def render(console: Console, inst: ir.Instance, result: ParetoResult, options: Mapping[str, Any] | None = None) -> None:
    if result.status is ParetoStatus.UNSAT:
        console.print(f"UNSAT  no composition within {result.horizon} steps")
        return
    labels = objective_labels(result.objectives)
    done = "complete" if result.complete else "incomplete: stopped by --max-points or --timeout"
    console.print(
        f"FRONT  {len(result.points)} non-dominated compositions ({done}) for problem "
        f"{inst.problem.name} of domain {inst.domain.name}"
    )
    table = Table("#", *labels, "components", right=tuple(range(len(labels) + 1)))
    for n, p in enumerate(result.points, 1):
        table.add_row(str(n), *[show_value(v) for v in p.values], " ".join(sorted(p.plan.components)))
    console.print(table)
    if result.points:
        console.print()
        console.print(ascii_plot([p.values for p in result.points], labels))


def check(inst: ir.Instance, options: Mapping[str, Any]) -> str | None:
    objectives = options.get("objectives")
    if objectives is None:
        metric = inst.problem.metric
        objectives = list(metric.objectives) if metric is not None else []
    if len(objectives) < 2:
        return "a Pareto front needs at least two objectives: use (:metric pareto ...) or --minimize/--maximize"
    return None


def plot_artifact(inst: ir.Instance, result: ParetoResult, options: Mapping[str, Any]) -> list[str]:
    """--plot FILE: the front drawn to PNG or SVG (the 'plots' extra)."""
    path = options.get("plot_path")
    if not path or not result.points:
        return []
    try:
        draw_front([p.values for p in result.points], objective_labels(result.objectives), path)
    except RuntimeError as exc:
        raise InputError(str(exc), code=codes.MISSING_EXTRA) from exc
    return [f"plot written to {path}"]


QUERY = Query(
    "pareto",
    summary="Every non-dominated composition for two or more objectives.",
    description=(
        "Objectives come from the problem's (:metric pareto ...) or from --minimize/--maximize. "
        "Exit 0 with a front, 1 infeasible, 2 input error, 3 stopped before the front was complete."
    ),
    options=(
        objectives_option(
            "An objective to minimise (repeatable; replaces the metric).",
            "An objective to maximise (repeatable).",
        ),
        Option(
            "max_points",
            ("--max-points",),
            Kind.POSITIVE,
            "Stop after this many points.",
            default=100,
            show_default=True,
        ),
        timeout_option("Stop after this many seconds; the points found so far are reported (exit 3)."),
        Option(
            "plot_path",
            ("--plot",),
            Kind.OUTPUT_FILE,
            "Draw the front (first two objectives; a third as colour) to FILE.png or FILE.svg (needs the 'plots' "
            "extra).",
            use=Use.OUTPUT,
        ),
        json_option("catc.pareto/1"),
    ),
    run=pareto,
    to_json=pareto_json,
    render=render,
    check=check,
    artifacts=plot_artifact,
)
