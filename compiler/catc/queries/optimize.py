"""Optimization over compositions (paper eq. optimization), lexicographic by priority.

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
from collections.abc import Callable
from dataclasses import dataclass, field
from enum import Enum
from fractions import Fraction

from catc import ir
from catc.ir.numbers import number_text
from catc.semantics.compositions import canonical_fresh, prune_plan
from catc.semantics.horizon import default_horizon
from catc.semantics.plan import Plan
from catc.semantics.validate import ValidationFailure
from catc.smt.backend import DEFAULT_BACKEND, Backend, Bound, Check, open_backend
from catc.smt.encoder import Encoder
from catc.smt.readback import read_plan
from catc.smt.script import real_literal
from catc.smt.terms import Term, and_, better, eq, or_


class OptStatus(str, Enum):
    OPT = "opt"  # proven optimal
    SUBOPT = "subopt"  # best found before the time limit
    UNSAT = "unsat"
    UNKNOWN = "unknown"
    UNBOUNDED = "unbounded"


@dataclass
class ObjectiveValue:
    objective: ir.Objective
    value: Fraction | None  # exact, recomputed by the validator (with penalties for the first)
    attained: bool = True  # False when the solver reports a supremum/infimum not reached
    bound: str | None = None  # the solver's bound when not attained or unbounded


@dataclass
class SoftOutcome:
    soft: ir.Soft
    violated: bool


@dataclass
class OptResult:
    status: OptStatus
    horizon: int
    plan: Plan | None = None
    states: tuple = ()
    values: list[ObjectiveValue] = field(default_factory=list)
    softs: list[SoftOutcome] = field(default_factory=list)
    reason: str | None = None
    timings: dict[str, float] = field(default_factory=dict)


#: Horizons shorter than this are optimised with the single encoding even under ``deepen``:
#: on the examples with 2–6 steps it costs 1.0–1.3× plain solve, the deepening route
#: 1.2–2.2× (its extra encodings dominate such small problems; docs/benchmarks.md).
DEEPEN_FROM = 8


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
    progress: Callable[[str], None] | None = None,
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
    ``progress(message)`` is told what is being tried as it starts."""
    say = progress or (lambda message: None)
    objectives = objectives_of(inst) if objectives is None else objectives
    softs = list(inst.problem.softs)
    if not objectives and softs:
        objectives = [ir.Objective(ir.Sense.MINIMIZE, ir.Const(Fraction(0), ir.REAL))]
    if not objectives:
        raise ValueError("nothing to optimise: the problem has no (:metric ...) and no soft constraints")
    if strategy not in ("deepen", "single"):
        raise ValueError(f"unknown strategy {strategy!r}; expected 'deepen' or 'single'")
    k = default_horizon(inst) if horizon is None else horizon
    start = time.perf_counter()
    deadline = start + timeout if timeout else None
    if strategy == "single" or k < (DEEPEN_FROM if deepen_from is None else deepen_from):
        say(f"optimising over {k} steps")
        return _done(_optimize_at(inst, objectives, softs, k, sequential, deadline, prune), start)

    from catc.queries.solve import Status, solve

    first = solve(
        inst,
        horizon=k,
        sequential=sequential,
        timeout=timeout,
        validate_answer=False,
        prune=False,
        progress=lambda t, k, elapsed: say(f"looking for a first composition: horizon {t} of {k}"),
    )
    timings = {"encode": first.timings["encode"], "solve": first.timings["solve"], "validate": 0.0}
    if first.status is Status.UNSAT:
        return _done(OptResult(OptStatus.UNSAT, k, timings=timings), start)
    if first.status is not Status.SAT:
        return _done(OptResult(OptStatus.UNKNOWN, k, reason=first.reason, timings=timings), start)
    k0 = len(first.plan.steps)
    from catc.semantics.validate import validate

    report0 = validate(inst, first.plan, horizon=k, sequential=sequential)
    if not report0.ok:
        raise ValidationFailure("the independent validator rejected the solver's first composition")

    def first_plan(status: OptStatus, reason: str | None = None) -> OptResult:
        """The first composition as the answer (no solver bound to compare its values with)."""
        t2 = time.perf_counter()
        result = OptResult(status, k, reason=reason, timings=timings)
        _finish(inst, result, first.plan, objectives, softs, [("exact", None)] * len(objectives), k, sequential, prune)
        timings["validate"] += time.perf_counter() - t2
        return _done(result, start)

    if k0 < k:
        # Often the first composition found is already optimal: try to refute anything better
        # within the whole horizon, on a budget as long as the time spent so far.
        values0 = _scores(inst, first.plan, objectives, softs, k, sequential, report0)
        if None not in values0:
            say(f"first composition: {k0} steps; is there a better one within {k} steps?")
            budget0 = max(0.25, time.perf_counter() - start)
            r = _better_exists(inst, objectives, softs, values0, k, sequential, _sooner(deadline, budget0), timings)
            if r is Check.UNSAT:
                return first_plan(OptStatus.OPT)
    say(f"optimising over {k0} steps")
    short = None if _expired(deadline) else _optimize_at(inst, objectives, softs, k0, sequential, deadline, prune)
    if short is None or (short.plan is None and _expired(deadline)):
        return first_plan(OptStatus.SUBOPT, "timeout")  # out of time: the first composition is the best known
    _add_timings(timings, short.timings)
    short.horizon = k
    exact = (
        short.status is OptStatus.OPT
        and short.plan is not None
        and all(v.attained and v.value is not None for v in short.values)
    )
    if not exact:  # unattained or unbounded over k₀ steps, or out of time: optimise over everything
        if short.status is OptStatus.SUBOPT and _expired(deadline):
            short.timings = timings
            return _done(short, start)
        say(f"optimising over all {k} steps")
        whole = _optimize_at(inst, objectives, softs, k, sequential, deadline, prune)
        _add_timings(timings, whole.timings)
        whole.timings = timings
        return _done(whole, start)
    if k0 == k:
        short.timings = timings
        return _done(short, start)
    # Refute anything better over the whole horizon, or optimise over the whole horizon,
    # whichever finishes first: the two alternate with doubling time budgets (neither is
    # always the faster: see docs/benchmarks.md), so the cost stays within a small factor of
    # the better of the two.
    values = [v.value for v in short.values]
    budget = max(0.25, time.perf_counter() - start)
    refute = True
    while True:
        if refute:
            say(f"optimum over {k0} steps: {_values_text(values)}; is there a better one within {k} steps?")
            limit = _sooner(deadline, budget)
            r = _better_exists(inst, objectives, softs, values, k, sequential, limit, timings)
            if r is Check.UNSAT:  # nothing better within the whole horizon: the short optimum is it
                short.timings = timings
                return _done(short, start)
            if r is Check.SAT or not _expired(limit):  # something better, or no proof to be had here
                refute = False
            budget *= 2
        if _expired(deadline):
            break
        limit = _sooner(deadline, None if not refute else budget)
        say(f"optimum over {k0} steps: {_values_text(values)}; optimising over all {k} steps")
        whole = _optimize_at(inst, objectives, softs, k, sequential, limit, prune)
        _add_timings(timings, whole.timings)
        if whole.reason != "timeout":  # finished
            whole.timings = timings
            return _done(whole, start)
        if _expired(deadline):  # the best found wins if it is at least as good as the short optimum
            if whole.plan is not None and _not_worse([v.value for v in whole.values], values, objectives):
                whole.timings = timings
                return _done(whole, start)
            break
        budget *= 2
    short.status, short.reason, short.timings = OptStatus.SUBOPT, "timeout", timings
    return _done(short, start)


def _values_text(values: list[Fraction]) -> str:
    return ", ".join(str(v) for v in values)


def _sooner(deadline: float | None, budget: float | None) -> float | None:
    """The earlier of the deadline and ``budget`` seconds from now (None: no limit)."""
    if budget is None:
        return deadline
    mine = time.perf_counter() + budget
    return mine if deadline is None else min(deadline, mine)


def _expired(deadline: float | None) -> bool:
    """Past the deadline — with 50 ms of slack, as Z3's timer may stop a check a little early."""
    return deadline is not None and time.perf_counter() >= deadline - 0.05


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
    penalty = " ".join(f"(ite {t} 0.0 {real_literal(s.weight)})" for s, t in zip(softs, soft_terms))
    out = []
    for i, obj in enumerate(objectives):
        term = enc.objective(obj.term, k)
        if i == 0 and penalty:
            sign = "+" if obj.sense is ir.Sense.MINIMIZE else "-"
            term = f"({sign} {term} {penalty})"
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
) -> Check:
    """Is there a composition of at most ``k`` steps lexicographically better than ``values``?

    Only an ``unsat`` answer is used (as a proof); anything else leads to optimising over the
    whole horizon.  The check runs on a solver configured for QF_LRA, measured ~8–10× faster
    on these refutations than the default configuration (docs/benchmarks.md); that is sound
    for ``unsat`` even if the configuration treated integer variables as reals, since the
    relaxed formula is implied by the exact one: unsat there implies unsat here."""
    t0 = time.perf_counter()
    enc, solver = _encode_whole(inst, k, sequential, optimize=False, logic="QF_LRA")
    terms = _objective_terms(enc, solver, objectives, softs, k)
    improvements: list[Term] = []
    ties: list[Term] = []
    for term, obj, v in zip(terms, objectives, values):
        improvements.append(and_(*ties, better(term, v, obj.sense is ir.Sense.MINIMIZE)))
        ties.append(eq(term, v))
    solver.assert_term(or_(*improvements))
    timings["encode"] += time.perf_counter() - t0
    if deadline is not None:
        solver.set_timeout(max(0.001, deadline - time.perf_counter()))
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
) -> OptResult:
    """One optimisation over an encoding of ``k`` steps (idle steps allowed)."""
    start = time.perf_counter()
    timings = {"encode": 0.0, "solve": 0.0, "validate": 0.0}
    enc, solver = _encode_whole(inst, k, sequential, optimize=True)
    handles = []
    for obj, term in zip(objectives, _objective_terms(enc, solver, objectives, softs, k)):
        handles.append(solver.minimize(term) if obj.sense is ir.Sense.MINIMIZE else solver.maximize(term))
    timings["encode"] = time.perf_counter() - start

    if deadline is not None:
        solver.set_timeout(max(0.001, deadline - time.perf_counter()))
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
            result.reason = "timeout"
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
    from catc.semantics.validate import validate

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
    from catc.semantics.validate import evaluate, objective_value, validate

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
    from catc.semantics.validate import evaluate, objective_value, validate

    if prune:
        target = _scores(inst, plan, objectives, softs, k, sequential)
        plan = prune_plan(
            inst,
            plan,
            k,
            sequential,
            accept=lambda p: _not_worse(_scores(inst, p, objectives, softs, k, sequential), target, objectives),
        )
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
