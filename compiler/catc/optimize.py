"""Optimization over compositions (paper eq. optimization), lexicographic by priority.

One encoding of the whole horizon (idle steps allowed) goes to ``z3.Optimize``.  The first
objective carries the soft-constraint penalties ``Σ wᵢ·zᵢ`` (``zᵢ`` = soft constraint ``i``
violated in the final state; added when minimising, subtracted when maximising); further
objectives break ties in order.  The answer's composition is replayed by the independent
validator, which also recomputes every objective value exactly; the value reported is the
validator's, and it must equal the solver's (else: internal error).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from enum import Enum
from fractions import Fraction

import z3

from catc import ir
from catc.encode.smt import Encoder, real_literal
from catc.encode.z3backend import Z3Session, to_fraction
from catc.plan import Plan
from catc.solve import ValidationFailure, canonical_fresh, default_horizon, prune_plan


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
) -> OptResult:
    from catc.validate import evaluate, objective_value, validate

    objectives = objectives_of(inst) if objectives is None else objectives
    softs = list(inst.problem.softs)
    if not objectives and softs:
        objectives = [ir.Objective(ir.Sense.MINIMIZE, ir.Const(Fraction(0), ir.REAL))]
    if not objectives:
        raise ValueError("nothing to optimise: the problem has no (:metric ...) and no soft constraints")
    k = default_horizon(inst) if horizon is None else horizon
    start = time.perf_counter()
    timings = {"encode": 0.0, "solve": 0.0, "validate": 0.0}

    enc = Encoder(inst, k, sequential=sequential)
    for _ in range(k):
        enc.add_step()
    for label, c in enc.goal_constraints(k) + enc.uses_constraints(k):
        enc.add(label, c)
    session = Z3Session(enc, optimize=True)
    session.flush()

    soft_terms = [enc.term(s.expr, _final_ctx(k)) for s in softs]
    penalty = " ".join(f"(ite {t} 0.0 {real_literal(s.weight)})" for s, t in zip(softs, soft_terms))
    handles = []
    for i, obj in enumerate(objectives):
        term = enc.objective(obj.term, k)
        if i == 0 and penalty:
            sign = "+" if obj.sense is ir.Sense.MINIMIZE else "-"
            term = f"({sign} {term} {penalty})"
        expr = session.parse_term(term)
        handles.append(session.solver.minimize(expr) if obj.sense is ir.Sense.MINIMIZE else session.solver.maximize(expr))
    timings["encode"] = time.perf_counter() - start

    if timeout:
        session.set_timeout(timeout)
    t1 = time.perf_counter()
    r = session.solver.check()
    timings["solve"] = time.perf_counter() - t1
    result = OptResult(OptStatus.UNKNOWN, k, timings=timings)
    if r == z3.unsat:
        result.status = OptStatus.UNSAT
        return _done(result, start)
    if r == z3.unknown:
        result.reason = session.reason_unknown()
        if timeout and time.perf_counter() - start >= timeout * 0.99:
            result.reason = "timeout"
        try:
            session.solver.model()
        except z3.Z3Exception:
            return _done(result, start)
        result.status = OptStatus.SUBOPT
    else:
        result.status = OptStatus.OPT

    # Values: unbounded / not attained are read from the solver's bounds.
    bounds = []
    for h, obj in zip(handles, objectives):
        v = h.value()
        text = str(v)
        if "oo" in text:
            result.status = OptStatus.UNBOUNDED
            bounds.append(("unbounded", text))
        elif z3.is_rational_value(v) or z3.is_int_value(v):
            bounds.append(("exact", to_fraction(v)))
        else:
            bounds.append(("epsilon", _limit_text(v, obj.sense)))

    t2 = time.perf_counter()
    plan = session.extract(k)
    report = validate(inst, plan, horizon=k, sequential=sequential)
    if not report.ok:
        raise ValidationFailure("the independent validator rejected the optimum's composition: "
                                + "; ".join(v.message for v in report.violations[:5]))

    def scores(p: Plan) -> list[Fraction | None]:
        rep = validate(inst, p, horizon=k, sequential=sequential)
        fin = rep.states[-1]
        pen = sum((s.weight for s in softs if evaluate(inst, s.expr, fin) is not True), Fraction(0))
        out = []
        for i, obj in enumerate(objectives):
            v = objective_value(inst, p, obj.term, fin)
            if v is not None and i == 0:
                v = v + pen if obj.sense is ir.Sense.MINIMIZE else v - pen
            out.append(v)
        return out

    if prune:
        target = scores(plan)
        plan = prune_plan(inst, plan, k, sequential, accept=lambda p: _not_worse(scores(p), target, objectives))
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
            if value is not None and value != bound and result.status is OptStatus.OPT:
                raise ValidationFailure(
                    f"objective {i + 1}: the solver reports {bound} but the composition's value is {value}"
                )
        else:
            ov.attained = False
            ov.bound = str(bound)
        result.values.append(ov)
    timings["validate"] = time.perf_counter() - t2
    return _done(result, start)


def _limit_text(v: z3.ExprRef, sense: ir.Sense) -> str:
    """A bound Z3 reports with an infinitesimal (a supremum/infimum that no composition
    reaches), as 'sup 4 (not attained)'."""
    eps = [c for c in _constants(v) if c.decl().name() == "epsilon"]
    limit = z3.simplify(z3.substitute(v, *[(e, z3.RealVal(0)) for e in eps])) if eps else v
    word = "infimum" if sense is ir.Sense.MINIMIZE else "supremum"
    try:
        from catc.sexpr import number_text

        return f"{word} {number_text(to_fraction(limit))}, not attained"
    except ValueError:
        return f"{word} {v}"


def _constants(e: z3.ExprRef) -> list[z3.ExprRef]:
    out, stack = [], [e]
    while stack:
        x = stack.pop()
        if z3.is_const(x) and x.decl().kind() == z3.Z3_OP_UNINTERPRETED:
            out.append(x)
        stack.extend(x.children())
    return out


def _not_worse(values: list, target: list, objectives: list[ir.Objective]) -> bool:
    """Lexicographically at least as good as ``target``."""
    for v, t, obj in zip(values, target, objectives):
        if v is None or t is None:
            return v == t
        if v != t:
            return (v < t) if obj.sense is ir.Sense.MINIMIZE else (v > t)
    return True


def _final_ctx(k: int):
    from catc.encode.smt import _Ctx

    return _Ctx(k, {}, [])


def _done(result: OptResult, start: float) -> OptResult:
    result.timings["total"] = time.perf_counter() - start
    return result
