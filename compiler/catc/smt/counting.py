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
from catc.semantics.relaxed import Interval, Value, _Eval, top
from catc.smt.backend import DEFAULT_BACKEND, Check, open_backend
from catc.smt.script import SmtSort, Symbol, real_literal

#: (label, kind, weight) of an eligible requirement: kind "initial value" | "precondition" | "goal".
Slackable = tuple[str, str, Fraction]


def slack_lower_bound(
    inst: ir.Instance,
    requirements: Iterable[Slackable],
    components: Collection[str] | None,
    timeout: float | None = None,
    backend: str = DEFAULT_BACKEND,
) -> Fraction | bool | None:
    """The least weighted slack of the counting relaxation: a Fraction; ``False`` when no
    slack satisfies it (then no relaxation exists); ``None`` when it could not be settled."""
    counting = _Counting(inst, list(requirements), components)
    solver = open_backend(backend, optimize=True)
    solver.add(counting.decls, [(None, a) for a in counting.asserts])
    handle = solver.minimize(counting.cost())
    solver.set_timeout(timeout)
    r = solver.check()
    if r is Check.UNSAT:
        return False
    if r is not Check.SAT:
        return None
    bound = solver.bound(handle)
    return bound.value if bound.infinite == 0 else None


class _Counting:
    def __init__(self, inst: ir.Instance, reqs: list[Slackable], components: Collection[str] | None) -> None:
        self.inst = inst
        self.reqs = reqs
        self.decls: list[Symbol] = []
        self.asserts: list[str] = []
        self.slack: dict[str, str] = {}  # label → slack term (≥ 0 weakening, or a signed move)
        self.n: dict[str, Symbol] = {}
        for label, kind, _ in reqs:
            if kind == "initial value":
                up, down = self._var(f"up.{label}"), self._var(f"down.{label}")
                self.slack[label] = f"(- {up} {down})"
            else:
                self.slack[label] = self._var(f"d.{label}")
        for m in inst.morphisms.values():
            n = self.n[m.name] = self._var(f"n.{m.name}", SmtSort.INT)
            if components is not None:
                self.asserts.append(f"(>= {n} 1)" if m.name in components else f"(= {n} 0)")
            if m.uses is not None:
                self.asserts.append(f"(<= {n} {m.uses})")
        assigned = {e.resource for m in inst.morphisms.values() for e in m.effects if e.kind is ir.EffectKind.ASSIGN}
        for r in inst.resources.values():
            if r.sort.is_numeric and r.name not in assigned and r.name in inst.problem.init:
                self._resource(r)

    def _var(self, name: str, sort: SmtSort = SmtSort.REAL) -> Symbol:
        v = Symbol(name, sort)
        self.decls.append(v)
        self.asserts.append(f"(>= {v} 0)")
        return v

    def cost(self) -> str:
        parts = []
        for label, kind, weight in self.reqs:
            if kind == "initial value":
                parts += [f"(* {real_literal(weight)} up.{label})", f"(* {real_literal(weight)} down.{label})"]
            else:
                parts.append(f"(* {real_literal(weight)} d.{label})")
        return f"(+ 0.0 {' '.join(parts)})" if parts else "0.0"

    # -- one resource's state equation
    def _deltas(self, r: ir.Resource) -> dict[str, Interval]:
        """Each morphism's net change of ``r`` per firing, as an interval."""
        out: dict[str, Interval] = {}
        for m in self.inst.morphisms.values():
            params = {p.name: _param(m, p) for p in m.params}
            total = Interval(Fraction(0), Fraction(0))
            for e in m.effects:
                if e.resource != r.name:
                    continue
                v = _Eval({}, params)(e.value)
                v = v if isinstance(v, Interval) else Interval()
                if e.kind is ir.EffectKind.DECREASE:
                    v = Interval(None if v.hi is None else -v.hi, None if v.lo is None else -v.lo)
                total = Interval(
                    None if total.lo is None or v.lo is None else total.lo + v.lo,
                    None if total.hi is None or v.hi is None else total.hi + v.hi,
                )
            if total != Interval(Fraction(0), Fraction(0)):
                out[m.name] = total
        return out

    def _resource(self, r: ir.Resource) -> None:
        init = self.inst.problem.init[r.name]
        if not isinstance(init.value, ir.Const) or not isinstance(init.value.value, Fraction):
            return
        start = real_literal(init.value.value)
        if init.label in self.slack:
            start = f"(+ {start} {self.slack[init.label]})"
        deltas = self._deltas(r)
        lo_final = self._sum(start, [(m, d.lo) for m, d in deltas.items()])
        hi_final = self._sum(start, [(m, d.hi) for m, d in deltas.items()])
        highest = self._sum(start, [(m, None if d.hi is None else max(d.hi, Fraction(0))) for m, d in deltas.items()])
        lowest = self._sum(start, [(m, None if d.lo is None else min(d.lo, Fraction(0))) for m, d in deltas.items()])
        if r.lower is not None and hi_final is not None:
            self.asserts.append(f"(>= {hi_final} {real_literal(r.lower)})")
        if r.upper is not None and lo_final is not None:
            self.asserts.append(f"(<= {lo_final} {real_literal(r.upper)})")
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
        options = [f"(= (+ 0 {' '.join(self.n[m.name] for m in touching)}) 0)"]
        for m in touching:
            d = deltas.get(m.name, Interval(Fraction(0), Fraction(0)))
            assert d.lo is not None and d.hi is not None  # finite: lo_final and hi_final exist
            before_lo = f"(- {lo_final} {real_literal(d.lo)})"
            before_hi = f"(- {hi_final} {real_literal(d.hi)})"
            needs: list[str] = []
            for lit in m.pre:
                need = self._need(lit, r.name, before_lo, before_hi)
                if need is not None:
                    needs.append(need)
            options.append(f"(and (>= {self.n[m.name]} 1) {' '.join(needs) or 'true'})")
        self.asserts.append(f"(or {' '.join(options)})")

    def _sum(self, start: str, terms: list[tuple[str, Fraction | None]]) -> str | None:
        if any(c is None for _, c in terms):
            return None
        parts = [f"(* {real_literal(c)} (to_real {self.n[m]}))" for m, c in terms if c]
        return f"(+ {start} {' '.join(parts)})" if parts else start

    def _literal(self, lit: ir.Literal, name: str, low: str | None, high: str | None, fires: Symbol | None) -> None:
        """``r op c`` (either way round): the extreme value of ``r`` must reach ``c``."""
        need = self._need(lit, name, low, high)
        if need is not None:
            self.asserts.append(need if fires is None else f"(=> (>= {fires} 1) {need})")

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
        c, delta = real_literal(right.value), self.slack.get(lit.label, "0.0")
        if op in (ir.CmpOp.GE, ir.CmpOp.GT):  # (+ r δ) ≥ c: the highest value must reach c − δ
            return None if high is None else f"(>= (+ {high} {delta}) {c})"
        return None if low is None else f"(<= {low} (+ {c} {delta}))"  # r ≤ c + δ


_MIRROR = {ir.CmpOp.GE: ir.CmpOp.LE, ir.CmpOp.GT: ir.CmpOp.LT, ir.CmpOp.LE: ir.CmpOp.GE, ir.CmpOp.LT: ir.CmpOp.GT}


def _param(m: ir.Morphism, p: ir.Param) -> Value:
    v = top(p.sort)
    if isinstance(v, Interval) and (p.fixed or m.uses != 0):
        return v.meet(p.lower, p.upper)
    return v
