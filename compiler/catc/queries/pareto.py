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
from fractions import Fraction
from typing import Any, NamedTuple

from catc import ir
from catc.ir.numbers import decimal_text
from catc.ir.text import to_text
from catc.present.console import Console, Table, counted
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
    certificate_option,
    json_option,
    objectives_option,
    timeout_option,
)
from catc.semantics.compositions import canonical_fresh
from catc.semantics.horizon import horizon_of
from catc.semantics.plan import Plan, value_to_json
from catc.semantics.validate import ValidationFailure, objective_value, validate
from catc.smt.backend import DEFAULT_BACKEND, Check, open_backend
from catc.smt.encoder import Encoder
from catc.smt.readback import read_plan
from catc.smt.terms import App, and_, better, or_
from catgrammar import codes, limits


class ParetoPoint(NamedTuple):  # (not a dataclass: `catc pareto` does not import dataclasses)
    values: tuple[Fraction, ...]
    plan: Plan
    states: tuple = ()
    #: False for a supremum (maximising) or infimum (minimising) that no composition
    #: reaches: ``values`` are the solver's bounds, ``plan`` a composition close to them
    attained: bool = True


class ParetoStatus(Status):
    FRONT = "front", ExitCode.OK
    UNSAT = "unsat", ExitCode.FAIL
    UNKNOWN = "unknown", ExitCode.UNKNOWN


class ParetoResult(Result):
    """The answer of :func:`pareto`; filled in as the front is found."""

    query = "pareto"
    __slots__ = ("status", "objectives", "points", "complete", "horizon", "checks", "timings", "reason")
    status: ParetoStatus

    def __init__(
        self,
        status: ParetoStatus,
        objectives: list[ir.Objective],
        points: list[ParetoPoint] | None = None,
        complete: bool = True,
        horizon: int = 0,
        checks: int = 0,
        timings: dict[str, float] | None = None,
        #: why the front is incomplete: "max-points", "timeout", "interrupted", "unbounded" or
        #: the solver's reason; None when complete
        reason: str | None = None,
    ) -> None:
        self.status, self.objectives = status, objectives
        self.points: list[ParetoPoint] = [] if points is None else points
        self.complete, self.horizon, self.checks = complete, horizon, checks
        self.timings: dict[str, float] = {} if timings is None else timings
        self.reason = reason

    def __repr__(self) -> str:
        fields = ", ".join(f"{name}={getattr(self, name)!r}" for name in self.__slots__)
        return f"ParetoResult({fields})"

    @property
    def settled(self) -> bool:
        return self.complete


#: Improvements of one point by plain checks before the optimiser is asked for the best point
#: that dominates it: a front point that is a supremum no composition reaches would otherwise
#: be approached for ever (every composition near it is dominated by a nearer one).
CLIMBS = 24


#: What the command is doing while it finds points (a time-limit message names it).
PHASE = "finding Pareto points"


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
    with limits.deadline(timeout):
        k = horizon_of(inst, horizon)
        result = ParetoResult(ParetoStatus.UNKNOWN, objectives, horizon=k)
        try:
            _front(inst, objectives, k, sequential, max_points, result, start)
        except limits.Stopped as stop:  # encoding or validating when the time ran out
            result.complete, result.reason = False, stop.reason
    if result.points:
        result.status = ParetoStatus.FRONT
    elif result.complete:
        result.status = ParetoStatus.UNSAT
    result.points.sort(key=lambda p: p.values)
    result.timings["total"] = time.perf_counter() - start
    return result


def _front(
    inst: ir.Instance,
    objectives: list[ir.Objective],
    k: int,
    sequential: bool,
    max_points: int,
    result: ParetoResult,
    start: float,
) -> None:
    """Fill ``result`` with front points until the front is complete, ``max_points``, the
    time limit or an interruption."""
    search = _Guided(inst, objectives, k, sequential, result)
    result.timings["encode"] = time.perf_counter() - start
    while len(result.points) < max_points:
        # Ctrl-C or the time limit between two points: a solver given the 1 ms left may
        # still answer an easy check, and the front would run on (issue 28)
        limits.check_time(PHASE)
        found = search.next_point()
        if found is None:
            return
        report = validate(inst, found.plan, horizon=k, sequential=sequential)
        if not report.ok:
            raise ValidationFailure(
                "the independent validator rejected a Pareto point: "
                + "; ".join(v.message for v in report.violations[:5])
            )
        recomputed = tuple(objective_value(inst, found.plan, o.term, report.states[-1]) for o in objectives)
        if found.attained and recomputed != found.values:
            raise ValidationFailure(f"Pareto point values {found.values} differ from the composition's {recomputed}")
        if not found.attained and not _approaches(recomputed, found.values, objectives):
            raise ValidationFailure(f"Pareto point {recomputed} lies beyond the solver's bound {found.values}")
        result.points.append(ParetoPoint(found.values, canonical_fresh(found.plan), report.states, found.attained))
        search.exclude(found.values)
    result.complete, result.reason = False, "max-points"


def _approaches(values: tuple, bound: tuple, objectives: list[ir.Objective]) -> bool:
    """Whether ``values`` are no better than ``bound`` in every objective."""
    return all((v >= b) if o.sense is ir.Sense.MINIMIZE else (v <= b) for v, b, o in zip(values, bound, objectives))


class _Guided:
    """The guided improvement algorithm over one solver: any composition not dominated by a
    point found so far, then ever better ones until nothing dominates it."""

    def __init__(
        self, inst: ir.Instance, objectives: list[ir.Objective], k: int, sequential: bool, result: ParetoResult
    ) -> None:
        self.inst, self.objectives, self.k, self.sequential = inst, objectives, k, sequential
        self.enc = enc = Encoder(inst, k, sequential=sequential)
        enc.unroll(k)
        texts = [enc.objective(o.term, k) for o in objectives]
        self.solver = open_backend(DEFAULT_BACKEND)
        self.solver.add(*enc.script.take())
        self.terms = [self.solver.intern(t) for t in texts]
        self.minimizing = [o.sense is ir.Sense.MINIMIZE for o in objectives]
        self.result = result
        self.found: list[tuple[Fraction, ...]] = []  # the points so far, each excluded from then on

    def as_good(self, values: tuple[Fraction, ...], terms: list[Any] | None = None) -> App:
        """At least as good as ``values`` in every objective."""
        terms = self.terms if terms is None else terms
        return and_(*[better(t, v, m, strict=False) for t, v, m in zip(terms, values, self.minimizing)])

    def improving(self, values: tuple[Fraction, ...], terms: list[Any] | None = None) -> App:
        """Strictly better than ``values`` in some objective."""
        terms = self.terms if terms is None else terms
        return or_(*[better(t, v, m) for t, v, m in zip(terms, values, self.minimizing)])

    def exclude(self, values: tuple[Fraction, ...]) -> None:
        """Every later answer must be strictly better than this point in some objective."""
        self.found.append(values)
        self.solver.assert_term(self.improving(values))

    def check(self) -> Check:
        self.solver.set_timeout(limits.for_check())  # None: no limit, not a stale one
        self.result.checks += 1
        return self.solver.check()

    def values_now(self) -> tuple[Fraction, ...]:
        out = []
        for t in self.terms:
            v = self.solver.value(t)
            assert not isinstance(v, bool)
            out.append(v)
        return tuple(out)

    def stop(self, r: Check) -> None:
        """The front ends here: complete after UNSAT, else incomplete, and why."""
        self.result.complete = r is Check.UNSAT
        if r is not Check.UNSAT:
            self.result.reason = limits.stop_reason() or self.solver.reason_unknown()

    def next_point(self) -> _Found | None:
        """The next Pareto-optimal point and its composition; None when the front is done
        (or, with ``result.complete`` false, when the solver gave up)."""
        r = self.check()
        if r is not Check.SAT:
            self.stop(r)
            return None
        values, plan = self.values_now(), read_plan(self.solver, self.enc, self.k)
        for _ in range(CLIMBS):  # improve until nothing dominates it
            limits.check_time(PHASE)
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
                self.stop(r)
                return None
            return _Found(values, plan)
        return self.best_dominating(values)

    def best_dominating(self, values: tuple[Fraction, ...]) -> _Found | None:
        """After :data:`CLIMBS` improvements: the lexicographic optimum among the compositions
        at least as good as ``values`` (and not excluded), which is Pareto-optimal — or, when
        the optimiser reports a bound no composition attains, that supremum or infimum."""
        enc = Encoder(self.inst, self.k, sequential=self.sequential)
        enc.unroll(self.k)
        texts = [enc.objective(o.term, self.k) for o in self.objectives]
        opt = open_backend(DEFAULT_BACKEND, optimize=True)
        opt.add(*enc.script.take())
        terms = [opt.intern(t) for t in texts]
        for point in self.found:
            opt.assert_term(self.improving(point, terms))
        opt.assert_term(self.as_good(values, terms))
        handles = [opt.minimize(t) if m else opt.maximize(t) for t, m in zip(terms, self.minimizing)]
        opt.set_timeout(limits.for_check())  # None: no limit, not a stale one
        self.result.checks += 1
        r = opt.check()
        bounds = [opt.bound(h) for h in handles] if r is Check.SAT else []
        if r is not Check.SAT or any(b.infinite for b in bounds):
            self.result.complete = False
            self.result.reason = "unbounded" if bounds else limits.stop_reason() or opt.reason_unknown()
            return None
        plan = read_plan(opt, enc, self.k)
        if all(b.exact for b in bounds):
            return _Found(tuple(opt.value(t) for t in terms), plan)  # type: ignore[misc]
        return _Found(tuple(b.value for b in bounds), plan, attained=False)


class _Found(NamedTuple):
    values: tuple[Fraction, ...]
    plan: Plan
    attained: bool = True


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
    doc = {
        "schema": "catc.pareto/1",
        "status": result.status.value,
        "complete": result.complete,
        "objectives": [{"sense": o.sense.value, "term": to_text(o.term)} for o in result.objectives],
        "points": [_point_json(inst, p) for p in result.points],
        "timings": timings_json(result.timings),
    }
    if result.reason is not None:  # why the front is incomplete
        doc["reason"] = result.reason
    return doc


def _point_json(inst: ir.Instance, p: ParetoPoint) -> dict:
    doc: dict[str, Any] = {
        "values": [value_to_json(v) for v in p.values],
        "decimals": [decimal_text(v) for v in p.values],
        "components": sorted(p.plan.components),
        "steps": steps_json(inst, p.plan, kinds=False),
    }
    if not p.attained:  # a supremum or infimum: the composition only comes close
        doc["attained"] = False
    return doc


def render(console: Console, inst: ir.Instance, result: ParetoResult, options: Mapping[str, Any] | None = None) -> None:
    if result.status is ParetoStatus.UNSAT:
        console.print(f"UNSAT  no composition within {counted(result.horizon, 'step')}")
        return
    labels = objective_labels(result.objectives)
    done = "complete" if result.complete else f"incomplete: {_STOPPED.get(result.reason or '', result.reason)}"
    if not result.points and not result.complete:
        console.print(f"UNKNOWN  no front point found ({done})")
        return
    console.print(
        f"FRONT  {counted(len(result.points), 'non-dominated composition')} ({done}) for problem "
        f"{inst.problem.name} of domain {inst.domain.name}"
    )
    table = Table("#", *labels, "components", right=tuple(range(len(labels) + 1)))
    for n, p in enumerate(result.points, 1):
        table.add_row(str(n), *[show_value(v) for v in p.values], " ".join(sorted(p.plan.components)))
    console.print(table)
    for n, p in enumerate(result.points, 1):
        if not p.attained:
            console.print(
                f"point {n} is not attained: compositions approach these values (a supremum where maximising, an "
                f"infimum where minimising) but none reaches them; the composition shown comes close "
                f"({', '.join(show_value(v) for v in _values_of(inst, p, result.objectives))})"
            )
    if result.points:
        console.print()
        console.print(ascii_plot([p.values for p in result.points], labels))


_STOPPED = {
    "max-points": "stopped by --max-points",
    "timeout": "stopped by the time limit",
    "interrupted": "interrupted",
    "unbounded": "an objective is unbounded",
}


def _values_of(inst: ir.Instance, p: ParetoPoint, objectives: list[ir.Objective]) -> list[Any]:
    """The objective values of the composition of ``p`` (in its final state)."""
    return [objective_value(inst, p.plan, o.term, p.states[-1]) for o in objectives]


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
        certificate_option(),
    ),
    run=pareto,
    to_json=pareto_json,
    render=render,
    check=check,
    artifacts=plot_artifact,
)
