"""Composition synthesis: find the shortest composition within the horizon.

Strategy (chosen by measurement, docs/benchmarks.md): *incremental deepening* on one Z3
solver — the encoding grows one step at a time and the goal is checked at each new state
inside a push/pop scope, so the first SAT answer is a shortest composition and the solver
keeps what it learnt from the shorter horizons.  ``strategy="single"`` encodes the whole
horizon with idle steps and checks once: any composition, not necessarily a shortest one,
but one check settles an infeasible problem, which is faster when most answers are UNSAT.

Every SAT answer is replayed by the independent validator (:mod:`catc.semantics.validate`) before it
is returned; a rejected answer is an internal error, never shown as a composition.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from enum import Enum

import z3

from catc import ir
from catc.semantics.plan import Activation, Plan
from catc.smt.encoder import Encoder
from catc.smt.z3backend import Z3Session

DEFAULT_HORIZON = 10


class Status(str, Enum):
    SAT = "sat"
    UNSAT = "unsat"
    UNKNOWN = "unknown"


class ValidationFailure(RuntimeError):
    """The solver's answer did not survive independent validation (a bug in catc)."""


class SolveResult:
    """The answer of :func:`solve`; filled in as the search goes."""

    __slots__ = (
        "status",
        "horizon",
        "plan",
        "states",
        "final",
        "length_bound",
        "reason",
        "timings",
        "horizons_tried",
        "sequential",
        "strategy",
    )

    def __init__(
        self,
        status: Status,
        horizon: int,
        plan: Plan | None = None,
        states: tuple = (),
        final: bool = False,  # UNSAT holds for every horizon (use limits bound the length)
        length_bound: int | None = None,  # Σ uses when every morphism is limited
        reason: str | None = None,  # why UNKNOWN
        timings: dict[str, float] | None = None,
        horizons_tried: int = 0,
        sequential: bool = False,  # how it was solved (echoed by catc.solve/1)
        strategy: str = "incremental",
    ) -> None:
        self.status = status
        self.horizon = horizon
        self.plan = plan
        self.states = states
        self.final = final
        self.length_bound = length_bound
        self.reason = reason
        self.timings: dict[str, float] = {} if timings is None else timings
        self.horizons_tried = horizons_tried
        self.sequential = sequential
        self.strategy = strategy

    def __repr__(self) -> str:
        return f"SolveResult({self.status.name}, horizon={self.horizon}, plan={self.plan!r})"


def use_bound(inst: ir.Instance) -> int | None:
    """Σ uses over all morphisms, or None when some morphism is unlimited.  No composition
    has more non-idle steps than this."""
    total = 0
    for m in inst.morphisms.values():
        if m.uses is None:
            return None
        total += m.uses
    return total


def prune_plan(inst: ir.Instance, plan: Plan, horizon: int, sequential: bool, accept=None) -> Plan:
    """Drop activations the composition does not need.

    The solver's model may switch on harmless extra morphisms (a step of length 0, a spare
    driver); each activation, last first, is removed when the validator still accepts the
    composition without it (and ``accept(candidate)`` agrees — optimisation passes a check
    that no objective gets worse), and emptied steps disappear.  The result is valid, no
    longer than the input, and irredundant: removing any single activation breaks it."""
    from catc.semantics.validate import validate

    steps = [list(s) for s in plan.steps]
    changed = True
    while changed:
        changed = False
        for i in range(len(steps) - 1, -1, -1):
            for j in range(len(steps[i]) - 1, -1, -1):
                trial = [list(s) for s in steps]
                del trial[i][j]
                candidate = Plan(tuple(tuple(s) for s in trial if s), plan.fresh)
                if validate(inst, candidate, horizon=horizon, sequential=sequential).ok and (
                    accept is None or accept(candidate)
                ):
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
    from catc.smt.grounding import fresh_name

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


def default_horizon(inst: ir.Instance) -> int:
    if inst.problem.horizon is not None:
        return inst.problem.horizon
    bound = use_bound(inst)
    return bound if bound is not None else DEFAULT_HORIZON


def solve(
    inst: ir.Instance,
    *,
    horizon: int | None = None,
    sequential: bool = False,
    timeout: float | None = None,
    progress: Callable[[int, int, float], None] | None = None,
    strategy: str = "incremental",
    validate_answer: bool = True,
    prune: bool = True,
) -> SolveResult:
    """``progress(t, k, elapsed)`` is called before each horizon is tried."""
    k = default_horizon(inst) if horizon is None else horizon
    start = time.perf_counter()
    deadline = start + timeout if timeout else None
    bound = use_bound(inst)
    # start: creating the Z3 context and solver (the first context of a process initialises
    # Z3, ~10 ms; a hand-written Z3 script pays it too)
    timings = {"start": 0.0, "encode": 0.0, "solve": 0.0, "validate": 0.0}

    t0 = time.perf_counter()
    enc = Encoder(inst, k, sequential=sequential)
    t1 = time.perf_counter()
    session = Z3Session(enc)
    t2 = time.perf_counter()
    session.flush()
    timings["start"] = t2 - t1
    timings["encode"] += (t1 - t0) + (time.perf_counter() - t2)

    tried = 0
    result: SolveResult | None = None

    def timed_check(extra: list[str]) -> z3.CheckSatResult:
        nonlocal tried
        if deadline is not None:  # an exhausted budget still checks (push/pop stay paired)
            session.set_timeout(max(0.001, deadline - time.perf_counter()))
        t2 = time.perf_counter()
        r = session.check(extra)
        timings["solve"] += time.perf_counter() - t2
        tried += 1
        return r

    def grow(t: int) -> list[str]:
        t1 = time.perf_counter()
        while len(enc.act) < t:
            enc.add_step()
        session.flush()
        extra = [c for _, c in enc.goal_constraints(t)] + [c for _, c in enc.uses_constraints(t)]
        timings["encode"] += time.perf_counter() - t1
        return extra

    def unknown() -> SolveResult:
        reason = session.reason_unknown()
        if deadline is not None and time.perf_counter() >= deadline:
            reason = "timeout"
        return SolveResult(Status.UNKNOWN, k, reason=reason, length_bound=bound)

    if strategy == "incremental":
        for t in range(k + 1):
            extra = grow(t)
            if progress is not None:
                progress(t, k, time.perf_counter() - start)
            r = timed_check(extra)
            if r == z3.sat:
                result = SolveResult(Status.SAT, k, session.extract(t), length_bound=bound)
            elif r == z3.unknown:
                result = unknown()
            session.pop()
            if result is not None:
                break
    elif strategy == "single":
        extra = grow(k)
        if progress is not None:
            progress(k, k, time.perf_counter() - start)
        r = timed_check(extra)
        if r == z3.sat:
            result = SolveResult(Status.SAT, k, session.extract(k), length_bound=bound)
        elif r == z3.unknown:
            result = unknown()
        session.pop()
    else:
        raise ValueError(f"unknown strategy {strategy!r}; expected 'incremental' or 'single'")
    if result is None:  # UNSAT at every horizon up to k
        final = bound is not None and k >= bound
        result = SolveResult(Status.UNSAT, k, final=final, length_bound=bound)
    result.horizons_tried = tried
    result.sequential, result.strategy = sequential, strategy
    if result.status is Status.SAT and validate_answer:
        from catc.semantics.validate import validate

        t2 = time.perf_counter()
        report = validate(inst, result.plan, horizon=k, sequential=sequential)
        if not report.ok:
            problems = "; ".join(v.message for v in report.violations[:5])
            raise ValidationFailure(f"the independent validator rejected the solver's composition: {problems}")
        plan = prune_plan(inst, result.plan, k, sequential) if prune else result.plan
        result.plan = canonical_fresh(plan)
        report = validate(inst, result.plan, horizon=k, sequential=sequential)
        if not report.ok:  # pragma: no cover - pruning and renaming keep validity
            raise ValidationFailure("pruning broke the composition: " + report.violations[0].message)
        timings["validate"] = time.perf_counter() - t2
        result.states = report.states
    timings["total"] = time.perf_counter() - start
    result.timings = timings
    return result
