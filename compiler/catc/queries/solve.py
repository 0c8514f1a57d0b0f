"""Composition synthesis: find the shortest composition within the horizon.

Strategy (chosen by measurement, docs/benchmarks.md): *incremental deepening* on one
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

from catc import ir
from catc.semantics.compositions import canonical_fresh, checked, prune_plan
from catc.semantics.horizon import default_horizon, use_bound
from catc.semantics.plan import Plan
from catc.smt.backend import DEFAULT_BACKEND, Check, open_backend
from catc.smt.encoder import Encoder
from catc.smt.readback import read_plan


class Status(str, Enum):
    SAT = "sat"
    UNSAT = "unsat"
    UNKNOWN = "unknown"


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
    backend: str = DEFAULT_BACKEND,
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
    solver = open_backend(backend)
    t2 = time.perf_counter()
    solver.add(*enc.script.take())
    timings["start"] = t2 - t1
    timings["encode"] += (t1 - t0) + (time.perf_counter() - t2)

    tried = 0
    result: SolveResult | None = None

    def timed_check(extra: list[str]) -> Check:
        """Check the goal (and use limits) at the current horizon, in a scope the caller pops."""
        nonlocal tried
        if deadline is not None:  # an exhausted budget still checks (push/pop stay paired)
            solver.set_timeout(max(0.001, deadline - time.perf_counter()))
        t2 = time.perf_counter()
        solver.push()
        solver.add((), [(None, c) for c in extra])
        r = solver.check()
        timings["solve"] += time.perf_counter() - t2
        tried += 1
        return r

    def grow(t: int) -> list[str]:
        t1 = time.perf_counter()
        while len(enc.act) < t:
            enc.add_step()
        solver.add(*enc.script.take())
        extra = [c for _, c in enc.goal_constraints(t)] + [c for _, c in enc.uses_constraints(t)]
        timings["encode"] += time.perf_counter() - t1
        return extra

    def unknown() -> SolveResult:
        reason = solver.reason_unknown()
        if deadline is not None and time.perf_counter() >= deadline:
            reason = "timeout"
        return SolveResult(Status.UNKNOWN, k, reason=reason, length_bound=bound)

    if strategy == "incremental":
        for t in range(k + 1):
            extra = grow(t)
            if progress is not None:
                progress(t, k, time.perf_counter() - start)
            r = timed_check(extra)
            if r is Check.SAT:
                result = SolveResult(Status.SAT, k, read_plan(solver, enc, t), length_bound=bound)
            elif r is Check.UNKNOWN:
                result = unknown()
            solver.pop()
            if result is not None:
                break
    elif strategy == "single":
        extra = grow(k)
        if progress is not None:
            progress(k, k, time.perf_counter() - start)
        r = timed_check(extra)
        if r is Check.SAT:
            result = SolveResult(Status.SAT, k, read_plan(solver, enc, k), length_bound=bound)
        elif r is Check.UNKNOWN:
            result = unknown()
        solver.pop()
    else:
        raise ValueError(f"unknown strategy {strategy!r}; expected 'incremental' or 'single'")
    if result is None:  # UNSAT at every horizon up to k
        final = bound is not None and k >= bound
        result = SolveResult(Status.UNSAT, k, final=final, length_bound=bound)
    result.horizons_tried = tried
    result.sequential, result.strategy = sequential, strategy
    if result.status is Status.SAT and validate_answer:
        t2 = time.perf_counter()
        checked(inst, result.plan, k, sequential, "the solver's composition")
        plan = prune_plan(inst, result.plan, k, sequential) if prune else result.plan
        result.plan = canonical_fresh(plan)
        result.states = checked(inst, result.plan, k, sequential, "the pruned composition")
        timings["validate"] = time.perf_counter() - t2
    timings["total"] = time.perf_counter() - start
    result.timings = timings
    return result
