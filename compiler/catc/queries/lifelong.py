"""The lifelong queries over one labelled model (paper §IV-D): diagnose, relax, recompose.

Every source construct's constraints are guarded by one indicator literal per label
(``pre/m/i``, ``eff/m/i``, ``init/r``, ``goal/i``, ``bound/m/p``, ``bounds/r``, ``uses/m``,
``horizon``), so a query is a question about subsets of labels:

* **diagnose** — an irreducible unsatisfiable subset (eq. diagnose): Z3's core, shrunk by
  deletion, then checked member by member (dropping any one restores feasibility);
  ``all_cores`` explores further cores by excluding a member of each core found (a hitting-set
  tree), bounded by count and time.
* **relax** — the least weighted slack on numeric requirements that restores feasibility
  (eq. relax), in one optimisation; or, ``discrete``, a least set of labels to drop.
* **recompose** — least weighted churn against the deployed composition, lexicographically
  with the mission objective, in either priority (eqs. churn, reconfigure).

Diagnoses are *relative to the composition* when the problem has ``(:deployed ...)`` (or one
is given): the components used are then fixed to exactly the deployed ones, so the core
names what stops that composition rather than the whole causal chain.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace
from fractions import Fraction

import z3

from catc import ir
from catc.queries.solve import ValidationFailure, canonical_fresh, default_horizon, use_bound
from catc.semantics.plan import Plan
from catc.smt.encoder import Encoder, _and, _or, quote, real_literal
from catc.smt.z3backend import Z3Session, to_fraction

HORIZON = "horizon"


# ====================================================================== the labelled model


class LabelledModel:
    """The composition formula with one indicator per source label.

    ``components`` fixes the set of morphisms used at least once (diagnosis relative to a
    composition).  With ``horizon_label`` the encoding extends past the horizon ``k`` — to
    the use-limit bound, or to 2k — and "nothing happens after step k" becomes the label
    ``horizon``, so a core can say that more steps would help."""

    def __init__(
        self,
        inst: ir.Instance,
        horizon: int,
        *,
        sequential: bool = False,
        components: Iterable[str] | None = None,
        horizon_label: bool = True,
        slack: dict[str, str] | None = None,
        slack_decls: list[tuple[str, str]] = (),  # type: ignore[assignment]
        optimize: bool = False,
        ctx: z3.Context | None = None,
    ):
        self.inst = inst
        self.k = horizon
        bound = use_bound(inst)
        extended = horizon
        if horizon_label:
            extended = (
                (bound if bound is not None and bound > horizon else horizon) if bound is not None else 2 * horizon
            )
            extended = max(extended, horizon)
        self.extended = extended
        self.enc = enc = Encoder(inst, extended, sequential=sequential, track=True, slack=slack)
        for _ in range(extended):
            enc.add_step()
        for label, c in enc.goal_constraints(extended) + enc.uses_constraints(extended):
            enc.add(label, c)
        if extended > horizon:
            for t in range(horizon, extended):
                enc.add(HORIZON, f"(not {_or(list(enc.act[t].values()))})")
        if components is not None:
            fixed = set(components)
            for m in enc.morphisms:
                used = _or([enc.act[t][m.name] for t in range(extended)])
                enc.add(None, used if m.name in fixed else f"(not {used})")
        # Indicators: assert (=> |L:label| group) for each label.
        groups: dict[str, list[str]] = {}
        structural: list[str] = []
        for label, text in enc.script.asserts:
            (structural if label is None else groups.setdefault(label, [])).append(text)
        self.labels = list(dict.fromkeys(list(groups) + list(enc.indicators)))
        self.indicator = {label: quote(f"L:{label}") for label in self.labels}
        decls = (
            list(slack_decls)
            + enc.script.decls
            + [(q, "Bool") for label, q in self.indicator.items() if label not in enc.indicators]
        )
        self.session = Z3Session(enc, optimize=optimize, ctx=ctx)
        enc.script.asserts = [(None, t) for t in structural] + [
            (label, f"(=> {self.indicator[label]} {_and(parts)})") for label, parts in groups.items()
        ]
        enc.script.decls = decls
        self.session.flush()
        self._ind_expr = {label: z3.Bool(q[1:-1], self.session.ctx) for label, q in self.indicator.items()}
        self.checks = 0

    def check(self, labels: Iterable[str], timeout: float | None = None) -> tuple[z3.CheckSatResult, list[str]]:
        """Check with exactly ``labels`` enforced; on UNSAT also return a core (labels)."""
        wanted = list(labels)
        if timeout is not None:
            self.session.set_timeout(timeout)
        self.checks += 1
        r = self.session.solver.check(*[self._ind_expr[l] for l in wanted])
        if r == z3.unsat:
            core = {str(c)[2:] for c in self.session.solver.unsat_core()}
            return r, [l for l in wanted if l in core]
        return r, []


# ====================================================================== diagnose


@dataclass
class Diagnosis:
    status: str  # "unsat" (cores found) | "sat" (nothing to diagnose) | "unknown"
    cores: list[list[str]] = field(default_factory=list)
    total: int = 0  # labelled constraints considered
    relative_to: tuple[str, ...] | None = None
    horizon: int = 0
    checks: int = 0
    complete: bool = True  # --all: the search ended (not cut by count or time)
    timings: dict[str, float] = field(default_factory=dict)


def _shrink(model: LabelledModel, core: list[str], deadline: float | None) -> list[str] | None:
    """Deletion-based minimisation of an unsat core to an irreducible one."""
    core = list(core)
    i = 0
    while i < len(core):
        trial = core[:i] + core[i + 1 :]
        r, smaller = model.check(trial, _remaining(deadline))
        if r == z3.unsat:
            keep = set(smaller)
            core = [l for l in trial if l in keep]
        elif r == z3.sat:
            i += 1
        else:
            return None
    return core


def _irreducible(model: LabelledModel, core: list[str], deadline: float | None) -> bool:
    r, _ = model.check(core, _remaining(deadline))
    if r != z3.unsat:
        return False
    return all(model.check([l for l in core if l != x], _remaining(deadline))[0] == z3.sat for x in core)


def _remaining(deadline: float | None) -> float | None:
    return None if deadline is None else max(0.001, deadline - time.perf_counter())


def diagnose(
    inst: ir.Instance,  # relative_to: None = the problem's (:deployed ...); () = no composition
    *,
    horizon: int | None = None,
    sequential: bool = False,
    relative_to: Iterable[str] | None = None,
    all_cores: bool = False,
    max_cores: int = 5,
    timeout: float | None = None,
    progress: Callable[[str], None] | None = None,
) -> Diagnosis:
    start = time.perf_counter()
    deadline = start + timeout if timeout else None
    k = default_horizon(inst) if horizon is None else horizon
    components = (tuple(relative_to) or None) if relative_to is not None else (inst.problem.deployed or None)
    model = LabelledModel(inst, k, sequential=sequential, components=components)
    result = Diagnosis("unknown", total=len(model.labels), relative_to=components, horizon=k)
    result.timings["encode"] = time.perf_counter() - start
    say = progress or (lambda message: None)
    say(f"checking {len(model.labels)} requirements together")
    r, core = model.check(model.labels, _remaining(deadline))
    if r == z3.sat:
        result.status = "sat"
    elif r == z3.unsat:
        found: list[list[str]] = []
        # Hitting-set tree: every further core must avoid one member of each core found.
        frontier: list[frozenset[str]] = [frozenset()]
        seen: set[frozenset[str]] = set()
        while frontier and len(found) < (max_cores if all_cores else 1):
            if deadline is not None and time.perf_counter() > deadline:
                result.complete = False
                break
            excluded = frontier.pop(0)
            if excluded in seen:
                continue
            seen.add(excluded)
            labels = [l for l in model.labels if l not in excluded]
            r, core = model.check(labels, _remaining(deadline))
            if r != z3.unsat:
                continue
            say(f"{len(found)} core(s) found; shrinking a core of {len(core)} requirements")
            mus = _shrink(model, core, deadline)
            if mus is None:
                result.complete = False
                break
            if not _irreducible(model, mus, deadline):  # pragma: no cover - _shrink guarantees it
                raise ValidationFailure(f"the core {mus} is not irreducible")
            if sorted(mus) not in [sorted(c) for c in found]:
                found.append(mus)
            frontier.extend(excluded | {x} for x in mus)
        if all_cores and frontier and len(found) >= max_cores:
            result.complete = False
        result.cores = found
        result.status = "unsat" if found else "unknown"
    result.checks = model.checks
    result.timings["total"] = time.perf_counter() - start
    return result


# ====================================================================== relax


@dataclass
class Requirement:
    label: str
    kind: str  # "initial value" | "precondition" | "goal"
    resources: frozenset[str]
    weight: Fraction
    integral: bool


@dataclass
class Relaxation:
    label: str
    kind: str
    delta: Fraction  # signed for initial values; ≥ 0 (the weakening) for comparisons
    weight: Fraction


@dataclass
class RelaxResult:
    status: str  # "relaxed" | "sat" (already feasible) | "unsat" (no relaxation helps) | "unknown"
    proven: bool = True  # False: the best relaxation found before the time limit
    relaxations: list[Relaxation] = field(default_factory=list)
    dropped: list[str] = field(default_factory=list)  # discrete variant
    cost: Fraction | None = None
    plan: Plan | None = None
    states: tuple = ()
    relaxed_instance: ir.Instance | None = None
    eligible: list[Requirement] = field(default_factory=list)
    horizon: int = 0
    timings: dict[str, float] = field(default_factory=dict)


def eligible_requirements(
    inst: ir.Instance, only: Iterable[str] = (), weights: dict[str, Fraction] | None = None
) -> list[Requirement]:
    """Numeric initial values, and order comparisons among preconditions and goals.

    ``only`` keeps those whose label equals or starts with an entry, or that mention a
    resource named by an entry; ``weights`` (same matching) sets weights (default 1)."""
    only = list(only)
    weights = weights or {}
    reqs: list[Requirement] = []

    def matches(key: str, label: str, resources: frozenset[str]) -> bool:
        return label == key or label.startswith(key.rstrip("/") + "/") or key in resources

    def add(label: str, kind: str, resources: frozenset[str], integral: bool) -> None:
        if only and not any(matches(k, label, resources) for k in only):
            return
        w = Fraction(1)
        for key, value in weights.items():
            if matches(key, label, resources):
                w = value
        reqs.append(Requirement(label, kind, resources, w, integral))

    for name, init in inst.problem.init.items():
        r = inst.resources.get(name)
        if r is not None and r.sort.is_numeric:
            add(init.label, "initial value", frozenset({name}), r.sort.kind is ir.SortKind.INT)
    for m in inst.morphisms.values():
        for lit in m.pre:
            if _is_order(lit.expr):
                add(lit.label, "precondition", ir.resources_in(lit.expr), _int_compare(lit.expr))
    for lit in inst.problem.goal:
        if _is_order(lit.expr):
            add(lit.label, "goal", ir.resources_in(lit.expr), _int_compare(lit.expr))
    return reqs


def _is_order(e: ir.Expr) -> bool:
    return isinstance(e, ir.Compare) and e.op is not ir.CmpOp.EQ


def _int_compare(e: ir.Compare) -> bool:  # type: ignore[name-defined]
    return e.left.sort.kind is ir.SortKind.INT and e.right.sort.kind is ir.SortKind.INT


def relax(
    inst: ir.Instance,
    *,
    horizon: int | None = None,
    sequential: bool = False,
    only: Iterable[str] = (),
    weights: dict[str, Fraction] | None = None,
    discrete: bool = False,
    relative_to: Iterable[str] | None = None,
    timeout: float | None = None,
    progress: Callable[[str], None] | None = None,
) -> RelaxResult:
    from catc.semantics.validate import validate

    start = time.perf_counter()
    k = default_horizon(inst) if horizon is None else horizon
    components = (tuple(relative_to) or None) if relative_to is not None else (inst.problem.deployed or None)
    result = RelaxResult("unknown", horizon=k)
    say = progress or (lambda message: None)
    if discrete:
        say("looking for the fewest requirements to drop")
        return _relax_discrete(inst, k, sequential, components, timeout, result, start)

    reqs = eligible_requirements(inst, only, weights)
    result.eligible = reqs
    slack: dict[str, str] = {}
    slack_vars: list[tuple[Requirement, list[str]]] = []
    for req in reqs:
        base = f"d.{req.label}"
        if req.kind == "initial value":
            plus, minus = quote(base + ".up"), quote(base + ".down")
            slack[req.label] = f"(- {plus} {minus})"
            slack_vars.append((req, [plus, minus]))
        else:
            q = quote(base)
            slack[req.label] = q
            slack_vars.append((req, [q]))
    slack_decls = [(v, "Int" if req.integral else "Real") for req, vs in slack_vars for v in vs]
    # Two copies of the model: a solver that looks for ever cheaper relaxations (any Boolean
    # skeleton), and an optimiser that finds the least slack for one skeleton (an LP).  The
    # loop ends when no cheaper relaxation exists (proven) or at the time limit (best found).
    deadline = start + timeout if timeout else None
    models = []
    ctx = z3.Context()  # one for both: a skeleton found by one is asserted in the other
    for optimize in (False, True):
        lm = LabelledModel(
            inst,
            k,
            sequential=sequential,
            components=components,
            horizon_label=False,
            slack=slack,
            slack_decls=slack_decls,
            optimize=optimize,
            ctx=ctx,
        )
        lm.session.solver.add(lm.session.parse_term(_and([f"(>= {v} 0)" for _, vs in slack_vars for v in vs])))
        for l in lm.labels:
            lm.session.solver.add(lm._ind_expr[l])
        models.append(lm)
    feas, lp = models
    weighted = []
    for req, vs in slack_vars:
        for v in vs:
            amount = f"(to_real {v})" if req.integral else v
            weighted.append(f"(* {real_literal(req.weight)} {amount})")
    cost_text = "(+ 0.0 " + " ".join(weighted) + ")"
    count_terms = [f"(ite (> {v} 0) 1 0)" for _, vs in slack_vars for v in vs]
    noninit_terms = [f"(ite (> {v} 0) 1 0)" for req, vs in slack_vars if req.kind != "initial value" for v in vs]
    h_cost = lp.session.solver.minimize(lp.session.parse_term(cost_text))
    lp.session.solver.minimize(lp.session.parse_term(f"(+ 0 {' '.join(count_terms)})"))
    lp.session.solver.minimize(lp.session.parse_term(f"(+ 0 {' '.join(noninit_terms)})"))
    feas_cost = feas.session.parse_term(cost_text)
    acts = [q for step in feas.enc.act for q in step.values()]
    result.timings["encode"] = time.perf_counter() - start
    best = None
    result.proven = False
    say("looking for a restoration")
    while True:
        feas.session.set_timeout(_remaining(deadline))
        r = feas.session.solver.check()
        if r == z3.unsat:
            result.proven = best is not None
            break
        if r == z3.unknown:
            break
        m = feas.session.solver.model()
        skeleton = [z3.Bool(q[1:-1], ctx) == m.eval(z3.Bool(q[1:-1], ctx), model_completion=True) for q in acts]
        lp.session.solver.push()
        lp.session.solver.add(skeleton)
        lp.session.set_timeout(_remaining(deadline))
        r2 = lp.session.solver.check()
        if r2 != z3.sat:
            lp.session.solver.pop()
            break
        lm_model = lp.session.solver.model()
        values: dict[str, Fraction] = {}
        for req, vs in slack_vars:
            amounts = [
                to_fraction(
                    lm_model.eval(
                        z3.Int(v[1:-1], ctx) if req.integral else z3.Real(v[1:-1], ctx), model_completion=True
                    )
                )
                for v in vs
            ]
            values[req.label] = amounts[0] - amounts[1] if req.kind == "initial value" else amounts[0]
        cost_value = to_fraction(h_cost.value())
        best = (cost_value, values, lp.session.extract(lp.extended))
        lp.session.solver.pop()
        if cost_value == 0:
            result.proven = True
            break
        say(f"best restoration so far: weighted total {cost_value}; is there a cheaper one?")
        feas.session.solver.add(feas_cost < z3.RealVal(f"{cost_value.numerator}/{cost_value.denominator}", ctx))
    if best is None:
        result.status = "unsat" if r == z3.unsat else "unknown"
        return _finish(result, start)
    result.cost, values, plan = best
    result.relaxations = [
        Relaxation(req.label, req.kind, values[req.label], req.weight)
        for req, _ in slack_vars
        if values[req.label] != 0
    ]
    result.status = "relaxed" if result.relaxations else "sat"
    relaxed = relaxed_instance(inst, {r_.label: r_.delta for r_ in result.relaxations})
    report = validate(relaxed, plan, horizon=k, sequential=sequential)
    if not report.ok:
        raise ValidationFailure(
            "the independent validator rejected the relaxed composition: "
            + "; ".join(v.message for v in report.violations[:5])
        )
    plan = canonical_fresh(plan)
    result.plan, result.states = plan, validate(relaxed, plan, horizon=k, sequential=sequential).states
    result.relaxed_instance = relaxed
    return _finish(result, start)


def _relax_discrete(inst, k, sequential, components, timeout, result: RelaxResult, start: float) -> RelaxResult:
    """A minimum-cardinality set of labelled constraints whose removal restores feasibility
    (a minimal correction set)."""
    model = LabelledModel(inst, k, sequential=sequential, components=components, horizon_label=True, optimize=True)
    opt = model.session.solver
    for l in model.labels:
        opt.add_soft(model._ind_expr[l], 1)
    if timeout:
        model.session.set_timeout(timeout)
    result.timings["encode"] = time.perf_counter() - start
    r = opt.check()
    if r != z3.sat:
        result.status = "unsat" if r == z3.unsat else "unknown"
        return _finish(result, start)
    m = opt.model()
    dropped = [l for l in model.labels if not z3.is_true(m.eval(model._ind_expr[l], model_completion=True))]
    # minimality: putting back any dropped label makes it infeasible again
    for l in dropped:
        keep = [x for x in model.labels if x not in dropped or x == l]
        if model.check(keep)[0] != z3.unsat:  # pragma: no cover - a minimum set is minimal
            raise ValidationFailure(f"dropping {dropped} is not minimal: {l} can stay")
    result.dropped = dropped
    result.status = "relaxed" if dropped else "sat"
    return _finish(result, start)


def relaxed_instance(inst: ir.Instance, deltas: dict[str, Fraction]) -> ir.Instance:
    """The instance with each relaxation applied to the IR (for independent validation)."""
    init = dict(inst.problem.init)
    for name, value in inst.problem.init.items():
        if value.label in deltas and isinstance(value.value, ir.Const):
            init[name] = replace(value, value=ir.Const(value.value.value + deltas[value.label], value.value.sort))  # type: ignore[operator]

    def weaken(lit: ir.Literal) -> ir.Literal:
        d = deltas.get(lit.label)
        if d is None or not isinstance(lit.expr, ir.Compare):
            return lit
        e = lit.expr
        c = ir.Const(d, ir.REAL if ir.REAL in (e.left.sort, e.right.sort) else ir.INT)
        if e.op in (ir.CmpOp.GE, ir.CmpOp.GT):
            e = replace(e, left=ir.Arith(ir.ArithOp.ADD, (e.left, c), c.sort if e.left.sort == c.sort else ir.REAL))
        else:
            e = replace(e, right=ir.Arith(ir.ArithOp.ADD, (e.right, c), c.sort if e.right.sort == c.sort else ir.REAL))
        return replace(lit, expr=e)

    morphisms = {n: replace(m, pre=tuple(weaken(l) for l in m.pre)) for n, m in inst.morphisms.items()}
    domain = replace(inst.domain, morphisms=ir.frozen(morphisms))
    problem = replace(inst.problem, init=ir.frozen(init), goal=tuple(weaken(l) for l in inst.problem.goal))
    return ir.Instance(domain, problem, inst.view)


def _finish(result, start: float):
    result.timings["total"] = time.perf_counter() - start
    return result


# ====================================================================== recompose


@dataclass
class ChurnItem:
    morphism: str
    change: str  # "added" | "removed"
    weight: Fraction


@dataclass
class Recomposition:
    result: object  # the OptResult of the lexicographic optimisation
    deployed: tuple[str, ...]
    priority: str  # "stability" (churn first) | "objective"
    churn: Fraction | None = None
    items: list[ChurnItem] = field(default_factory=list)


def recompose(
    inst: ir.Instance,
    *,
    deployed: Iterable[str] | None = None,
    priority: str = "stability",
    objectives: list[ir.Objective] | None = None,
    horizon: int | None = None,
    sequential: bool = False,
    timeout: float | None = None,
    progress: Callable[[str], None] | None = None,
) -> Recomposition:
    from catc.queries.optimize import objectives_of, optimize

    if deployed is not None:
        inst = ir.Instance(inst.domain, replace(inst.problem, deployed=tuple(deployed)), inst.view)
    mission = objectives_of(inst) if objectives is None else objectives
    mission = [o for o in mission if not isinstance(o.term, ir.TotalChurn)]
    churn = ir.Objective(ir.Sense.MINIMIZE, ir.TotalChurn())
    order = [churn] + mission if priority == "stability" else mission + [churn]
    result = optimize(inst, order, horizon=horizon, sequential=sequential, timeout=timeout, progress=progress)
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
