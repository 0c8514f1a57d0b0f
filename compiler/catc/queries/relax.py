"""relax: the least weakening of the requirements that makes the problem feasible.

The least weighted slack on numeric requirements — initial values, and order comparisons
among preconditions and goals — that restores feasibility (paper eq. relax), proven least by
a search over Boolean skeletons with an LP per skeleton; or, ``discrete``, a least set of
labelled constructs to drop (a minimum correction set).  The composition the relaxation makes
possible is replayed by the independent validator on the relaxed instance.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from fractions import Fraction
from typing import Any, NamedTuple, TypeGuard

from catc import ir
from catc.ir.labels import LabelInfo, label_index
from catc.present.composition import print_composition
from catc.present.console import Console, escape
from catc.present.labels import describe, label_json, where
from catc.present.values import show_value, steps_json, timings_json
from catc.queries.base import (
    ExitCode,
    Kind,
    Option,
    Progress,
    Query,
    Result,
    Status,
    certificate_option,
    diagram_artifact,
    json_option,
    timeout_option,
    unknown_why,
)
from catc.queries.cores import optimal_restoration, restoration
from catc.semantics.compositions import canonical_fresh, checked
from catc.semantics.horizon import horizon_of
from catc.semantics.plan import Plan, value_to_json
from catc.semantics.validate import ValidationFailure
from catc.smt.backend import Check
from catc.smt.consumption import consumption_bound, stronger_bound
from catc.smt.counting import slack_lower_bound
from catc.smt.labelled import LabelledModel
from catc.smt.readback import read_plan
from catc.smt.script import SmtSort, Symbol, and_text, int_literal
from catc.smt.terms import Term, and_, eq, ge, gt, ite, le, lt, minus, not_, plus, times, to_real, to_text
from catgrammar import limits
from catgrammar.record import replace


class Requirement(NamedTuple):  # (not a dataclass: `catc relax` does not import dataclasses)
    label: str
    kind: str  # "initial value" | "precondition" | "goal"
    resources: frozenset[str]
    weight: Fraction
    integral: bool


class Relaxation(NamedTuple):
    label: str
    kind: str
    delta: Fraction  # signed for initial values; ≥ 0 (the weakening) for comparisons
    weight: Fraction


class RelaxStatus(Status):
    RELAXED = "relaxed", ExitCode.OK
    SAT = "sat", ExitCode.FAIL  # already feasible: nothing to relax
    UNSAT = "unsat", ExitCode.FAIL  # no relaxation of the eligible requirements helps
    UNKNOWN = "unknown", ExitCode.UNKNOWN


class RelaxResult(Result):
    """The answer of :func:`relax`; filled in as the search goes."""

    query = "relax"
    __slots__ = (
        "status",
        "proven",
        "relaxations",
        "dropped",
        "cost",
        "infimum",
        "attained",
        "plan",
        "states",
        "relaxed_instance",
        "eligible",
        "horizon",
        "timings",
        "reason",
    )
    status: RelaxStatus

    def __init__(
        self,
        status: RelaxStatus,
        proven: bool = True,  # False: the best relaxation found before the time limit
        relaxations: list[Relaxation] | None = None,
        dropped: list[str] | None = None,  # discrete variant
        cost: Fraction | None = None,  # the weighted total of the relaxations shown
        #: the least weighted total: ``cost`` when ``attained``; otherwise approached by ever
        #: smaller relaxations but reached by none (e.g. a goal ``(> x 5)`` from ``x = 5``)
        infimum: Fraction | None = None,
        attained: bool = True,
        plan: Plan | None = None,
        states: tuple = (),
        relaxed_instance: ir.Instance | None = None,
        eligible: list[Requirement] | None = None,
        horizon: int = 0,
        timings: dict[str, float] | None = None,
        reason: str | None = None,  # why the search stopped early: "timeout" or "interrupted"
    ) -> None:
        self.status = status
        self.proven = proven
        self.relaxations: list[Relaxation] = [] if relaxations is None else relaxations
        self.dropped: list[str] = [] if dropped is None else dropped
        self.cost = cost
        self.infimum = infimum
        self.attained = attained
        self.plan = plan
        self.states = states
        self.relaxed_instance = relaxed_instance
        self.eligible: list[Requirement] = [] if eligible is None else eligible
        self.horizon = horizon
        self.timings: dict[str, float] = {} if timings is None else timings
        self.reason = reason

    def __repr__(self) -> str:
        fields = ", ".join(f"{name}={getattr(self, name)!r}" for name in self.__slots__)
        return f"RelaxResult({fields})"

    @property
    def settled(self) -> bool:
        return self.proven


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


def check(inst: ir.Instance, options: Mapping[str, Any]) -> str | None:
    """Every ``--only`` and ``--weights`` key must name some eligible requirement (a label, a
    label prefix or a resource): a typo would otherwise leave nothing eligible, or weigh
    nothing, without a word."""
    every = eligible_requirements(inst)
    labels = {r.label for r in every}
    names = sorted(labels | {r for req in every for r in req.resources} | {lab.split("/")[0] + "/" for lab in labels})
    keys = [("--only", k) for k in options.get("only") or ()]
    keys += [("--weights", k) for k in (options.get("weights") or {})]
    initial = sorted({r for req in every if req.kind == "initial value" for r in req.resources})
    for name in options.get("fixed") or ():
        if name not in initial:
            from catgrammar.diagnostics import did_you_mean

            return f"--fixed {name!r} is no resource with a numeric initial value{did_you_mean(name, initial)}"
    for flag, key in keys:
        if not eligible_requirements(inst, [key]):
            from catgrammar.diagnostics import did_you_mean

            return (
                f"{flag} {key!r} matches no eligible requirement (numeric initial values and order "
                f"comparisons of preconditions and goals: a label, a label prefix such as init/, or a "
                f"resource){did_you_mean(key, names)}"
            )
    if options.get("discrete"):
        return None
    given = options.get("weights") or {}
    return unit_safe_weights(inst, options.get("only") or (), given, options.get("fixed") or ())[1]


def unit_safe_weights(
    inst: ir.Instance,
    only: Iterable[str] = (),
    weights: Mapping[str, Fraction] | None = None,
    fixed: Iterable[str] = (),
) -> tuple[dict[str, Fraction], str | None]:
    """The default weights of a restoration, one policy for ``catc relax`` and the runtime.

    Returns (``weights`` to pass to :func:`relax`, None), or (``{}``, why not) when the
    default cannot be set.  Given weights are kept.  When the eligible requirements left
    unweighted (``only``, less the ``fixed`` initial values) are all of one unit, each weighs
    1 (1 W counts as 1 W).  When they are of different units — a requirement has the unit of
    the resources it constrains; no unit is a unit of its own — each is weighed by its
    relative change, 1/scale: the scale of a resource is |its initial value|, else its
    largest nonzero |bound|, else the largest |constant| it is compared with; a
    precondition or goal takes the largest scale of its resources, else |its own constant|.  With no scale, 1 W would have to count as 1 USD:
    the answer is why, asking for ``--weights``."""
    given = dict(weights or {})
    held = set(fixed)
    every = eligible_requirements(inst, only, given)
    keys = list(given)
    free = [r for r in every if not (r.kind == "initial value" and r.resources & held)]
    open_ = [r for r in free if not _weighted(r, keys)]
    if len({_unit_of(inst, r) for r in open_}) <= 1:
        return given, None
    defaults: dict[str, Fraction] = {}
    for req in open_:
        scale = max((_scale(inst, name) for name in req.resources), default=Fraction(0))
        if not scale and req.kind != "initial value":
            scale = _constant_of(inst, req)
        if not scale:
            units = sorted(str(u or "no unit") for u in {_unit_of(inst, r) for r in open_})
            return {}, (
                f"the requirements to relax are of different units ({', '.join(units)}) and {req.label} "
                f"has no scale to weigh it by (initial value, bounds and the constants compared with are 0 or absent): "
                f"give --weights (e.g. --weights {sorted(req.resources)[0] if req.resources else req.label}=1)"
            )
        defaults[req.label] = 1 / scale
    return {**defaults, **given}, None


def _weighted(req: Requirement, keys: Iterable[str]) -> bool:
    return any(req.label == k or req.label.startswith(k.rstrip("/") + "/") or k in req.resources for k in keys)


def _unit_of(inst: ir.Instance, req: Requirement) -> str | frozenset[str] | None:
    """The unit of a requirement's slack: that of the resources it constrains (a set of
    several is a compound unit of its own)."""
    units = frozenset(u for name in req.resources if name in inst.resources for u in [inst.resources[name].unit] if u)
    return None if not units else next(iter(units)) if len(units) == 1 else units


def _scale(inst: ir.Instance, name: str) -> Fraction:
    """|initial value| of a numeric resource, else its largest nonzero |bound|, else the
    largest |constant| an order comparison of it (precondition or goal) compares with, else 0."""
    init = inst.problem.init.get(name)
    value = getattr(init.value, "value", None) if init is not None else None
    if isinstance(value, (int, Fraction)) and not isinstance(value, bool) and value:
        return abs(Fraction(value))
    r = inst.resources.get(name)
    bounds = [abs(b) for b in (r.lower, r.upper) if b is not None and b] if r is not None else []
    if bounds:
        return max(bounds)
    literals = [lit for m in inst.morphisms.values() for lit in m.pre] + list(inst.problem.goal)
    return max((_constant(lit.expr) for lit in literals if name in ir.resources_in(lit.expr)), default=Fraction(0))


def _constant_of(inst: ir.Instance, req: Requirement) -> Fraction:
    """|the constant| a precondition or goal compares with (0 when none)."""
    literals = [lit for m in inst.morphisms.values() for lit in m.pre] + list(inst.problem.goal)
    return max((_constant(lit.expr) for lit in literals if lit.label == req.label), default=Fraction(0))


def _constant(e: ir.Expr) -> Fraction:
    if _is_order(e):
        for side in (e.right, e.left):
            if isinstance(side, ir.Const) and isinstance(side.value, Fraction):
                return abs(side.value)
    return Fraction(0)


def _is_order(e: ir.Expr) -> TypeGuard[ir.Compare]:
    return isinstance(e, ir.Compare) and e.op is not ir.CmpOp.EQ


def _int_compare(e: ir.Compare) -> bool:
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
    progress: Progress | None = None,
    counting: bool = True,
    fixed: Iterable[str] = (),
) -> RelaxResult:
    """``counting=False`` proves a restoration least by search alone, without the lower
    bound of :mod:`catc.smt.counting` (for tests and benchmarks).  ``fixed`` resources keep
    their initial values (``--fixed``: a battery nobody can recharge)."""
    start = time.perf_counter()
    with limits.deadline(timeout):
        k = horizon_of(inst, horizon)
        result = RelaxResult(RelaxStatus.UNKNOWN, horizon=k)
        if not discrete:  # unlike units are never added at weight 1 (docs/semantics.md)
            only = list(only)
            weights, refused = unit_safe_weights(inst, only, weights, fixed)
            if refused is not None:
                result.reason = refused
                return _finish(result, start)
        if fixed and not discrete:  # every eligible requirement but the fixed initial values
            held = set(fixed)
            kept = eligible_requirements(inst, only, weights)
            only = [r.label for r in kept if not (r.kind == "initial value" and r.resources & held)]
            if not only:  # nothing may change
                result.status = RelaxStatus.UNSAT
                return _finish(result, start)
        try:
            return _relax(inst, k, sequential, only, weights, discrete, relative_to, progress, result, start, counting)
        except limits.Stopped as stop:  # encoding or validating when the time ran out
            result.status, result.reason, result.plan = RelaxStatus.UNKNOWN, stop.reason, None
            return _finish(result, start)


def _relax(
    inst: ir.Instance,
    k: int,
    sequential: bool,
    only: Iterable[str],
    weights: dict[str, Fraction] | None,
    discrete: bool,
    relative_to: Iterable[str] | None,
    progress: Progress | None,
    result: RelaxResult,
    start: float,
    counting: bool = True,
) -> RelaxResult:
    components = (tuple(relative_to) or None) if relative_to is not None else (inst.problem.deployed or None)
    say = progress or (lambda message: None)
    deadline = limits.deadline_at()
    if discrete:
        say("looking for the fewest requirements to drop")
        return _finish(_relax_discrete(inst, k, sequential, components, result, start), start)
    result.eligible = eligible_requirements(inst, only, weights)
    best = _at_bound(inst, k, sequential, result.eligible) if components is None and counting else None
    if best is not None:  # least: it meets the least-consumption bound (issue 24)
        say(f"restoration of weighted total {best.cost}: least, it meets the least-consumption bound")
        result.proven, exhausted = True, False
    else:
        search = _SlackSearch(inst, k, sequential, components, result.eligible, counting)
        result.timings["encode"] = time.perf_counter() - start
        say("looking for a restoration")
        best, result.proven, exhausted = search.run(deadline, say)
    result.reason = None if result.proven or exhausted else limits.stop_reason()
    if best is None:
        result.status = RelaxStatus.UNSAT if exhausted else RelaxStatus.UNKNOWN
        return _finish(result, start)
    result.cost, result.infimum, result.attained = best.cost, best.infimum, best.attained
    values, plan = best.values, best.plan
    result.relaxations = [
        Relaxation(req.label, req.kind, values[req.label], req.weight)
        for req in result.eligible
        if values[req.label] != 0
    ]
    result.status = RelaxStatus.RELAXED if result.relaxations else RelaxStatus.SAT
    found = time.perf_counter()
    result.timings["solve"] = found - start - result.timings.get("encode", 0)
    relaxed = relaxed_instance(inst, {r_.label: r_.delta for r_ in result.relaxations})
    checked(relaxed, plan, k, sequential, "the relaxed composition")
    result.plan = canonical_fresh(plan)
    result.states = checked(relaxed, result.plan, k, sequential, "the relaxed composition")
    result.relaxed_instance = relaxed
    result.timings["validate"] = time.perf_counter() - found
    return _finish(result, start)


_ZERO, _ONE = int_literal(0), int_literal(1)


def _at_bound(inst: ir.Instance, k: int, sequential: bool, reqs: list[Requirement]) -> _Found | None:
    """A restoration of the whole catalog built at the h_max least-consumption bound and
    accepted by the validator (:func:`catc.queries.cores.restoration`): least, no search."""
    weights = {r.label: r.weight for r in reqs if r.kind == "initial value"}
    integral = {r.label for r in reqs if r.integral}
    found = restoration(inst, k, sequential, weights, integral, lambda deltas: relaxed_instance(inst, deltas))
    if found is None:  # several resources short: the abstraction's exact optimum
        triples = [(r.label, r.kind, r.weight) for r in reqs]
        found = optimal_restoration(inst, k, sequential, triples, integral, lambda d: relaxed_instance(inst, d))
    if found is None:
        return None
    cost, raised, plan = found
    values = {r.label: raised.get(r.label, Fraction(0)) for r in reqs}
    return _Found(cost, cost, True, values, plan)


class _SlackSearch:
    """The least weighted slack, found by two copies of the labelled model with slack on
    every eligible requirement: a solver that looks for ever cheaper relaxations (any
    Boolean skeleton), and an optimiser that finds the least slack for one skeleton (an LP).
    The search ends when no cheaper relaxation exists (proven) or at the deadline (the best
    found).  Both share one term store: a skeleton found by one is asserted in the other."""

    def __init__(
        self,
        inst: ir.Instance,
        k: int,
        sequential: bool,
        components: tuple[str, ...] | None,
        reqs: list[Requirement],
        counting: bool = True,
    ) -> None:
        slack: dict[str, str] = {}
        self.slack_vars: list[tuple[Requirement, list[Symbol]]] = []
        for req in reqs:
            base = f"d.{req.label}"
            sort = SmtSort.INT if req.integral else SmtSort.REAL
            if req.kind == "initial value":  # s0 = v + δ⁺ − δ⁻: initial values move either way
                up, down = Symbol(base + ".up", sort), Symbol(base + ".down", sort)
                slack[req.label] = to_text(minus(up, down))
                self.slack_vars.append((req, [up, down]))
            else:
                q = Symbol(base, sort)
                slack[req.label] = q
                self.slack_vars.append((req, [q]))
        decls = [v for _, vs in self.slack_vars for v in vs]
        models: list[LabelledModel] = []
        for optimize in (False, True):
            lm = LabelledModel(
                inst,
                k,
                sequential=sequential,
                components=components,
                horizon_label=False,
                slack=slack,
                slack_decls=decls,
                optimize=optimize,
                share_with=models[0] if models else None,
            )
            lm.backend.assert_term(and_text([to_text(ge(v, _ZERO)) for v in decls]))
            lm.enforce_all()
            models.append(lm)
        self.feas, self.lp = models
        weighted: list[Term] = []
        for req, vs in self.slack_vars:
            for v in vs:
                weighted.append(times(req.weight, to_real(v) if req.integral else v))
        cost = to_text(plus(Fraction(0), *weighted))
        used = [ite(gt(v, _ZERO), _ONE, _ZERO) for _, vs in self.slack_vars for v in vs]
        noninit = [
            ite(gt(v, _ZERO), _ONE, _ZERO) for req, vs in self.slack_vars if req.kind != "initial value" for v in vs
        ]
        lp = self.lp.backend
        # least cost, then fewest slacks, then fewest weakened conditions (initial values first)
        self.cost_handle = lp.minimize(lp.intern(cost))
        lp.minimize(lp.intern(to_text(plus(_ZERO, *used))))
        lp.minimize(lp.intern(to_text(plus(_ZERO, *noninit))))
        self.feas_cost = self.feas.backend.intern(cost)
        self.acts = [q for step in self.feas.enc.act for q in step.values()]
        # a lower bound from counting activations (catc.smt.counting): a restoration that
        # reaches it is least without refuting every cheaper ordering
        self.lower: Fraction | bool | None = None
        #: the consumption bound's arguments while it is not computed yet (see :meth:`_stronger`)
        self._consumption: tuple[ir.Instance, list[Requirement], tuple[str, ...] | None] | None = None
        if counting:
            self.lower = slack_lower_bound(
                inst,
                [(r.label, r.kind, r.weight) for r in reqs],
                components,
                timeout=_remaining(limits.deadline_at()),
                # the search's context: one Z3 context less (~7 ms); the consumption
                # bound keeps its own, as sharing that one changes which least
                # restoration the search returns on two golden examples
                share_with=self.feas.backend,
            )
            if self.lower is not False:
                self._consumption = (inst, reqs, components)

    def _stronger(self) -> Fraction | bool | None:
        """The lower bound with the consumption bound (issue 24: it sees budget sums over
        competing alternatives) taken in, computed on first use: only when the counting bound
        alone does not prove the restoration found least.  It has a Z3 context of its own
        (~8 ms to make), which a restoration meeting the counting bound — most of them, as
        ``catc relax examples/lifelong/budget-cut.cat`` — never needs.  Computing it later
        changes no answer: its context is not the search's, and where it is False (no
        restoration) the search's first check is UNSAT as well, the same answer."""
        if self._consumption is not None:
            inst, reqs, components = self._consumption
            self._consumption = None
            self.lower = stronger_bound(self.lower, consumption_bound(inst, reqs, components))
        return self.lower

    def run(self, deadline: float | None, say: Callable[[str], None]) -> tuple[_Found | None, bool, bool]:
        """The best relaxation found, whether it is proven least, and whether the search space
        ran out.  A skeleton whose least slack is approached but not reached (an infimum, as
        for a goal ``(> x 5)`` from ``x = 5``) is blocked, and the search goes on for one that
        reaches that total or goes below it."""
        feas = self.feas.backend
        best: _Found | None = None
        if self.lower is False:  # not even the counting relaxation can be restored
            return None, False, True
        jumped = False  # a restoration at the lower bound was looked for (issue 24)
        while True:
            feas.set_timeout(_remaining(deadline))
            r = feas.check()
            if r is Check.UNSAT:
                return best, best is not None, True
            if r is Check.UNKNOWN:
                return best, False, False
            skeleton = [eq(q, feas.value(q)) for q in self.acts]
            found = self._least_slack(skeleton, deadline)
            if found is None:
                return best, False, False
            if best is None or found.infimum < best.infimum or (found.infimum == best.infimum and found.attained):
                best = found
            if best.attained and best.infimum == 0:
                return best, True, False
            if best.attained and self._meets(best.infimum):
                say(
                    f"best restoration so far: weighted total {best.infimum}; least: it meets the lower bound "
                    "from counting activations"
                )
                return best, True, False
            lower = self._stronger() if not jumped and best.attained else None
            if _is_bound(lower) and lower > 0:
                jumped, at_bound = True, self._at_bound(lower, deadline)
                if at_bound is not None:  # instead of descending one restoration at a time
                    say(f"restoration of weighted total {at_bound.infimum}: least, it meets the lower bound")
                    return at_bound, True, False
            if best.attained:
                say(f"best restoration so far: weighted total {best.infimum}; is there a cheaper one?")
                feas.assert_term(lt(self.feas_cost, best.infimum))
            else:
                say(f"restorations approach weighted total {best.infimum}; does one reach it?")
                feas.assert_term(le(self.feas_cost, best.infimum))
            if not found.attained:
                feas.assert_term(not_(and_(*skeleton)) if skeleton else False)

    def _meets(self, total: Fraction) -> bool:
        """Whether ``total`` is at the lower bound: first against the counting bound alone (a
        total at or below it is at the stronger bound too, both being sound), then with the
        consumption bound taken in."""
        if _is_bound(self.lower) and total <= self.lower:
            return True
        lower = self._stronger()
        return _is_bound(lower) and total <= lower

    def _at_bound(self, lower: Fraction, deadline: float | None) -> _Found | None:
        """A restoration of weighted total ``lower`` (the proven lower bound), or None."""
        feas = self.feas.backend
        feas.push()
        feas.assert_term(le(self.feas_cost, lower))
        feas.set_timeout(_remaining(deadline))
        found = None
        if feas.check() is Check.SAT:
            found = self._least_slack([eq(q, feas.value(q)) for q in self.acts], deadline)
        feas.pop()
        return found if found is not None and found.attained and found.infimum <= lower else None

    def _least_slack(self, skeleton: Sequence[Term], deadline: float | None) -> _Found | None:
        """The LP for one Boolean skeleton: its least cost (or the infimum it approaches), the
        slack per label and the composition of the solver's model (when the infimum is not
        attained, one restoration above it)."""
        lp = self.lp.backend
        lp.push()
        for part in skeleton:
            lp.assert_term(part)
        lp.set_timeout(_remaining(deadline))
        if lp.check() is not Check.SAT:
            lp.pop()
            return None
        values: dict[str, Fraction] = {}
        shown = Fraction(0)  # the weighted total of the model's restoration
        for req, vs in self.slack_vars:
            amounts = [a for a in (lp.value(v) for v in vs) if not isinstance(a, bool)]
            assert len(amounts) == len(vs)  # slacks are numbers
            values[req.label] = amounts[0] - amounts[1] if req.kind == "initial value" else amounts[0]
            shown += req.weight * sum(amounts, Fraction(0))
        bound = lp.bound(self.cost_handle)
        assert bound.infinite == 0  # a sum of non-negative slacks is bounded below by 0
        cost = bound.value if bound.exact else shown
        found = _Found(cost, bound.value, bound.exact, values, read_plan(lp, self.lp.enc, self.lp.extended))
        lp.pop()
        return found


def _is_bound(lower: Fraction | bool | None) -> TypeGuard[Fraction]:
    return isinstance(lower, Fraction)


class _Found(NamedTuple):
    """One skeleton's least slack: ``cost`` is the weighted total of the restoration shown
    (``values``, ``plan``); ``infimum`` the least total over the skeleton, ``attained``
    whether some restoration reaches it (then ``cost == infimum``)."""

    cost: Fraction
    infimum: Fraction
    attained: bool
    values: dict[str, Fraction]
    plan: Plan


def _relax_discrete(
    inst: ir.Instance,
    k: int,
    sequential: bool,
    components: tuple[str, ...] | None,
    result: RelaxResult,
    start: float,
) -> RelaxResult:
    """A minimum-cardinality set of labelled constraints whose removal restores feasibility
    (a minimal correction set)."""
    model = LabelledModel(inst, k, sequential=sequential, components=components, horizon_label=True, optimize=True)
    opt = model.backend
    for label in model.labels:
        opt.add_soft(model.indicator[label], Fraction(1))
    opt.set_timeout(limits.for_check())  # None: no limit, not a stale one
    result.timings["encode"] = time.perf_counter() - start
    r = opt.check()
    if r is not Check.SAT:
        result.status = RelaxStatus.UNSAT if r is Check.UNSAT else RelaxStatus.UNKNOWN
        result.reason = None if r is Check.UNSAT else limits.stop_reason()
        return result
    dropped = [label for label in model.labels if opt.value(model.indicator[label]) is not True]
    # minimality: putting back any dropped label makes it infeasible again
    for label in dropped:
        keep = [x for x in model.labels if x not in dropped or x == label]
        if model.check(keep)[0] is not Check.UNSAT:  # pragma: no cover - a minimum set is minimal
            raise ValidationFailure(f"dropping {dropped} is not minimal: {label} can stay")
    result.dropped = dropped
    result.status = RelaxStatus.RELAXED if dropped else RelaxStatus.SAT
    return result


def _remaining(deadline: float | None) -> float | None:
    """Time for the next check: up to ``deadline`` (1 ms once interrupted)."""
    return limits.for_check(deadline)


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


# ====================================================================== output


def _unit_json(inst: ir.Instance, rel: Relaxation, info: LabelInfo) -> dict[str, str]:
    """``{"unit": "USD"}`` for a relaxed initial value of a resource with a unit (the delta's unit)."""
    if rel.kind != "initial value" or info.owner not in inst.resources:
        return {}
    unit = inst.resources[info.owner].unit  # type: ignore[index]  # owner checked above
    return {"unit": unit} if unit else {}


def relaxation_text(inst: ir.Instance, rel: Relaxation, info: LabelInfo) -> str:
    if rel.kind == "initial value":
        name = info.owner
        assert name is not None
        unit = inst.resources[name].unit if name in inst.resources else None
        sign = "+" if rel.delta > 0 else "-"
        initial = inst.problem.init[name].value
        assert isinstance(initial, ir.Const)  # a relaxable initial value is a number
        old = initial.value
        return (
            f"{name}: {sign}{show_value(abs(rel.delta))}{' ' + escape(unit) if unit else ''}"
            f"   (initial value {show_value(old)} → {show_value(old + rel.delta)})"  # type: ignore[operator]
        )
    return f"{info.label}: weaken {escape(info.text)} by {show_value(rel.delta)}"


def relax_json(inst: ir.Instance, result: RelaxResult) -> dict:
    """The ``catc.relax/1`` document; ``attained: false`` and the ``infimum`` are added only
    when no relaxation reaches the least total (the recorded answers of the others stay as
    they were)."""
    index = label_index(inst)
    doc = {
        "schema": "catc.relax/1",
        "status": result.status.value,
        "problem": inst.problem.name,
        "cost": value_to_json(result.cost) if result.cost is not None else None,
        "proven": result.proven,
        "relaxations": [
            {
                **label_json(index[r.label]),
                "delta": value_to_json(r.delta),
                "weight": value_to_json(r.weight),
                **_unit_json(inst, r, index[r.label]),
            }
            for r in result.relaxations
        ],
        "dropped": [label_json(index[label]) for label in result.dropped],
        "steps": None if result.plan is None else steps_json(inst, result.plan, kinds=False),
        "timings": timings_json(result.timings),
    }
    if not result.attained and result.infimum is not None:
        doc["attained"] = False
        doc["infimum"] = value_to_json(result.infimum)
    if result.reason is not None:  # why the search stopped early
        doc["reason"] = result.reason
    return doc


_STOPPED = {"timeout": "the time limit", "interrupted": "the run was interrupted"}


def render(console: Console, inst: ir.Instance, result: RelaxResult, options: Mapping[str, Any] | None = None) -> None:
    _render_answer(console, inst, result)
    console.print(timing_line(result.timings))


def timing_line(t: Mapping[str, float]) -> str:
    """``time: encode E ms, search S ms, validate V ms`` (the parts measured), as the other
    queries end their answer."""
    search = t.get("solve", t.get("total", 0) - t.get("encode", 0) - t.get("validate", 0))
    parts = [f"encode {t.get('encode', 0) * 1000:.0f} ms", f"search {search * 1000:.0f} ms"]
    if "validate" in t:
        parts.append(f"validate {t['validate'] * 1000:.0f} ms")
    return f"[dim]time: {', '.join(parts)}; total {t.get('total', 0) * 1000:.0f} ms[/]"


def _render_answer(console: Console, inst: ir.Instance, result: RelaxResult) -> None:
    if result.status is RelaxStatus.SAT:
        console.print("[bold green]SAT[/]  nothing to relax: the problem is feasible as it is")
        return
    if result.status is RelaxStatus.UNSAT:
        console.print("[bold red]UNSAT[/]  no relaxation of the eligible requirements restores feasibility")
        return
    if result.status is not RelaxStatus.RELAXED:
        why = "interrupted" if result.reason == "interrupted" else unknown_why(result.reason)
        console.print(f"[bold yellow]UNKNOWN[/]  {why}")
        return
    index = label_index(inst)
    if result.dropped:
        console.print(
            f"[bold yellow]RELAXED[/]  drop {len(result.dropped)} requirement"
            f"{'s' if len(result.dropped) != 1 else ''} (a minimum set whose removal restores feasibility):"
        )
        for label in result.dropped:
            info = index[label]
            console.print(f"  - {escape(describe(info))}   {escape(where(info))}")
        return
    console.print(
        f"[bold yellow]RELAXED[/]  {_headline(result)} over {len(result.eligible)} eligible requirement{'' if len(result.eligible) == 1 else 's'}:"
    )
    for rel in result.relaxations:
        info = index[rel.label]
        console.print(f"  {relaxation_text(inst, rel, info)}   {escape(where(info))}")
    if result.plan is not None:
        console.print("\nthe composition this makes possible:")
        print_composition(console, result.relaxed_instance or inst, result.plan, result.states)


def _headline(result: RelaxResult) -> str:
    """What the relaxations shown are: the least, the best before the time limit, or one
    above a least total that no relaxation reaches."""
    total = show_value(result.cost)
    if not result.attained and result.infimum is not None:
        proof = "" if result.proven else ", not proven least"
        limit = f"infimum {show_value(result.infimum)}, not attained{proof}"
        return f"one restoration (weighted total {total}; no restoration is least: {limit})"
    if result.proven:
        return f"the least restoration (weighted total {total})"
    stopped = _STOPPED.get(result.reason or "", "the search stopped")
    return f"the best restoration found before {stopped} (not proven least) (weighted total {total})"


QUERY = Query(
    "relax",
    summary="The least weakening of the requirements that makes the problem feasible.",
    description=(
        "Exit 0 when a relaxation is found, 1 when none helps or the problem is already "
        "feasible, 2 input error, 3 unknown."
    ),
    options=(
        Option(
            "only",
            ("--only",),
            Kind.TEXTS,
            "Relax only these requirements (a label, a label prefix such as init/, or a resource name; repeatable).",
            default=(),
            metavar="LABEL|RESOURCE",
        ),
        Option(
            "weights",
            ("--weights",),
            Kind.WEIGHTS,
            "Weight of the slack on matching requirements (default 1; repeatable).",
            default=(),
            metavar="KEY=W",
        ),
        Option(
            "fixed",
            ("--fixed",),
            Kind.TEXTS,
            "Never change this resource's initial value (repeatable).",
            default=(),
            metavar="RESOURCE",
        ),
        Option(
            "discrete",
            ("--discrete",),
            Kind.FLAG,
            "Return a minimum set of requirements to drop instead of numeric slack.",
            default=False,
        ),
        Option(
            "relative_to",
            ("--relative-to",),
            Kind.COMPONENTS,
            "Keep this composition (default: the problem's (:deployed ...); 'none' for any).",
            metavar="COMPONENTS",
            none_word="none",
        ),
        timeout_option("Stop after this many seconds; the best relaxation so far is reported (exit 3)."),
        json_option("catc.relax/1"),
        certificate_option(),
    ),
    run=relax,
    check=check,
    to_json=relax_json,
    render=render,
    artifacts=diagram_artifact,
    progress=True,
)
