"""The search for the optimum of ``catc optimize`` (paper eq. optimization), lexicographic by
priority; :mod:`catc.queries.optimize` is the query (options, JSON, rendering).

One encoding of the whole horizon (idle steps allowed) goes to an optimising backend (Z3's
``Optimize``).  The first
objective carries the soft-constraint penalties ``Σ wᵢ·zᵢ`` (``zᵢ`` = soft constraint ``i``
violated in the final state; added when minimising, subtracted when maximising); further
objectives break ties in order.  The answer's composition is replayed by the independent
validator, which also recomputes every objective value exactly; the value reported is the
validator's, and it must equal the solver's (else: internal error).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from fractions import Fraction
from typing import Any, NamedTuple

from catc import ir
from catc.ir.numbers import number_text, ratio_text
from catc.queries.base import ExitCode, Progress, Result, Status
from catc.queries.churn_search import churn_floor_refutes, tightened
from catc.queries.solve import SolveStatus, solve
from catc.semantics.compositions import canonical_fresh, drop_idle_steps, prune_plan
from catc.semantics.horizon import horizon_of
from catc.semantics.plan import Plan
from catc.semantics.validate import ValidationFailure, evaluate, objective_value, validate
from catc.smt.backend import DEFAULT_BACKEND, Backend, Bound, Check, kept_mark, open_backend, release_kept
from catc.smt.counting import better_refuted
from catc.smt.encoder import Encoder
from catc.smt.readback import read_plan
from catc.smt.terms import Term, and_, better, eq, ite, minus, not_, or_, plus
from catc.smt.terms import to_text as smt_text
from catgrammar import limits


class OptStatus(Status):
    OPT = "opt", ExitCode.OK  # proven optimal
    SUBOPT = "subopt", ExitCode.UNKNOWN  # best found before the time limit
    UNSAT = "unsat", ExitCode.FAIL
    UNKNOWN = "unknown", ExitCode.UNKNOWN
    UNBOUNDED = "unbounded", ExitCode.FAIL


class ObjectiveValue:
    # a plain class, not a dataclass: importing dataclasses costs every `catc optimize` ~6 ms
    __slots__ = ("objective", "value", "attained", "bound")

    def __init__(
        self,
        objective: ir.Objective,
        value: Fraction | None,  # exact, recomputed by the validator (with penalties for the first)
        attained: bool = True,  # False when the solver reports a supremum/infimum not reached
        bound: str | None = None,  # the solver's bound when not attained or unbounded
    ) -> None:
        self.objective, self.value, self.attained, self.bound = objective, value, attained, bound

    def __repr__(self) -> str:
        return f"ObjectiveValue({self.objective!r}, {self.value!r}, attained={self.attained}, bound={self.bound!r})"


class SoftOutcome:
    __slots__ = ("soft", "violated")

    def __init__(self, soft: ir.Soft, violated: bool) -> None:
        self.soft, self.violated = soft, violated

    def __repr__(self) -> str:
        return f"SoftOutcome({self.soft!r}, violated={self.violated})"


class OptResult(Result):
    query = "optimize"
    __slots__ = ("status", "horizon", "plan", "states", "values", "softs", "reason", "timings")
    status: OptStatus

    def __init__(
        self,
        status: OptStatus,
        horizon: int,
        plan: Plan | None = None,
        states: tuple = (),
        values: list[ObjectiveValue] | None = None,
        softs: list[SoftOutcome] | None = None,
        reason: str | None = None,
        timings: dict[str, float] | None = None,
    ) -> None:
        self.status, self.horizon, self.plan, self.states = status, horizon, plan, states
        self.values: list[ObjectiveValue] = [] if values is None else values
        self.softs: list[SoftOutcome] = [] if softs is None else softs
        self.reason = reason
        self.timings: dict[str, float] = {} if timings is None else timings

    def __repr__(self) -> str:
        return f"OptResult({self.status.name}, horizon={self.horizon}, plan={self.plan!r}, values={self.values!r})"


#: Horizons shorter than this are optimised with the single encoding even under ``deepen``:
#: on the examples with 2–6 steps it costs 1.0–1.3× plain solve, the deepening route
#: 1.2–2.2× (its extra encodings dominate such small problems; docs/benchmarks.md).
DEEPEN_FROM = 8


class Tactics(NamedTuple):
    """How :func:`optimize` looks for the optimum (arguments, not process-wide switches).

    ``maxsmt_churn``: churn objectives as soft-constraint groups for Z3's MaxSMT engine
    instead of arithmetic sums (docs/benchmarks.md compares the two).  ``counting_proofs``:
    try the counting relaxation's proof that nothing is better (:mod:`catc.smt.counting`)
    before the SMT refutation; off, only the SMT refutation (lifelong_bench.py's "before")."""

    maxsmt_churn: bool = False
    counting_proofs: bool = True


#: The default tactics.
DEFAULT_TACTICS = Tactics()

STRATEGIES = ("deepen", "single")


def objectives_of(inst: ir.Instance) -> list[ir.Objective]:
    metric = inst.problem.metric
    if metric is not None:
        return list(metric.objectives)
    return []


def optimize(
    inst: ir.Instance,
    objectives: list[ir.Objective] | None = None,
    *,
    horizon: int | None = None,
    sequential: bool = False,
    timeout: float | None = None,
    prune: bool = True,
    strategy: str = "deepen",
    deepen_from: int | None = None,
    progress: Progress | None = None,
    tactics: Tactics = DEFAULT_TACTICS,
    known: Sequence[Plan] = (),
) -> OptResult:
    """The optimum over every composition of at most ``horizon`` steps.

    ``strategy="single"`` hands one encoding of the whole horizon to the optimiser.
    ``strategy="deepen"`` (default) finds the shortest feasible horizon k₀ by incremental
    deepening (as ``catc solve``), optimises over k₀ steps, and then proves the value optimal
    over the whole horizon with one satisfiability check — "is there a composition of at
    most ``horizon`` steps that is lexicographically better?"; only when there is does it
    optimise over the whole horizon.  The refutation and the optimisation over the whole
    horizon alternate with doubling time budgets, as neither is always faster.  Both
    strategies give the same optimum.  Below ``deepen_from`` steps of horizon (default
    :data:`DEEPEN_FROM`) ``deepen`` uses the single encoding, which is then as cheap.
    ``progress(message)`` is told what is being tried as it starts; ``tactics`` chooses
    encodings and proofs (:class:`Tactics`).  ``known``: compositions the caller already has
    (recompose: the deployed one); when the validator accepts one and it is better than the
    first composition found, ``deepen`` skips the refutation that could only fail — the
    answer is the same, as that refutation's failure leads to the very next step either way."""
    say = progress or (lambda message: None)
    objectives = objectives_of(inst) if objectives is None else objectives
    softs = list(inst.problem.softs)
    if not objectives and softs:
        objectives = [ir.Objective(ir.Sense.MINIMIZE, ir.Const(Fraction(0), ir.REAL))]
    if not objectives:
        raise ValueError("nothing to optimise: the problem has no (:metric ...) and no soft constraints")
    if strategy not in STRATEGIES:
        raise ValueError(f"unknown strategy {strategy!r}; expected 'deepen' or 'single'")
    start = time.perf_counter()
    with limits.deadline(timeout):
        k = horizon_of(inst, horizon)
        try:
            if strategy == "single" or k < (DEEPEN_FROM if deepen_from is None else deepen_from):
                say(f"optimising over {k} steps")
                at = _optimize_at(inst, objectives, softs, k, sequential, limits.deadline_at(), prune, tactics)
                return _done(at, start)
            deepening = _Deepening(inst, objectives, softs, k, sequential, prune, say, tactics, known)
            return _done(deepening.run(), start)
        except limits.Stopped as stop:  # encoding or validating when the time ran out
            return _done(OptResult(OptStatus.UNKNOWN, k, reason=stop.reason), start)


class _Deepening:
    """``strategy="deepen"``: the first composition, the optimum over its length k₀, and the
    proof that nothing longer (up to the horizon) is better."""

    def __init__(
        self,
        inst: ir.Instance,
        objectives: list[ir.Objective],
        softs: list[ir.Soft],
        k: int,
        sequential: bool,
        prune: bool,
        say: Progress,
        tactics: Tactics,
        known: Sequence[Plan] = (),
    ) -> None:
        self.inst, self.objectives, self.softs, self.k = inst, objectives, softs, k
        self.sequential, self.prune, self.say, self.tactics = sequential, prune, say, tactics
        self.known = known
        self.start = time.perf_counter()
        self.deadline = limits.deadline_at()
        self.timings: dict[str, float] = {}
        self.values0: list[Fraction | None] | None = None  # the first composition's values
        self.short: OptResult | None = None  # the optimum over the first composition's length
        # the optimiser of that optimum, whose Z3 context the race's proofs share (its answer is
        # read by then: a proof's terms in its context change no composition; one context less)
        self.solvers: list[Backend] = []

    def run(self) -> OptResult:
        inst, k = self.inst, self.k
        mark = kept_mark()
        first = solve(
            inst,
            horizon=k,
            sequential=self.sequential,
            validate_answer=False,
            prune=False,
            progress=self.say,
            phase="looking for a first composition",
        )
        release_kept(mark)  # its solver is done with: the optimiser's context reuses its memory
        self.timings = {"encode": first.timings["encode"], "solve": first.timings["solve"], "validate": 0.0}
        if first.status is SolveStatus.UNSAT:
            return OptResult(OptStatus.UNSAT, k, timings=self.timings)
        if first.status is not SolveStatus.SAT or first.plan is None:
            return OptResult(OptStatus.UNKNOWN, k, reason=first.reason, timings=self.timings)
        self.first = first.plan
        report0 = validate(inst, first.plan, horizon=k, sequential=self.sequential)
        if not report0.ok:
            raise ValidationFailure("the independent validator rejected the solver's first composition")
        try:
            return self._improve(len(first.plan.steps), report0)
        except limits.Stopped as stop:  # encoding when the time ran out: the best so far
            if self.short is not None and self.short.plan is not None:
                self.short.status, self.short.reason, self.short.timings = OptStatus.SUBOPT, stop.reason, self.timings
                return self.short
            return self._first_plan(OptStatus.SUBOPT, stop.reason)

    def _improve(self, k0: int, report0: Any) -> OptResult:
        """From the first composition (of ``k0`` steps) to the optimum."""
        inst, k = self.inst, self.k
        if k0 < k and self._first_is_optimal(k0, report0):
            return self._first_plan(OptStatus.OPT)
        self.say(f"optimising over {k0} steps")
        expired = _expired(self.deadline)
        short = (
            None
            if expired
            else _optimize_at(inst, *self._args(k0), self.deadline, self.prune, self.tactics, self.solvers)
        )
        if short is None or (short.plan is None and _expired(self.deadline)):
            # out of time: the first composition is the best known
            return self._first_plan(OptStatus.SUBOPT, limits.stop_reason() or "timeout")
        _add_timings(self.timings, short.timings)
        short.horizon = k
        if short.plan is not None:
            self.short = short
        exact = (
            short.status is OptStatus.OPT
            and short.plan is not None
            and all(v.attained and v.value is not None for v in short.values)
        )
        if not exact:  # unattained or unbounded over k₀ steps, or out of time: optimise over everything
            if short.status is OptStatus.SUBOPT and _expired(self.deadline):
                short.timings = self.timings
                return short
            self.say(f"optimising over all {k} steps")
            whole = _optimize_at(inst, *self._args(k), self.deadline, self.prune, self.tactics)
            _add_timings(self.timings, whole.timings)
            whole.timings = self.timings
            return whole
        if k0 == k:
            short.timings = self.timings
            return self._same_answer(short)
        return self._race(short, k0)

    def _same_answer(self, best: OptResult) -> OptResult:
        """The answer, independent of which proof finished first: when the first composition
        is as good as the optimum, it (the solver's first answer is deterministic); else the
        optimum over the fewest steps.  Which optimal composition a timed race returns would
        otherwise depend on the machine's speed, and so would everything grounded from it."""
        values = [v.value for v in best.values]
        if self.values0 is not None and values == self.values0:
            return self._first_plan(OptStatus.OPT)
        return best

    def _args(self, k: int) -> tuple[list[ir.Objective], list[ir.Soft], int, bool]:
        return self.objectives, self.softs, k, self.sequential

    def _first_is_optimal(self, k0: int, report0: Any) -> bool:
        """Often the first composition found is already optimal: try to refute anything
        better within the whole horizon, on a budget as long as the time spent so far."""
        scores = _scores(self.inst, self.first, self.objectives, self.softs, self.k, self.sequential, report0)
        values0 = [v for v in scores if v is not None]
        if len(values0) != len(scores):
            return False
        self.values0 = scores
        self.say(f"first composition: {k0} steps; is there a better one within {self.k} steps?")
        if any(self._better_than(plan, values0) for plan in self.known):
            return False  # a better one is known: a refutation cannot succeed (and costs a solver)
        budget0 = max(0.25, time.perf_counter() - self.start)
        limit = _sooner(self.deadline, budget0)
        r = _better_exists(
            self.inst, self.objectives, self.softs, values0, self.k, self.sequential, limit, self.timings, self.tactics
        )
        return r is Check.UNSAT

    def _better_than(self, plan: Plan, values: list[Fraction]) -> bool:
        """Whether ``plan`` is a composition of at most ``k`` steps that the validator accepts
        and that is lexicographically better than ``values``."""
        if len(plan.steps) > self.k:
            return False
        report = validate(self.inst, plan, horizon=self.k, sequential=self.sequential)
        if not report.ok:
            return False
        scores = _scores(self.inst, plan, self.objectives, self.softs, self.k, self.sequential, report)
        return None not in scores and scores != values and _not_worse(scores, values, self.objectives)

    def _first_plan(self, status: OptStatus, reason: str | None = None) -> OptResult:
        """The first composition as the answer (no solver bound to compare its values with)."""
        t2 = time.perf_counter()
        result = OptResult(status, self.k, reason=reason, timings=self.timings)
        exact: list[tuple[str, object]] = [("exact", None)] * len(self.objectives)
        _finish(self.inst, result, self.first, self.objectives, self.softs, exact, self.k, self.sequential, self.prune)
        self.timings["validate"] += time.perf_counter() - t2
        return result

    def _race(self, short: OptResult, k0: int) -> OptResult:
        """Refute anything better over the whole horizon, or optimise over the whole horizon,
        whichever finishes first: the two alternate with doubling time budgets (neither is
        always the faster: see docs/benchmarks.md), so the cost stays within a small factor
        of the better of the two."""
        inst, k, deadline = self.inst, self.k, self.deadline
        values: list[Fraction] = [v.value for v in short.values]  # type: ignore[misc]
        budget = max(0.25, time.perf_counter() - self.start)
        refute = True
        while True:
            if refute:
                self.say(f"optimum over {k0} steps: {_values_text(values)}; is there a better one within {k} steps?")
                limit = _sooner(deadline, budget)
                r = _better_exists(
                    inst,
                    self.objectives,
                    self.softs,
                    values,
                    k,
                    self.sequential,
                    limit,
                    self.timings,
                    self.tactics,
                    share_with=self.solvers[0] if self.solvers else None,
                )
                if r is Check.UNSAT:  # nothing better within the whole horizon: the short optimum is it
                    short.timings = self.timings
                    return self._same_answer(short)
                if r is Check.SAT or not _expired(limit):  # something better, or no proof to be had here
                    refute = False
                budget *= 2
            if _expired(deadline):
                break
            limit = _sooner(deadline, None if not refute else budget)
            self.say(f"optimum over {k0} steps: {_values_text(values)}; optimising over all {k} steps")
            whole = _optimize_at(inst, *self._args(k), limit, self.prune, self.tactics)
            _add_timings(self.timings, whole.timings)
            if whole.reason not in _STOPPED:  # finished
                whole.timings = self.timings
                if whole.plan is not None and _not_worse(values, [v.value for v in whole.values], self.objectives):
                    short.timings = self.timings
                    return self._same_answer(short)  # no better than the short optimum: that one, always
                return whole
            if _expired(deadline):  # the best found wins if it is at least as good as the short optimum
                if whole.plan is not None and _not_worse([v.value for v in whole.values], values, self.objectives):
                    whole.timings = self.timings
                    return whole
                break
            budget *= 2
        short.status, short.reason, short.timings = OptStatus.SUBOPT, limits.stop_reason() or "timeout", self.timings
        return short


def _values_text(values: list[Fraction]) -> str:
    return ", ".join(ratio_text(v) for v in values)


def _sooner(deadline: float | None, budget: float | None) -> float | None:
    """The earlier of the deadline and ``budget`` seconds from now (None: no limit)."""
    if budget is None:
        return deadline
    mine = time.perf_counter() + budget
    return mine if deadline is None else min(deadline, mine)


def _expired(deadline: float | None) -> bool:
    """Interrupted, or past the deadline — with 50 ms of slack, as Z3's timer may stop a check
    a little early."""
    return limits.interrupted() or (deadline is not None and time.perf_counter() >= deadline - 0.05)


#: The reasons of a run that stopped before its end (its best so far is not proven).
_STOPPED = ("timeout", "interrupted")


def _budget(solver: Backend, deadline: float | None) -> None:
    """The solver's time for its next check: until ``deadline`` or the command's time limit,
    whichever comes first (1 ms once interrupted)."""
    left = limits.for_check(deadline)
    if left is not None:
        solver.set_timeout(left)


def _add_timings(total: dict[str, float], part: dict[str, float]) -> None:
    for key in ("encode", "solve", "validate"):
        total[key] = total.get(key, 0.0) + part.get(key, 0.0)


def _encode_whole(
    inst: ir.Instance, k: int, sequential: bool, optimize: bool, logic: str | None = None
) -> tuple[Encoder, Backend]:
    enc = Encoder(inst, k, sequential=sequential)
    enc.unroll(k)
    solver = open_backend(DEFAULT_BACKEND, optimize=optimize, logic=logic)
    solver.add(*enc.script.take())
    return enc, solver


def _objective_terms(
    enc: Encoder, solver: Backend, objectives: list[ir.Objective], softs: list[ir.Soft], k: int
) -> list[Term]:
    """The objectives as terms of ``solver``; the first carries the soft penalties ``Σ wᵢ·zᵢ``."""
    soft_terms = [enc.at_state(s.expr, k) for s in softs]
    penalty: list[Term] = []
    for s, t in zip(softs, soft_terms):
        assert isinstance(t, str)  # a soft constraint is Boolean: its term is text
        penalty.append(ite(t, Fraction(0), s.weight))
    out = []
    for i, obj in enumerate(objectives):
        term = enc.objective(obj.term, k)
        if i == 0 and penalty:
            term = smt_text((plus if obj.sense is ir.Sense.MINIMIZE else minus)(term, *penalty))
        out.append(solver.intern(term))
    return out


def _better_exists(
    inst: ir.Instance,
    objectives: list[ir.Objective],
    softs: list[ir.Soft],
    values: list[Fraction],
    k: int,
    sequential: bool,
    deadline: float | None,
    timings: dict[str, float],
    tactics: Tactics,
    share_with: Backend | None = None,
) -> Check:
    """Is there a composition of at most ``k`` steps lexicographically better than ``values``?

    Only an ``unsat`` answer is used (as a proof); anything else leads to optimising over the
    whole horizon.  The check runs on a solver configured for QF_LRA, measured ~8–10× faster
    on these refutations than the default configuration (docs/benchmarks.md); that is sound
    for ``unsat`` even if the configuration treated integer variables as reals, since the
    relaxed formula is implied by the exact one: unsat there implies unsat here.  Before it,
    the counting relaxation's proof runs on the instance with its invariants made explicit
    (:func:`~catc.queries.churn_search.tightened`: same valid compositions), which proves
    the search-and-rescue mission's event IV in milliseconds where the SMT check takes
    seconds (docs/benchmarks.md); and before that, where it applies, the solver-free bound of
    a churn kept at 0 (:func:`~catc.queries.churn_search.churn_floor_refutes`: recompose when
    nothing changes, as on lifelong/cheaper-camera).  ``share_with``: a backend whose Z3 context the counting
    proof's solver shares (one context fewer to make; an UNSAT answer does not depend on it)."""
    t0 = time.perf_counter()
    if _expired(deadline):  # stopped (Ctrl-C or the time limit): no new proof is started
        return Check.UNKNOWN
    if (
        tactics.counting_proofs
        and not softs
        and (
            churn_floor_refutes(inst, objectives, values)  # recompose keeping its deployed set: no solver
            or better_refuted(
                tightened(inst), objectives, values, timeout=limits.for_check(deadline), share_with=share_with
            )
        )
    ):
        timings["solve"] += time.perf_counter() - t0  # proved by counting activations (catc.smt.counting)
        return Check.UNSAT
    enc, solver = _encode_whole(inst, k, sequential, optimize=False, logic="QF_LRA")
    terms = _objective_terms(enc, solver, objectives, softs, k)
    improvements: list[Term] = []
    ties: list[Term] = []
    for term, obj, v in zip(terms, objectives, values):
        improvements.append(and_(*ties, better(term, v, obj.sense is ir.Sense.MINIMIZE)))
        ties.append(eq(term, v))
    solver.assert_term(or_(*improvements))
    timings["encode"] += time.perf_counter() - t0
    _budget(solver, deadline)
    t1 = time.perf_counter()
    r = solver.check()  # UNKNOWN also when the configuration refuses the formula: no proof from it
    timings["solve"] += time.perf_counter() - t1
    return r


def _optimize_at(
    inst: ir.Instance,
    objectives: list[ir.Objective],
    softs: list[ir.Soft],
    k: int,
    sequential: bool,
    deadline: float | None,
    prune: bool,
    tactics: Tactics,
    solvers: list[Backend] | None = None,
) -> OptResult:
    """One optimisation over an encoding of ``k`` steps (idle steps allowed); its optimiser is
    appended to ``solvers`` when given (for later proofs to share its context)."""
    start = time.perf_counter()
    timings = {"encode": 0.0, "solve": 0.0, "validate": 0.0}
    enc, solver = _encode_whole(inst, k, sequential, optimize=True)
    if solvers is not None:
        solvers.append(solver)
    handles = []
    for i, (obj, term) in enumerate(zip(objectives, _objective_terms(enc, solver, objectives, softs, k))):
        literals = []
        if tactics.maxsmt_churn and isinstance(obj.term, ir.TotalChurn) and not (i == 0 and softs):
            literals = [(changed, w) for changed, w in enc.churn_literals(k) if w > 0]
        if literals:  # churn as one group of soft constraints, answered by Z3's MaxSMT engine
            for changed, w in literals:
                handle = solver.add_soft(solver.intern(smt_text(not_(changed))), w, f"churn{i}")
            handles.append(handle)
        else:
            handles.append(solver.minimize(term) if obj.sense is ir.Sense.MINIMIZE else solver.maximize(term))
    timings["encode"] = time.perf_counter() - start

    _budget(solver, deadline)
    t1 = time.perf_counter()
    r = solver.check()
    timings["solve"] = time.perf_counter() - t1
    result = OptResult(OptStatus.UNKNOWN, k, timings=timings)
    if r is Check.UNSAT:
        result.status = OptStatus.UNSAT
        return result
    if r is Check.UNKNOWN:
        result.reason = solver.reason_unknown()
        if _expired(deadline) or (deadline is not None and result.reason in ("canceled", "timeout")):
            result.reason = limits.stop_reason() or "timeout"
        if not solver.has_model():
            return result
        result.status = OptStatus.SUBOPT
    else:
        result.status = OptStatus.OPT

    # Values: unbounded / not attained are read from the solver's bounds (of a finished run).
    bounds: list[tuple[str, object]] = []
    for h, obj in zip(handles, objectives):
        if result.status is OptStatus.SUBOPT:  # an interrupted run's bounds mean nothing
            bounds.append(("exact", None))
            continue
        b = solver.bound(h)
        if b.infinite:
            result.status = OptStatus.UNBOUNDED
            bounds.append(("unbounded", "oo" if b.infinite > 0 else "-oo"))
        elif b.exact:
            bounds.append(("exact", b.value))
        else:
            bounds.append(("epsilon", _limit_text(b, obj.sense)))

    t2 = time.perf_counter()
    plan = read_plan(solver, enc, k)
    report = validate(inst, plan, horizon=k, sequential=sequential)
    if not report.ok and result.status is OptStatus.SUBOPT:
        # an interrupted optimiser may hold a model it had not finished: not a composition
        result.status = OptStatus.UNKNOWN
        return result
    if not report.ok:
        raise ValidationFailure(
            "the independent validator rejected the optimum's composition: "
            + "; ".join(v.message for v in report.violations[:5])
        )

    _finish(inst, result, plan, objectives, softs, bounds, k, sequential, prune)
    timings["validate"] = time.perf_counter() - t2
    return result


def _scores(
    inst: ir.Instance,
    p: Plan,
    objectives: list[ir.Objective],
    softs: list[ir.Soft],
    k: int,
    sequential: bool,
    report=None,
) -> list[Fraction | None]:
    """A composition's objective values, exact, from the validator's replay (the first with
    the soft penalties); ``report`` is the replay when the caller already has it."""
    rep = report if report is not None else validate(inst, p, horizon=k, sequential=sequential)
    fin = rep.states[-1]
    pen = sum((s.weight for s in softs if evaluate(inst, s.expr, fin) is not True), Fraction(0))
    out = []
    for i, obj in enumerate(objectives):
        v = objective_value(inst, p, obj.term, fin)
        if v is not None and i == 0:
            v = v + pen if obj.sense is ir.Sense.MINIMIZE else v - pen
        out.append(v)
    return out


def _finish(
    inst: ir.Instance,
    result: OptResult,
    plan: Plan,
    objectives: list[ir.Objective],
    softs: list[ir.Soft],
    bounds: list[tuple[str, object]],
    k: int,
    sequential: bool,
    prune: bool,
) -> None:
    """Prune (keeping the values), rename fresh values, and fill in ``result`` from the
    validator's replay; an OPT value must equal the solver's bound where it gave one."""
    target = _scores(inst, plan, objectives, softs, k, sequential)

    def not_worse(p: Plan) -> bool:
        return _not_worse(_scores(inst, p, objectives, softs, k, sequential), target, objectives)

    plan = drop_idle_steps(inst, plan, k, sequential, accept=not_worse)  # always: no step that does nothing
    if prune:
        plan = prune_plan(inst, plan, k, sequential, accept=not_worse)
    plan = canonical_fresh(plan)
    report = validate(inst, plan, horizon=k, sequential=sequential)
    final = report.states[-1]
    result.plan, result.states = plan, report.states
    result.softs = [SoftOutcome(s, evaluate(inst, s.expr, final) is not True) for s in softs]
    penalty_value = sum((o.soft.weight for o in result.softs if o.violated), Fraction(0))
    for i, (obj, (kind, bound)) in enumerate(zip(objectives, bounds)):
        value = objective_value(inst, plan, obj.term, final)
        if value is not None and i == 0 and softs:
            value = value + penalty_value if obj.sense is ir.Sense.MINIMIZE else value - penalty_value
        ov = ObjectiveValue(obj, value)
        if kind == "exact":
            if bound is not None and value is not None and value != bound and result.status is OptStatus.OPT:
                raise ValidationFailure(
                    f"objective {i + 1}: the solver reports {bound} but the composition's value is {value}"
                )
        else:
            ov.attained = False
            ov.bound = str(bound)
        result.values.append(ov)


def _limit_text(b: Bound, sense: ir.Sense) -> str:
    """A bound with an infinitesimal (a supremum/infimum that no composition reaches), as
    'supremum 4, not attained'."""
    word = "infimum" if sense is ir.Sense.MINIMIZE else "supremum"
    return f"{word} {number_text(b.value)}, not attained"


def _not_worse(values: list, target: list, objectives: list[ir.Objective]) -> bool:
    """Lexicographically at least as good as ``target``."""
    for v, t, obj in zip(values, target, objectives):
        if v is None or t is None:
            return v == t
        if v != t:
            return (v < t) if obj.sense is ir.Sense.MINIMIZE else (v > t)
    return True


def _done(result: OptResult, start: float) -> OptResult:
    result.timings["total"] = time.perf_counter() - start
    return result
