"""A lower bound on the least relaxation, from counting activations (no order, no steps).

``catc relax`` finds restorations quickly, but proving the cheapest one least means refuting
"a cheaper one exists" over every ordering of every composition — the slow part (issue 16).
This module gives the proof a target: an *operator-counting* relaxation in the sense of
Pommerening, Röger, Helmert and Bonet (ICAPS 2014) — the state equation of Petri nets —
solved as one small optimisation: each morphism ``m`` fires ``n_m`` times (at least once for
a component of the fixed composition, never for the others, at most its use limit), and a
numeric resource ``r`` that no morphism assigns ends at ``init(r) + Σ n_m·Δ(m, r)``, where
``Δ(m, r)`` is an interval from ``m``'s increments with θ within its bounds.  Then:

* the final value must lie within the resource's bounds and satisfy the goal's comparisons
  on ``r`` (weakened by their slack);
* a precondition ``r ≥ c`` of a morphism that fires needs ``r``'s highest possible value —
  its initial value plus every increment that could come before — to reach ``c`` (weakened
  by its slack); ``r ≤ c`` likewise with the lowest.

Every composition satisfies these, so the least weighted slack subject to them is a lower
bound on the least relaxation: when a restoration found costs exactly that, it is proven
least without further search; when the bound is infeasible, no relaxation exists.
Comparisons of other shapes, assigned resources and unbounded increments add no constraint
(the bound only weakens).
"""

from __future__ import annotations

from collections.abc import Collection, Iterable
from fractions import Fraction

from catc import ir
from catc.semantics import transfer
from catc.semantics.relaxed import VALUES, Finite, Interval, SetValue, Value, _Eval, top
from catc.smt.backend import DEFAULT_BACKEND, Backend, Check, open_backend
from catc.smt.script import SmtSort, Symbol, int_literal
from catc.smt.terms import Term, and_, eq, ge, gt, implies, ite, le, lt, minus, or_, plus, times, to_real, to_text

_ZERO, _ONE = int_literal(0), int_literal(1)
_REAL_ZERO = Fraction(0)

#: (label, kind, weight) of an eligible requirement: kind "initial value" | "precondition" | "goal".
Slackable = tuple[str, str, Fraction]


def slack_lower_bound(
    inst: ir.Instance,
    requirements: Iterable[Slackable],
    components: Collection[str] | None,
    timeout: float | None = None,
    backend: str = DEFAULT_BACKEND,
    share_with: Backend | None = None,
) -> Fraction | bool | None:
    """The least weighted slack of the counting relaxation: a Fraction; ``False`` when no
    slack satisfies it (then no relaxation exists); ``None`` when it could not be settled.
    ``share_with``: a backend whose term store (Z3: context) its solver shares."""
    counting = _Counting(inst, list(requirements), components)
    solver = open_backend(backend, optimize=True, share_with=share_with)
    solver.add(counting.decls, [(None, a) for a in counting.asserts])
    handle = solver.minimize(counting.cost())
    solver.set_timeout(timeout)
    r = solver.check()
    if r is Check.UNSAT:
        return False
    if r is not Check.SAT:
        return None
    bound = solver.bound(handle)
    # only an exact optimum is a bound: Z3's optimiser has been seen to answer "1 − ε" on a
    # mixed integer model whose optimum is 0 (tests/test_counting.py found it), so anything
    # with an infinitesimal or infinite part is no proof
    return bound.value if bound.exact else None


class _Counting:
    def __init__(self, inst: ir.Instance, reqs: list[Slackable], components: Collection[str] | None) -> None:
        self.inst = inst
        self.reqs = reqs
        self.decls: list[Symbol] = []
        self.asserts: list[str] = []
        self.slack: dict[str, str] = {}  # label → slack term (≥ 0 weakening, or a signed move)
        self.final: dict[str, str] = {}  # resource → a variable for its final value (when modelled)
        self.n: dict[str, Symbol] = {}
        self.weighted: list[tuple[Fraction, Symbol]] = []  # the cost: Σ weight · slack variable
        for label, kind, weight in reqs:
            if kind == "initial value":
                up, down = self._var(f"up.{label}"), self._var(f"down.{label}")
                self.slack[label] = to_text(minus(up, down))
                self.weighted += [(weight, up), (weight, down)]
            else:
                d = self.slack[label] = self._var(f"d.{label}")
                self.weighted.append((weight, d))
        for m in inst.morphisms.values():
            n = self.n[m.name] = self._var(f"n.{m.name}", SmtSort.INT)
            if components is not None:
                self.asserts.append(to_text(ge(n, _ONE) if m.name in components else eq(n, _ZERO)))
            if m.uses is not None:
                self.asserts.append(to_text(le(n, int_literal(m.uses))))
        assigned = {e.resource for m in inst.morphisms.values() for e in m.effects if e.kind is ir.EffectKind.ASSIGN}
        for r in inst.resources.values():
            if r.sort.is_numeric and r.name not in assigned and r.name in inst.problem.init:
                self._resource(r)

    # -- facts: a Boolean or a membership that does not hold at first needs an achiever
    def causal_constraints(self) -> None:
        """A morphism that fires (or the goal) needing a fact that is false at first needs
        some morphism that may make it true to fire too (delete relaxation, counted)."""
        for m in self.inst.morphisms.values():
            for lit in m.pre:
                self._needs_fact(lit.expr, to_text(ge(self.n[m.name], _ONE)))
        for lit in self.inst.problem.goal:
            self._needs_fact(lit.expr, to_text(True))

    def _needs_fact(self, e: ir.Expr, when: str) -> None:
        fact = _fact(self.inst, e)
        if fact is None:
            return
        resource, elements, value = fact
        init = self.inst.problem.init.get(resource)
        if init is None:
            return
        start = _Eval({}, {})(init.value)
        if any(_holds(start, element, value) is not False for element in elements):
            return
        achievers = [
            self.n[m.name]
            for m in self.inst.morphisms.values()
            if any(
                _may_achieve(ef, element, value) for ef in m.effects if ef.resource == resource for element in elements
            )
        ]
        total = to_text(plus(_ZERO, *achievers)) if achievers else _ZERO
        self.asserts.append(to_text(implies(when, ge(total, _ONE))))

    def objective(self, term: ir.Expr) -> str | None:
        """The objective's value over the counts (bounded by a fresh variable for a final
        resource value), or None when the counting relaxation does not model it."""
        if isinstance(term, ir.TotalChurn):
            deployed = set(self.inst.problem.deployed)
            parts = [
                ite(eq(self.n[m.name], _ZERO) if m.name in deployed else ge(self.n[m.name], _ONE), m.churn, _REAL_ZERO)
                for m in self.inst.morphisms.values()
            ]
            return to_text(plus(_REAL_ZERO, *parts))
        if isinstance(term, ir.Uses) and term.morphism in self.n:
            return to_text(to_real(self.n[term.morphism]))
        if isinstance(term, ir.ResourceRef):
            return self.final.get(term.name)
        if isinstance(term, ir.Const) and isinstance(term.value, Fraction):
            return to_text(term.value)
        return None

    def _var(self, name: str, sort: SmtSort = SmtSort.REAL) -> Symbol:
        v = Symbol(name, sort)
        self.decls.append(v)
        self.asserts.append(to_text(ge(v, _ZERO)))
        return v

    def cost(self) -> str:
        parts = [times(weight, v) for weight, v in self.weighted]
        return to_text(plus(_REAL_ZERO, *parts) if parts else _REAL_ZERO)

    # -- one resource's state equation
    def _deltas(self, r: ir.Resource) -> dict[str, Interval]:
        """Each morphism's net change of ``r`` per firing, as an interval: the transfer
        function (:mod:`catc.semantics.transfer`) from a zero state (``r`` is never assigned)."""
        out: dict[str, Interval] = {}
        zero = Interval(Fraction(0), Fraction(0))
        for m in self.inst.morphisms.values():
            ev = _Eval({}, {p.name: _param(m, p) for p in m.params})
            writes = [(e, ev(e.value), True) for e in m.effects if e.resource == r.name]
            total = transfer.post(VALUES, writes, lambda _: zero).get(r.name, zero)
            assert isinstance(total, Interval)  # an increase or decrease of a number
            if total != zero:
                out[m.name] = total
        return out

    def _resource(self, r: ir.Resource) -> None:
        init = self.inst.problem.init[r.name]
        if not isinstance(init.value, ir.Const) or not isinstance(init.value.value, Fraction):
            return
        start = to_text(init.value.value)
        if init.label in self.slack:
            start = to_text(plus(init.value.value, self.slack[init.label]))
        deltas = self._deltas(r)
        lo_final = self._sum(start, [(m, d.lo) for m, d in deltas.items()])
        hi_final = self._sum(start, [(m, d.hi) for m, d in deltas.items()])
        highest = self._sum(start, [(m, None if d.hi is None else max(d.hi, Fraction(0))) for m, d in deltas.items()])
        lowest = self._sum(start, [(m, None if d.lo is None else min(d.lo, Fraction(0))) for m, d in deltas.items()])
        if lo_final is not None and hi_final is not None:
            f = Symbol(f"final.{r.name}", SmtSort.REAL)
            self.decls.append(f)
            self.asserts += [to_text(le(lo_final, f)), to_text(le(f, hi_final))]
            self.asserts += [to_text(ge(f, b)) for b in [r.lower] if b is not None]
            self.asserts += [to_text(le(f, b)) for b in [r.upper] if b is not None]
            self.final[r.name] = f
        if r.lower is not None and hi_final is not None:
            self.asserts.append(to_text(ge(hi_final, r.lower)))
        if r.upper is not None and lo_final is not None:
            self.asserts.append(to_text(le(lo_final, r.upper)))
        for lit in self.inst.problem.goal:
            self._literal(lit, r.name, lo_final, hi_final, None)
        for m in self.inst.morphisms.values():
            for lit in m.pre:
                self._literal(lit, r.name, lowest, highest, self.n[m.name])
        self._last(r, start, deltas, lo_final, hi_final)

    def _last(
        self, r: ir.Resource, start: str, deltas: dict[str, Interval], lo_final: str | None, hi_final: str | None
    ) -> None:
        """Some firing touching ``r`` is the last one, and none shares its step when it reads
        ``r`` (non-interference): its preconditions on ``r`` see every other firing's change.
        So one of them — ``m`` firing and its preconditions holding on ``start + Σ n·Δ − Δ(m)``
        — or none fires.  (A last firing without a precondition on ``r`` makes this trivial.)"""
        touching = [m for m in self.inst.morphisms.values() if r.name in m.reads or r.name in m.writes]
        if not touching or lo_final is None or hi_final is None:
            return
        options = [eq(plus(_ZERO, *(self.n[m.name] for m in touching)), _ZERO)]
        for m in touching:
            d = deltas.get(m.name, Interval(Fraction(0), Fraction(0)))
            assert d.lo is not None and d.hi is not None  # finite: lo_final and hi_final exist
            before_lo = to_text(minus(lo_final, d.lo))
            before_hi = to_text(minus(hi_final, d.hi))
            needs: list[str] = []
            for lit in m.pre:
                need = self._need(lit, r.name, before_lo, before_hi)
                if need is not None:
                    needs.append(need)
            options.append(and_(ge(self.n[m.name], _ONE), *(needs or [to_text(True)])))
        self.asserts.append(to_text(or_(*options)))

    def _sum(self, start: str, terms: list[tuple[str, Fraction | None]]) -> str | None:
        if any(c is None for _, c in terms):
            return None
        parts = [times(c, to_real(self.n[m])) for m, c in terms if c]
        return to_text(plus(start, *parts)) if parts else start

    def _literal(self, lit: ir.Literal, name: str, low: str | None, high: str | None, fires: Symbol | None) -> None:
        """``r op c`` (either way round): the extreme value of ``r`` must reach ``c``."""
        need = self._need(lit, name, low, high)
        if need is not None:
            self.asserts.append(need if fires is None else to_text(implies(ge(fires, _ONE), need)))

    def _need(self, lit: ir.Literal, name: str, low: str | None, high: str | None) -> str | None:
        """What ``lit``, when it is ``r op c``, needs of r's lowest and highest values."""
        e = lit.expr
        if not isinstance(e, ir.Compare) or e.op is ir.CmpOp.EQ:
            return None
        op: ir.CmpOp = e.op
        left, right = e.left, e.right
        if isinstance(right, ir.ResourceRef) and isinstance(left, ir.Const):
            left, right = right, left
            op = _MIRROR[op]
        if not (isinstance(left, ir.ResourceRef) and left.name == name and isinstance(right, ir.Const)):
            return None
        if not isinstance(right.value, Fraction):
            return None
        c, delta = right.value, self.slack.get(lit.label, _REAL_ZERO)
        if op in (ir.CmpOp.GE, ir.CmpOp.GT):  # (+ r δ) ≥ c: the highest value must reach c − δ
            return None if high is None else to_text(ge(plus(high, delta), c))
        return None if low is None else to_text(le(low, plus(c, delta)))  # r ≤ c + δ


def _fact(inst: ir.Instance, e: ir.Expr) -> tuple[str, tuple[str | None, ...], bool] | None:
    """(resource, the elements any of which would do — ``(None,)`` for a Boolean —, wanted
    truth) of a fact literal: a Boolean resource, a constant's membership, or a parameter's
    membership ``(member ?x s)`` (some value of ``?x``'s sort in ``s``; only positive: a
    reserve value is never in a set at first, and only an effect adding a parameter's value
    may add it, which :func:`_may_achieve` counts)."""
    positive = True
    if isinstance(e, ir.BoolOp) and e.op is ir.BoolOpKind.NOT:
        e, positive = e.args[0], False
    if isinstance(e, ir.ResourceRef) and e.sort.kind is ir.SortKind.BOOL:
        return e.name, (None,), positive
    if not (isinstance(e, ir.Member) and isinstance(e.set, ir.ResourceRef)):
        return None
    element = e.element
    if isinstance(element, ir.Const) and isinstance(element.value, str):
        return e.set.name, (element.value,), positive
    if isinstance(element, ir.ParamRef) and element.sort.is_symbolic and positive:
        return e.set.name, (*inst.constants_of(element.sort), _RESERVE), positive
    return None


#: An element no constant names (a parameter's reserve value): never in a set at first.
_RESERVE = "\u0000reserve"


def _holds(start: Value, element: str | None, value: bool) -> bool | None:
    """Whether the fact holds in the initial value (None: unknown)."""
    if element is None:
        if isinstance(start, Finite) and start.values is not None and len(start.values) == 1:
            return next(iter(start.values)) is value
        return None
    if isinstance(start, SetValue) and start.may is not None:
        inside = element in start.must
        if not inside and element not in start.may:
            return value is False
        if inside:
            return value is True
    return None


def _may_achieve(e: ir.Effect, element: str | None, value: bool) -> bool:
    """Whether effect ``e`` (on the fact's resource) may make the fact hold."""
    v = e.value
    if element is None:  # a Boolean: an assignment of anything but the other constant
        return e.kind is ir.EffectKind.ASSIGN and not (isinstance(v, ir.Const) and v.value is (not value))
    if e.kind is ir.EffectKind.ASSIGN:
        return True
    adds = e.kind is ir.EffectKind.ADD
    if adds != value:
        return False
    return not (isinstance(v, ir.Const) and isinstance(v.value, str) and v.value != element)


_MIRROR = {ir.CmpOp.GE: ir.CmpOp.LE, ir.CmpOp.GT: ir.CmpOp.LT, ir.CmpOp.LE: ir.CmpOp.GE, ir.CmpOp.LT: ir.CmpOp.GT}


def _param(m: ir.Morphism, p: ir.Param) -> Value:
    v = top(p.sort)
    if isinstance(v, Interval) and (p.fixed or m.uses != 0):
        return v.meet(p.lower, p.upper)
    return v


# ---------------------------------------------------------------- objectives


def better_refuted(
    inst: ir.Instance,
    objectives: list[ir.Objective],
    values: list[Fraction],
    timeout: float | None = None,
    share_with: Backend | None = None,
) -> bool:
    """True when the counting relaxation proves that no composition (of any length) is
    lexicographically better than ``values``; False when it cannot (an objective it does not
    model, or a better count vector exists).  A proof of optimality for ``catc optimize`` and
    ``catc recompose`` that needs no refutation over every ordering.  ``share_with``: a backend
    whose term store (Z3: context) its solver shares."""
    counting = _Counting(inst, [], None)
    counting.causal_constraints()
    terms = [counting.objective(o.term) for o in objectives]
    if any(t is None for t in terms):
        return False
    better: list[Term] = []
    ties: list[Term] = []
    for term, obj, v in zip(terms, objectives, values, strict=True):
        assert term is not None
        better.append(and_(*ties, (lt if obj.sense is ir.Sense.MINIMIZE else gt)(term, v)))
        ties.append(eq(term, v))
    counting.asserts.append(to_text(or_(*better)))
    solver = open_backend(DEFAULT_BACKEND, share_with=share_with)
    solver.add(counting.decls, [(None, a) for a in counting.asserts])
    solver.set_timeout(timeout)
    return solver.check() is Check.UNSAT
