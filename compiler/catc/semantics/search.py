"""A forward state-space search for shortest sequential compositions: greedy best-first on a
numeric h_add for a first composition, then A* with a numeric h^max to prove it shortest.

The greedy phase (:func:`_greedy`, h_add over the conditions cut into atoms by :class:`_Atoms`,
or over literals on bitmasks; ordered first by the counting bound where the task has numeric
goal conditions) is inadmissible and claims nothing about length; its plan is shortened through
its neighbourhood (:func:`_improve`), and A* below that length (:func:`_astar`) either finds a
shorter composition or proves that there is none. The rest of this docstring is about A*.

For numeric tasks A*'s heuristic is the largest of h^max (below), a goal-achiever bound read
off h^max's layers (:meth:`_Task._achiever_bound`: a goal fact's achiever cannot fire before
its layer, and the achievers of goal facts independent of it are further steps) and an
operator-counting bound (:class:`_Counting`: a linear program over how often each morphism
fires, solved exactly), all read against the bounds every reachable state keeps — declared, or inferred from the
preconditions that guard every change of a number (:func:`infer_bounds`).

For ground instances (morphisms without parameters, as :mod:`catc.frontend.up_import` makes
them) the shortest sequential composition is found by A* over the concrete states (exact
``Fraction`` arithmetic), guided by an admissible and consistent heuristic: the number of
layers of an *interval relaxation* after which the goal can hold (h^max generalised to numbers,
as ENHSP's ``hrmax``). Layer 0 is the state itself, each resource a point (a number an
interval, a Boolean or symbol a set of possible values); layer i+1 joins into layer i the
effects of every morphism whose preconditions can hold in layer i. Every state reachable in i
steps lies within layer i, so the layer where the goal first can hold is a lower bound on the
distance to the goal, and a layer that no longer changes without the goal proves a dead end.

What the search answers, all of it a proof (the validator still replays every composition):

* a composition of L steps — the shortest (A* with an admissible heuristic, unit steps),
  unless ``shortest`` is False (the greedy composition, A* stopped by the time);
* none within the horizon k — every state within k steps was expanded or pruned by the
  heuristic (whose bound is sound);
* none of any length (``final``) — additionally no state was cut by the horizon: the
  reachable state space was exhausted (by A*, dead ends proven by the relaxation; or by the
  greedy phase, which prunes nothing).

Instances with what the search does not model (parameters, sets, holes, use limits, an
effect that assigns and increases one resource, a resource without an initial value) are
answered :attr:`SearchStatus.UNSUPPORTED`, and the caller falls back to the SMT encoding.
"""

from __future__ import annotations

import heapq
import itertools
import operator
import time
from collections.abc import Callable, Generator
from enum import Enum
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir import ArithOp, BoolOpKind, CmpOp, EffectKind, SortKind
from catc.ir.fold import arith
from catc.semantics.plan import Activation, Plan

__all__ = ["SearchResult", "SearchStatus", "search"]


class SearchStatus(str, Enum):
    PLAN = "plan"
    NONE = "none"  # no composition within the horizon (``final``: of any length)
    STOPPED = "stopped"  # the time ran out
    UNSUPPORTED = "unsupported"


class SearchResult:
    __slots__ = ("status", "plan", "final", "expanded", "reason", "length", "shortest", "first_plan")

    def __init__(
        self,
        status: SearchStatus,
        plan: Plan | None = None,
        *,
        final: bool = False,
        expanded: int = 0,
        reason: str = "",
        shortest: bool = True,
        first_plan: float | None = None,
    ) -> None:
        self.status, self.plan, self.final, self.expanded, self.reason = status, plan, final, expanded, reason
        self.length = None if plan is None else len(plan.steps)
        #: a plan is a shortest one (proven by A*); False: the greedy search's plan, no proof
        self.shortest = shortest
        #: seconds until the first plan was found (the greedy search's), None when none was
        self.first_plan = first_plan


class _Unsupported(Exception):
    pass


# ---------------------------------------------------------------- concrete terms
#
# Numbers are exact: a whole number is a Python int (much faster than a Fraction of
# denominator 1, and as exact), any other a Fraction; division always goes through Fraction.


def _num(v: Any) -> Any:
    """An int for a whole Fraction (not a bool), the value itself otherwise."""
    if isinstance(v, Fraction) and v.denominator == 1:
        return int(v.numerator)
    return v


def _arith(op: ArithOp, values: list[Any]) -> Any:
    if op is ArithOp.DIV:
        out = Fraction(values[0])
        for x in values[1:]:
            out /= x
        return _num(out)
    return _num(arith(op, [Fraction(v) for v in values]))


State = tuple[Any, ...]
Fn = Callable[[State], Any]


_CMP: dict[CmpOp, Callable[[Any, Any], Any]] = {
    CmpOp.EQ: operator.eq,
    CmpOp.LT: operator.lt,
    CmpOp.LE: operator.le,
    CmpOp.GT: operator.gt,
    CmpOp.GE: operator.ge,
}


def _concrete(e: ir.Expr, index: dict[str, int]) -> Fn:
    """``e`` as a function of the state tuple (exact values: Fraction, bool, str)."""
    if isinstance(e, ir.Const):
        v = _num(e.value)
        return lambda s: v
    if isinstance(e, ir.ResourceRef):
        i = index[e.name]
        return lambda s: s[i]
    if isinstance(e, ir.Arith):
        fs = [_concrete(a, index) for a in e.args]
        op = e.op
        if op is ArithOp.ADD and len(fs) == 2:
            a, b = fs
            return lambda s: a(s) + b(s)
        if op is ArithOp.SUB and len(fs) == 2:
            a, b = fs
            return lambda s: a(s) - b(s)
        if op is ArithOp.MUL and len(fs) == 2:
            a, b = fs
            return lambda s: a(s) * b(s)
        return lambda s: _arith(op, [f(s) for f in fs])
    if isinstance(e, ir.Compare):
        a, b = _concrete(e.left, index), _concrete(e.right, index)
        cmp = _CMP[e.op]
        return lambda s: bool(cmp(a(s), b(s)))
    if isinstance(e, ir.BoolOp):
        fs = [_concrete(a, index) for a in e.args]
        if e.op is BoolOpKind.AND:
            return lambda s: all(f(s) for f in fs)
        if e.op is BoolOpKind.OR:
            return lambda s: any(f(s) for f in fs)
        if e.op is BoolOpKind.NOT:
            (f,) = fs
            return lambda s: not f(s)
        *init, last = fs
        return lambda s: (not all(f(s) for f in init)) or last(s)
    if isinstance(e, ir.Ite):
        c, t, o = _concrete(e.cond, index), _concrete(e.then, index), _concrete(e.orelse, index)
        return lambda s: t(s) if c(s) else o(s)
    raise _Unsupported(type(e).__name__)


# ---------------------------------------------------------------- relaxed terms
#
# A relaxed value: a number → (lo, hi), None for an infinite bound; a Boolean → (can be true,
# can be false); a symbol → a frozenset of the names it may hold.

Relaxed = tuple[Any, ...]


def _shift(x: tuple[Any, Any], c: Any) -> tuple[Any, Any]:
    return (None if x[0] is None else x[0] + c, None if x[1] is None else x[1] + c)


def _lo_add(a: Fraction | None, b: Fraction | None) -> Fraction | None:
    return None if a is None or b is None else a + b


def _mul(a: tuple[Any, Any], b: tuple[Any, Any]) -> tuple[Any, Any]:
    if None in a or None in b:
        if a == (0, 0) or b == (0, 0):
            return (0, 0)
        return (None, None)
    ps = [x * y for x in a for y in b]
    return (min(ps), max(ps))


def _div(a: tuple[Any, Any], b: tuple[Any, Any]) -> tuple[Any, Any]:
    lo, hi = b
    if lo is None or hi is None or lo <= 0 <= hi or None in a:
        return (None, None)
    return _mul(a, (Fraction(1) / hi, Fraction(1) / lo))


def _arith_relaxed(op: ArithOp, args: list[tuple[Any, Any]]) -> tuple[Any, Any]:
    if op is ArithOp.ADD:
        lo: Any = 0
        hi: Any = 0
        for a_lo, a_hi in args:
            lo, hi = _lo_add(lo, a_lo), _lo_add(hi, a_hi)
        return (lo, hi)
    if op is ArithOp.SUB:
        first = args[0]
        if len(args) == 1:
            return (None if first[1] is None else -first[1], None if first[0] is None else -first[0])
        rest = _arith_relaxed(ArithOp.ADD, args[1:])
        return (
            _lo_add(first[0], None if rest[1] is None else -rest[1]),
            _lo_add(first[1], None if rest[0] is None else -rest[0]),
        )
    if op is ArithOp.MUL:
        out = args[0]
        for a in args[1:]:
            out = _mul(out, a)
        return out
    if op is ArithOp.DIV:
        out = args[0]
        for a in args[1:]:
            out = _div(out, a)
        return out
    pick = min if op is ArithOp.MIN else max
    los, his = [a[0] for a in args], [a[1] for a in args]
    if op is ArithOp.MIN:
        lo = None if None in los else pick(los)
        hi = pick(h for h in his if h is not None) if any(h is not None for h in his) else None
    else:
        lo = pick(x for x in los if x is not None) if any(x is not None for x in los) else None
        hi = None if None in his else pick(his)
    return (lo, hi)


def _lt(a: Any, b: Any) -> bool:
    """a < b for a lower end ``a`` (None: -∞) and an upper end ``b`` (None: +∞)."""
    return a is None or b is None or a < b


def _le(a: Any, b: Any) -> bool:
    return a is None or b is None or a <= b


def _compare_relaxed(op: CmpOp, a: Any, b: Any, kind: str) -> tuple[bool, bool]:
    if kind == "bool":
        t = (a[0] and b[0]) or (a[1] and b[1])
        f = (a[0] and b[1]) or (a[1] and b[0])
        return (t, f)
    if kind == "symbol":
        return (bool(a & b), not (len(a) == 1 and a == b))
    if op is CmpOp.EQ:
        t = _le(a[0], b[1]) and _le(b[0], a[1])
        f = not (a[0] is not None and a[0] == a[1] == b[0] == b[1])
        return (t, f)
    if op in (CmpOp.GT, CmpOp.GE):
        a, b = b, a
        op = CmpOp.LT if op is CmpOp.GT else CmpOp.LE
    if op is CmpOp.LT:  # a < b can hold when a.lo < b.hi; fail when a.hi >= b.lo
        return (_lt(a[0], b[1]), _le(b[0], a[1]))
    return (_le(a[0], b[1]), _lt(b[0], a[1]))  # a <= b


def _kind(sort: ir.Sort) -> str:
    if sort.kind is SortKind.BOOL:
        return "bool"
    if sort.is_numeric:
        return "number"
    if sort.kind in (SortKind.SYMBOL, SortKind.ENUM):
        return "symbol"
    raise _Unsupported(f"a {sort.kind.value} value")


def _relaxed(e: ir.Expr, index: dict[str, int]) -> Callable[[Relaxed], Any]:
    if isinstance(e, ir.Const):
        k = _kind(e.sort)
        v: Any
        if k == "bool":
            v = (bool(e.value), not e.value)
        elif k == "number":
            v = (_num(e.value), _num(e.value))
        else:
            v = frozenset({e.value})
        return lambda r: v
    if isinstance(e, ir.ResourceRef):
        i = index[e.name]
        return lambda r: r[i]
    if isinstance(e, ir.Arith):
        fs = [_relaxed(a, index) for a in e.args]
        op = e.op
        if op in (ArithOp.ADD, ArithOp.SUB) and len(e.args) == 2 and isinstance(e.args[1], ir.Const):
            x, c = fs[0], _num(e.args[1].value)  # the common x ± c, without the general case's lists
            c = c if op is ArithOp.ADD else -c
            return lambda r: _shift(x(r), c)
        return lambda r: _arith_relaxed(op, [f(r) for f in fs])
    if isinstance(e, ir.Compare):
        a, b = _relaxed(e.left, index), _relaxed(e.right, index)
        cop, kind = e.op, _kind(e.left.sort)
        if kind == "number" and cop in (CmpOp.LE, CmpOp.GE):
            lo_side, hi_side = (a, b) if cop is CmpOp.LE else (b, a)  # lo_side <= hi_side

            def le(r: Relaxed) -> tuple[bool, bool]:
                x, y = lo_side(r), hi_side(r)
                return (_le(x[0], y[1]), _lt(y[0], x[1]))

            return le
        return lambda r: _compare_relaxed(cop, a(r), b(r), kind)
    if isinstance(e, ir.BoolOp):
        fs = [_relaxed(a, index) for a in e.args]
        if e.op is BoolOpKind.AND:

            def conj(r: Relaxed) -> tuple[bool, bool]:
                vs = [f(r) for f in fs]
                return (all(v[0] for v in vs), any(v[1] for v in vs))

            return conj
        if e.op is BoolOpKind.OR:

            def disj(r: Relaxed) -> tuple[bool, bool]:
                vs = [f(r) for f in fs]
                return (any(v[0] for v in vs), all(v[1] for v in vs))

            return disj
        if e.op is BoolOpKind.NOT:
            (f,) = fs
            return lambda r: f(r)[::-1]
        *init, last = fs

        def imply(r: Relaxed) -> tuple[bool, bool]:
            vs = [f(r) for f in init]
            premise = (all(v[0] for v in vs), any(v[1] for v in vs))
            c = last(r)
            return (premise[1] or c[0], premise[0] and c[1])

        return imply
    if isinstance(e, ir.Ite):
        c, t, o = _relaxed(e.cond, index), _relaxed(e.then, index), _relaxed(e.orelse, index)
        kind = _kind(e.sort)

        def ite(r: Relaxed) -> Any:
            can_t, can_f = c(r)
            if can_t and can_f:
                return _join(t(r), o(r), kind)
            return t(r) if can_t else o(r)

        return ite
    raise _Unsupported(type(e).__name__)


def _redundant(exprs: list[ir.Expr], index: dict[str, int]) -> list[Callable[[Relaxed], tuple[bool, bool]]]:
    """Relaxed tests of the sums of two linear inequalities among the conjuncts ``exprs`` where
    a resource cancels out (as ENHSP's hrmax adds redundant constraints): x + y ≥ d and
    y − x ≥ d give 2·y ≥ 2·d, which the intervals of x and y, taken one conjunct at a time,
    do not see. Each sum is implied by the conjunction (non-strict, weaker than a strict sum),
    so testing it too keeps the relaxation an over-approximation: h^max stays admissible and
    consistent, and grows where the sum needs more layers."""
    forms: list[tuple[dict[int, Fraction], Fraction]] = []
    todo = list(exprs)
    while todo:
        e = todo.pop()
        if isinstance(e, ir.BoolOp) and e.op is BoolOpKind.AND:
            todo.extend(e.args)
            continue
        if not isinstance(e, ir.Compare) or e.op not in (CmpOp.LE, CmpOp.LT, CmpOp.GE, CmpOp.GT):
            continue
        if _kind(e.left.sort) != "number":
            continue
        left, right = _linear(e.left, index), _linear(e.right, index)
        if left is not None and right is not None:
            forms.append(_minus(right, left) if e.op in (CmpOp.LE, CmpOp.LT) else _minus(left, right))
    out = []
    for (wa, ka), (wb, kb) in itertools.combinations(forms, 2):
        w = dict(wa)
        for i, c in wb.items():
            w[i] = w.get(i, Fraction(0)) + c
        terms = [(i, _num(c)) for i, c in w.items() if c != 0]
        if terms and len(terms) < len(set(wa) | set(wb)):
            out.append(_linear_test(terms, _num(ka + kb)))
    return out


def _linear_test(terms: list[tuple[int, Any]], k: Any) -> Callable[[Relaxed], tuple[bool, bool]]:
    """Whether Σ c·x + k ≥ 0 can hold over intervals (and, not tracked, whether it can fail)."""

    def test(r: Relaxed) -> tuple[bool, bool]:
        hi = k
        for i, c in terms:
            end = r[i][1] if c > 0 else r[i][0]
            if end is None:
                return (True, True)
            hi += c * end
        return (hi >= 0, True)

    return test


def _join(a: Any, b: Any, kind: str) -> Any:
    if kind == "bool":
        return (a[0] or b[0], a[1] or b[1])
    if kind == "symbol":
        return a | b
    lo = None if a[0] is None or b[0] is None else min(a[0], b[0])
    hi = None if a[1] is None or b[1] is None else max(a[1], b[1])
    return (lo, hi)


def _point(v: Any, kind: str) -> Any:
    if kind == "bool":
        return (v, not v)
    if kind == "symbol":
        return frozenset({v})
    return (v, v)


# ---------------------------------------------------------------- the ground task


class _Action:
    __slots__ = ("name", "pre", "effects", "rpre", "reffects", "constant")

    def __init__(self, m: ir.Morphism, index: dict[str, int]) -> None:
        if m.params or m.uses is not None:
            raise _Unsupported("parameters or use limits")
        self.name = m.name
        self.pre = [_concrete(lit.expr, index) for lit in m.pre]
        self.rpre = [_relaxed(lit.expr, index) for lit in m.pre] + _redundant([lit.expr for lit in m.pre], index)
        by_res: dict[int, list[ir.Effect]] = {}
        for e in m.effects:
            if e.kind not in (EffectKind.ASSIGN, EffectKind.INCREASE, EffectKind.DECREASE):
                raise _Unsupported("a set effect")
            by_res.setdefault(index[e.resource], []).append(e)
        self.effects: list[tuple[int, str, list[tuple[int, Fn]]]] = []
        self.reffects: list[tuple[int, str, list[tuple[int, Callable[[Relaxed], Any]]]]] = []
        self.constant = True  # every effect assigns a constant: once fired, firing again adds nothing
        for i, group in by_res.items():
            assigns = [e for e in group if e.kind is EffectKind.ASSIGN]
            if assigns and len(group) > 1:
                raise _Unsupported("one resource assigned and changed by one morphism")
            mode = "assign" if assigns else "step"
            terms = [(-1 if e.kind is EffectKind.DECREASE else 1, e) for e in group]
            self.effects.append((i, mode, [(sign, _concrete(e.value, index)) for sign, e in terms]))
            self.reffects.append((i, mode, [(sign, _relaxed(e.value, index)) for sign, e in terms]))
            if mode == "step" or not isinstance(group[0].value, ir.Const):
                self.constant = False


class _Task:
    def __init__(self, inst: ir.Instance) -> None:
        from catc.semantics.validate import initial_state

        d, p = inst.domain, inst.problem
        if d.holes:
            raise _Unsupported("holes")
        self.names = list(d.resources)
        self.index = {n: i for i, n in enumerate(self.names)}
        self.kinds = [_kind(d.resources[n].sort) for n in self.names]
        self.ints = [d.resources[n].sort.kind is SortKind.INT for n in self.names]
        self.bounds = [(d.resources[n].lower, d.resources[n].upper) for n in self.names]
        self.bounded = [i for i, (lo, hi) in enumerate(self.bounds) if lo is not None or hi is not None]
        init = initial_state(inst)
        if any(n not in init for n in self.names):
            raise _Unsupported("a resource without an initial value")
        self.init: State = tuple(
            _num(Fraction(init[n])) if k == "number" else init[n]  # type: ignore[call-overload]
            for n, k in zip(self.names, self.kinds)
        )
        self.actions = [_Action(m, self.index) for m in d.morphisms.values()]
        self.goal = [_concrete(lit.expr, self.index) for lit in p.goal]
        self.rgoal = [_relaxed(lit.expr, self.index) for lit in p.goal] + _redundant(
            [lit.expr for lit in p.goal], self.index
        )
        # the declared bounds stay the validity test of a successor (``bounded``); the
        # relaxation and the counting heuristic use them narrowed by the inferred ones
        self.bounds = [
            (_tighter(lo, ilo, max), _tighter(hi, ihi, min))
            for (lo, hi), (ilo, ihi) in zip(self.bounds, infer_bounds(inst, self))
        ]
        self.counting: _Counting | None = None
        self.landmarks: Any = None
        self._achievers(inst)

    def _achievers(self, inst: ir.Instance) -> None:
        """The Boolean goal facts (``goal_facts``: resource, value), for each the morphisms
        that may make it true (``achievers``: those assigning the resource that value or a
        value that is not a constant — more than the true ones loses no soundness below) and
        its independent goal facts (``independent``) for :meth:`_achiever_bound`.

        R_g, the resources relevant to g: those the preconditions of g's achievers read,
        closed under every morphism that writes one of them (its precondition's and effects'
        reads join). A goal fact g′ ≠ g is independent of g when none of its achievers writes
        a resource of R_g and none of them is an achiever of g."""
        self.goal_facts: list[tuple[int, Any]] = []
        todo = [lit.expr for lit in inst.problem.goal]
        while todo:
            e = todo.pop()
            if isinstance(e, ir.BoolOp) and e.op is BoolOpKind.AND:
                todo.extend(e.args)
            elif isinstance(e, ir.ResourceRef) and self.kinds[self.index[e.name]] == "bool":
                self.goal_facts.append((self.index[e.name], True))
            elif (
                isinstance(e, ir.BoolOp)
                and e.op is BoolOpKind.NOT
                and isinstance(e.args[0], ir.ResourceRef)
                and self.kinds[self.index[e.args[0].name]] == "bool"
            ):
                self.goal_facts.append((self.index[e.args[0].name], False))
        self.goal_facts = list(dict.fromkeys(self.goal_facts))
        morphisms = list(inst.domain.morphisms.values())
        writes = [{self.index[e.resource] for e in m.effects} for m in morphisms]
        reads_pre = [{self.index[n] for lit in m.pre for n in _reads(lit.expr)} for m in morphisms]
        reads_all = [
            reads_pre[a] | {self.index[n] for e in m.effects for n in _reads(e.value)} for a, m in enumerate(morphisms)
        ]
        self.achievers: list[set[int]] = []
        for i, value in self.goal_facts:
            name = self.names[i]
            self.achievers.append(
                {
                    a
                    for a, m in enumerate(morphisms)
                    for e in m.effects
                    if e.resource == name
                    and e.kind is EffectKind.ASSIGN
                    and (_constant(e.value) is None or _constant(e.value) == value)
                }
            )
        self.independent: list[list[int]] = []
        for g, ach in enumerate(self.achievers):
            relevant: set[int] = set().union(*(reads_pre[a] for a in ach)) if ach else set()
            grew = True
            while grew:
                grew = False
                for a, w in enumerate(writes):
                    if w & relevant and not reads_all[a] <= relevant:
                        relevant |= reads_all[a]
                        grew = True
            self.independent.append(
                [
                    k
                    for k, other in enumerate(self.achievers)
                    if k != g and not other & ach and all(not writes[a] & relevant for a in other)
                ]
            )

    def valid(self, s: list[Any]) -> bool:
        for i in self.bounded:
            lo, hi = self.bounds[i]
            v = s[i]
            if (lo is not None and v < lo) or (hi is not None and v > hi):
                return False
        return True

    def successors(self, s: State) -> list[tuple[int, State]]:
        out = []
        for a_i, a in enumerate(self.actions):
            try:
                if not all(f(s) for f in a.pre):
                    continue
                new = list(s)
                for i, mode, terms in a.effects:
                    if mode == "assign":
                        v = terms[0][1](s)
                    else:
                        v = s[i]
                        for sign, f in terms:
                            v = v + f(s) if sign > 0 else v - f(s)
                    if isinstance(v, Fraction):
                        if self.ints[i] and v.denominator != 1:
                            raise ArithmeticError("a non-integer value for an int resource")
                        v = _num(v)
                    new[i] = v
            except ArithmeticError:  # a zero divisor: the step has no value, it cannot happen
                continue
            if self.valid(new):
                out.append((a_i, tuple(new)))
        return out

    def is_goal(self, s: State) -> bool:
        try:
            return all(f(s) for f in self.goal)
        except ArithmeticError:
            return False

    def h(self, s: State, cap: int) -> int | None:
        """The largest of three admissible bounds: h^max (:meth:`hmax`, consistent), the
        goal-achiever bound read off the same layers (:meth:`_achiever_bound`) and, where the
        task has numeric conditions, the operator-counting bound (:class:`_Counting`,
        consistent); None for a dead end any of them proves. A* needs admissibility only
        (:func:`_astar`). A fourth, ``landmarks`` (:mod:`catc.semantics.landmarks`: counting
        plus landmarks, with a case split on a gate fact), where :func:`search` builds one."""
        first: list[int] | None = [-1] * len(self.actions) if self.goal_facts else None
        h = self._hmax(s, cap, first)
        if h is None or h >= cap:
            return h
        if first is not None:
            h = min(max(h, self._achiever_bound(s, first)), cap)
        for bound in (self.counting, self.landmarks):  # landmarks: catc.semantics.landmarks
            if bound is None or h >= cap:
                continue
            c = bound.h(s)
            if c is None:
                return None
            h = min(max(h, c), cap)
        return h

    def hmax(self, s: State, cap: int) -> int | None:
        """Layers of the interval relaxation until the goal can hold: None for a proven dead
        end, ``cap`` when the goal cannot hold within ``cap - 1`` layers (and the widened
        relaxation, :meth:`_dead`, cannot prove it never will)."""
        return self._hmax(s, cap, None)

    def _hmax(self, s: State, cap: int, first: list[int] | None) -> int | None:
        """:meth:`hmax`; with ``first``, also the first layer in which each morphism may
        fire (−1: not before the goal's layer)."""
        r: list[Any] = [_point(v, k) for v, k in zip(s, self.kinds)]
        fired: set[int] = set()
        for layer in range(cap):
            rt = tuple(r)
            if all(f(rt)[0] for f in self.rgoal):
                return layer
            new = self._layer(rt, fired, first, layer)
            if new is None:
                return None
            r = new
        return None if self._dead(r) else cap

    def _achiever_bound(self, s: State, first: list[int]) -> int:
        """A lower bound on the steps from ``s`` to the goal, from its Boolean goal facts: for
        a goal fact g false in ``s``, e_g + 1 + m_g, the largest over such g (0 if none), where
        e_g is the first layer in which an achiever of g may fire (``first``, from the layers
        of :meth:`_hmax`) and m_g the number of goal facts false in ``s`` among g's independent
        ones (:meth:`_achievers`), or 1 if some two of those share an achiever.

        Admissible. Take any composition π from ``s`` to the goal and the last step t of π
        that fires an achiever a of g (g is false in ``s`` and true at the end, so there is
        one). (1) The steps before t include at least e_g steps relevant to g (writing a
        resource of R_g, :meth:`_achievers`): drop the others and the resources of R_g take the
        same values along the relevant steps — the dropped ones write none of them, and the
        relevant ones read only resources of R_g — so, by the relaxation's induction (each
        relevant step's precondition holds on values inside the current layer, its effects land
        inside the next one; a step that writes nothing of R_g keeps the values where they
        were, and layers only grow), after j relevant steps the values of R_g lie inside layer
        j; a's precondition, which reads only R_g, holds before t, so j ≥ e_g. (2) Step t
        itself. (3) Each independent goal fact g′ false in ``s`` needs a step firing one of its
        achievers; these write nothing of R_g (so they are not among (1)) and none of them
        achieves g (so none is step t); where no two of them share an achiever, the m_g facts
        need m_g distinct steps, else at least one. So π has at least e_g + 1 + m_g steps.

        Not consistent in general (a step achieving g drops g's term), so A* keeps the
        estimates admissible by other means (:func:`_astar`)."""
        best = 0
        for g, (i, value) in enumerate(self.goal_facts):
            if s[i] == value:
                continue
            e = min((first[a] for a in self.achievers[g] if first[a] >= 0), default=-1)
            if e < 0:
                continue
            unmet = [k for k in self.independent[g] if s[self.goal_facts[k][0]] != self.goal_facts[k][1]]
            m = len(unmet)
            if m > 1:
                seen: set[int] = set()
                for k in unmet:
                    if seen & self.achievers[k]:
                        m = 1
                        break
                    seen |= self.achievers[k]
            best = max(best, e + 1 + m)
        return best

    def _layer(self, rt: Relaxed, fired: set[int], first: list[int] | None = None, layer: int = 0) -> list[Any] | None:
        """The next layer: every morphism that may fire in ``rt`` applied (relaxed, joined);
        None when nothing changes (a fixpoint). With ``first``, a morphism seen to fire for
        the first time is marked with ``layer``."""
        changed = False
        new = list(rt)
        for a_i, a in enumerate(self.actions):
            if a_i in fired:
                continue
            if not all(f(rt)[0] for f in a.rpre):
                continue
            if first is not None and first[a_i] < 0:
                first[a_i] = layer
            if a.constant:
                fired.add(a_i)
            for i, mode, terms in a.reffects:
                kind = self.kinds[i]
                if mode == "assign":
                    post = terms[0][1](rt)
                else:
                    post = rt[i]
                    for sign, f in terms:
                        d = f(rt)
                        if sign < 0:
                            d = (None if d[1] is None else -d[1], None if d[0] is None else -d[0])
                        post = (_lo_add(post[0], d[0]), _lo_add(post[1], d[1]))
                post = self._cut(i, post) if kind == "number" else post
                if post is None:
                    continue
                joined = _join(new[i], post, kind)
                if joined != new[i]:
                    new[i] = joined
                    changed = True
        return new if changed else None

    def _dead(self, r: list[Any]) -> bool:
        """The goal can never hold from layer ``r``: the relaxation run to a fixpoint, each
        number bound that still moves widened to infinity (then cut by the resource's bounds),
        so that it ends; a goal that cannot hold there cannot hold in any later layer."""
        fired: set[int] = set()
        while True:  # ends: each number bound widens once, Boolean and symbol sets only grow
            rt = tuple(r)
            if all(f(rt)[0] for f in self.rgoal):
                return False
            new = self._layer(rt, fired)
            if new is None:
                return True
            for i, kind in enumerate(self.kinds):
                if kind == "number" and new[i] != rt[i]:
                    lo = None if new[i][0] != rt[i][0] else new[i][0]
                    hi = None if new[i][1] != rt[i][1] else new[i][1]
                    new[i] = self._cut(i, (lo, hi))
            r = new

    def _cut(self, i: int, v: tuple[Any, Any]) -> tuple[Any, Any] | None:
        lo, hi = self.bounds[i]
        a, b = v
        if lo is not None and (a is None or a < lo):
            a = lo
        if hi is not None and (b is None or b > hi):
            b = hi
        if a is not None and b is not None and a > b:
            return None
        return (a, b)


def _tighter(a: Any, b: Any, pick: Callable[[Any, Any], Any]) -> Any:
    return b if a is None else a if b is None else pick(a, b)


def _pre_bounds(m: ir.Morphism, index: dict[str, int], static: dict[int, Any]) -> dict[int, list[Any]]:
    """The bounds ``m``'s precondition puts on single numeric resources: each conjunct that is
    linear over one written resource (the others static, replaced by their values), as
    ``{resource: [lo, hi]}`` (None: no bound). A strict inequality gives the non-strict bound
    (weaker, still implied)."""
    out: dict[int, list[Any]] = {}
    todo = [lit.expr for lit in m.pre]
    while todo:
        e = todo.pop()
        if isinstance(e, ir.BoolOp) and e.op is BoolOpKind.AND:
            todo.extend(e.args)
            continue
        if not isinstance(e, ir.Compare) or _kind(e.left.sort) != "number":
            continue
        left, right = _linear(e.left, index), _linear(e.right, index)
        if left is None or right is None:
            continue
        forms = []
        if e.op in (CmpOp.LE, CmpOp.LT, CmpOp.EQ):
            forms.append(_minus(right, left))  # right − left ≥ 0
        if e.op in (CmpOp.GE, CmpOp.GT, CmpOp.EQ):
            forms.append(_minus(left, right))
        for w, k in forms:  # Σ w·x + k ≥ 0
            rest = {i: c for i, c in w.items() if c != 0 and i not in static}
            if len(rest) != 1:
                continue
            k_all = k + sum((c * static[i] for i, c in w.items() if i in static), Fraction(0))
            ((i, c),) = rest.items()
            b = _num(-k_all / c)
            lo_hi = out.setdefault(i, [None, None])
            if c > 0:  # x ≥ −k/c
                lo_hi[0] = _tighter(lo_hi[0], b, max)
            else:  # x ≤ −k/c
                lo_hi[1] = _tighter(lo_hi[1], b, min)
    return out


def infer_bounds(inst: ir.Instance, task: _Task) -> list[tuple[Any, Any]]:
    """Bounds (lo, hi; None: none) that every reachable state keeps on each numeric resource,
    inferred from the task where PDDL declares none (imported numbers are unbounded reals).

    For a resource x written by the morphisms M_x, with initial value v₀:

    * lo = min(v₀, every constant that a morphism of M_x assigns to x, and k − d for every
      morphism of M_x that decreases x by a constant d > 0 and whose precondition has a
      conjunct implying x ≥ k); no lo when a morphism of M_x changes x by a non-constant, or
      decreases it without such a conjunct;
    * hi symmetrically (max; increases by d > 0 under x ≤ k give k + d).

    Soundness, by induction over the steps of any execution: the initial state has x = v₀
    within [lo, hi]. A step that does not write x keeps it. A step that assigns the constant
    c leaves c, within the bounds by their definition. A step that changes x by a constant
    d ≥ 0 keeps x ≥ lo (x grows) and, if d > 0, fired from a state where its precondition held,
    so x ≤ k before and x + d ≤ k + d ≤ hi after; d ≤ 0 symmetrically. The precondition
    conjuncts are read with the other resources they mention replaced by their initial values
    only where no morphism writes those (static: the same in every state). Every reachable
    state therefore lies within the bounds, and cutting the relaxation (or the counting bound)
    by them loses no reachable state: what they prove unreachable is unreachable."""
    d = inst.domain
    index = task.index
    written = {index[e.resource] for m in d.morphisms.values() for e in m.effects}
    static = {i: v for i, v in enumerate(task.init) if task.kinds[i] == "number" and i not in written}
    lo: list[Any] = [v if k == "number" else None for v, k in zip(task.init, task.kinds)]
    hi: list[Any] = list(lo)
    pre: dict[str, dict[int, list[Any]]] = {}
    for m in d.morphisms.values():
        by_res: dict[int, list[ir.Effect]] = {}
        for e in m.effects:
            by_res.setdefault(index[e.resource], []).append(e)
        for i, group in by_res.items():
            if task.kinds[i] != "number" or (lo[i] is None and hi[i] is None):
                continue
            values = [e.value.value for e in group if isinstance(e.value, ir.Const)]
            if len(values) < len(group) or (len(group) > 1 and any(e.kind is EffectKind.ASSIGN for e in group)):
                lo[i] = hi[i] = None
                continue
            if group[0].kind is EffectKind.ASSIGN:
                v = _num(values[0])
                lo[i] = None if lo[i] is None else min(lo[i], v)
                hi[i] = None if hi[i] is None else max(hi[i], v)
                continue
            delta = Fraction(0)
            for e, c in zip(group, values):
                delta += -Fraction(c) if e.kind is EffectKind.DECREASE else Fraction(c)
            if delta == 0:
                continue
            if m.name not in pre:
                pre[m.name] = _pre_bounds(m, index, static)
            k_lo, k_hi = pre[m.name].get(i, [None, None])
            if delta < 0:
                lo[i] = None if lo[i] is None or k_lo is None else min(lo[i], _num(k_lo + delta))
            else:
                hi[i] = None if hi[i] is None or k_hi is None else max(hi[i], _num(k_hi + delta))
    return list(zip(lo, hi))


class _Counting:
    """An operator-counting lower bound (Pommerening et al. 2014, the state equation over
    numbers): the least Σ c_a over real c ≥ 0, c_a standing for how often morphism a fires on
    the way to the goal, such that the values at the end, x + Σ c_a·Δ_a (Δ_a: a's constant
    change of each numeric resource), satisfy every linear goal condition and the resources'
    bounds (declared, and inferred: :func:`infer_bounds`), and every goal fact false now has
    an achiever with c_a ≥ 1.

    Only resources every morphism changes by constants (or leaves alone) take part, so the
    counts of any composition reaching the goal are a solution: the least Σ c_a, rounded up,
    is a lower bound on its length (admissible), and an infeasible system proves a dead end.
    It is consistent: from s, a step a to s′ and a solution c′ for s′ give the solution c′ +
    e_a for s (the same values at the end; a fact false in s and true in s′ has a as an
    achiever), so h(s) ≤ h(s′) + 1.

    The least Σ c_a is read from the dual, max r·y subject to Mᵀy ≤ 1, y ≥ 0, solved by an
    exact simplex (Fractions, Bland's rule): the slacks are a feasible start, every basis on
    the way is dual feasible, so its value is a lower bound even if the pivots are capped, and
    an unbounded dual is an infeasible primal."""

    PIVOTS = 200

    def __init__(self, rows: list[tuple[list[tuple[int, Fraction]], Callable[[State], Any]]], n_actions: int) -> None:
        self.rows = rows  # (the column's non-zero entries (action, coefficient), rhs of the state)
        used = sorted({a for coeffs, _ in rows for a, _ in coeffs})
        where = {a: k for k, a in enumerate(used)}
        # the dual's constraint matrix: one row per action taking part, one column per primal row
        matrix = [[Fraction(0)] * len(rows) for _ in used]
        for j, (coeffs, _) in enumerate(rows):
            for a, c in coeffs:
                matrix[where[a]][j] += c
        self.dual = _Dual(matrix, len(rows))

    @classmethod
    def build(cls, task: _Task, atoms: _Atoms, inst: ir.Instance) -> _Counting | None:
        n_act = len(task.actions)
        deltas: list[dict[int, Fraction]] = [{} for _ in range(n_act)]
        counted = [k == "number" for k in task.kinds]
        for a_i, m in enumerate(inst.domain.morphisms.values()):
            for e in m.effects:
                i = task.index[e.resource]
                if task.kinds[i] != "number":
                    continue
                if e.kind is EffectKind.ASSIGN or not isinstance(e.value, ir.Const):
                    counted[i] = False
                    continue
                c = Fraction(e.value.value)
                deltas[a_i][i] = deltas[a_i].get(i, Fraction(0)) + (-c if e.kind is EffectKind.DECREASE else c)
        rows: list[tuple[list[tuple[int, Fraction]], Callable[[State], Any]]] = []

        def column(w: list[tuple[int, Fraction]]) -> list[tuple[int, Fraction]]:
            out = []
            for a_i in range(n_act):
                c = sum((wi * deltas[a_i].get(i, 0) for i, wi in w), Fraction(0))
                if c:
                    out.append((a_i, c))
            return out

        def rhs(w: list[tuple[int, Fraction]], k: Any) -> Callable[[State], Any]:
            return lambda s: -k - sum((wi * s[i] for i, wi in w), 0)  # Σ w·(x + Σ c·Δ) + k ≥ 0

        for atom in atoms.goal:
            what, j = atoms.kind[atom]
            if what != "linear":
                continue
            terms, k, _strict = atoms.linear[j]
            if all(counted[i] for i, _ in terms):
                rows.append((column(terms), rhs(terms, k)))
        if not rows:
            return None
        for i, (lo, hi) in enumerate(task.bounds):
            if not counted[i]:
                continue
            if lo is not None:
                rows.append((column([(i, Fraction(1))]), rhs([(i, Fraction(1))], -lo)))  # x ≥ lo
            if hi is not None:
                rows.append((column([(i, Fraction(-1))]), rhs([(i, Fraction(-1))], hi)))  # x ≤ hi
        for atom in atoms.goal:
            if atoms.kind[atom][0] != "fact":
                continue
            achievers = [(a_i, Fraction(1)) for a_i in range(n_act) if atom in atoms.adds[a_i]]
            rows.append((achievers, _unmet(dict(atoms.tests)[atom])))
        return cls(rows, n_act)

    def h(self, s: State) -> int | None:
        r = []
        for _, f in self.rows:
            try:
                r.append(Fraction(f(s)))
            except ArithmeticError:
                return 0
        if all(x <= 0 for x in r):
            return 0
        value = self.dual.solve(r, self.PIVOTS)
        if value is None:
            return None
        return int(-((-value) // 1))  # ⌈value⌉


def _unmet(test: Fn) -> Callable[[State], Any]:
    return lambda s: 0 if test(s) else 1


def _max_dual(matrix: list[list[Fraction]], r: list[Fraction], pivots: int) -> Fraction | None:
    """max r·y subject to matrix·y ≤ 1, y ≥ 0 (:class:`_Dual`, from the slack basis)."""
    return _Dual(matrix, len(r)).solve(r, pivots)


class _Dual:
    """max r·y subject to A·y ≤ 1, y ≥ 0 for one A and many r, by an exact simplex (Fractions,
    Bland's rule). The feasible region does not depend on r, so the basis the last call ended
    in is a feasible start for the next (a warm start: a state's bound differs from its
    parent's by a few pivots); every basis on the way is feasible, so the value reached after
    ``pivots`` pivots is a lower bound on the maximum; None when unbounded."""

    def __init__(self, matrix: list[list[Fraction]], n: int) -> None:
        m = len(matrix)
        self.n, self.m = n, m
        self.rows = [
            list(row) + [Fraction(int(i == k)) for k in range(m)] + [Fraction(1)] for i, row in enumerate(matrix)
        ]
        self.basis = [n + i for i in range(m)]

    def solve(self, r: list[Fraction], pivots: int) -> Fraction | None:
        n, m, rows, basis = self.n, self.m, self.rows, self.basis
        cost = list(r) + [Fraction(0)] * m
        z = [-c for c in cost] + [Fraction(0)]
        for i, b in enumerate(basis):  # the reduced costs in the kept basis: −c + Σ c_B·row
            cb = cost[b]
            if cb:
                z = [x + cb * y for x, y in zip(z, rows[i])]
        for _ in range(pivots):
            j = next((j for j in range(n + m) if z[j] < 0), None)
            if j is None:
                break
            best: tuple[Fraction, int, int] | None = None
            for i, row in enumerate(rows):
                if row[j] > 0:
                    key = (row[-1] / row[j], basis[i], i)
                    if best is None or key < best:
                        best = key
            if best is None:
                return None  # unbounded
            i = best[2]
            p = rows[i][j]
            prow = [x / p for x in rows[i]]
            rows[i] = prow
            for k, row in enumerate(rows):
                f = row[j]
                if k != i and f:
                    rows[k] = [x - f * y for x, y in zip(row, prow)]
            f = z[j]
            z = [x - f * y for x, y in zip(z, prow)]
            basis[i] = j
        return z[-1]


#: The most states the greedy phase stores before it gives way to A* (with no deadline it
#: would otherwise run as long as the horizon allows; A* also prunes proven dead ends).
GREEDY_STATES = 200_000

_FAR = 1 << 40  # "not reached" in h_add: larger than any sum of reached costs


def _linear(e: ir.Expr, index: dict[str, int]) -> tuple[dict[int, Fraction], Fraction] | None:
    """``e`` as Σ w·x + k over numeric resources, or None when it is not linear."""
    if isinstance(e, ir.Const) and isinstance(e.value, Fraction):
        return {}, e.value
    if isinstance(e, ir.ResourceRef) and e.name in index:
        return {index[e.name]: Fraction(1)}, Fraction(0)
    if isinstance(e, ir.Arith) and e.op in (ArithOp.ADD, ArithOp.SUB, ArithOp.MUL):
        parts = [_linear(a, index) for a in e.args]
        if any(x is None for x in parts):
            return None
        if e.op is ArithOp.MUL:
            w: dict[int, Fraction] = {}
            k = Fraction(1)
            for x in parts:
                assert x is not None
                if x[0] and w:
                    return None  # a product of two resources
                if x[0]:
                    w = {i: c * k for i, c in x[0].items()}
                    k = k * x[1]
                else:
                    w = {i: c * x[1] for i, c in w.items()}
                    k = k * x[1]
            return w, k
        first = parts[0]
        assert first is not None
        w, k = dict(first[0]), first[1]
        if e.op is ArithOp.SUB and len(parts) == 1:
            return {i: -c for i, c in w.items()}, -k
        sign = 1 if e.op is ArithOp.ADD else -1
        for x in parts[1:]:
            assert x is not None
            for i, c in x[0].items():
                w[i] = w.get(i, Fraction(0)) + sign * c
            k += sign * x[1]
        return w, k
    return None


class _Atoms:
    """The conditions of a numeric task cut into atoms for h_add: a literal (a resource holds
    a value), a linear condition Σ w·x + k ≥ 0 (> 0 when strict), or anything else (tested
    on the state; made true, in the relaxation, by any morphism that writes what it reads)."""

    def __init__(self, task: _Task, inst: ir.Instance) -> None:
        self.task = task
        self.facts: dict[tuple[int, Any], int] = {}
        self.linear: list[tuple[list[tuple[int, Fraction]], Fraction, bool]] = []
        self.tests: list[tuple[int, Fn]] = []  # (atom, holds in a state)
        self.kind: list[tuple[str, int]] = []  # atom → ("fact", fact) | ("linear", j) | ("other", reads)
        self.reads: list[frozenset[int]] = []
        d = inst.domain
        self.pre = [self.of([lit.expr for lit in m.pre]) for m in d.morphisms.values()]
        self.goal = self.of([lit.expr for lit in inst.problem.goal])
        n = len(self.kind)
        # achievers: morphism → atoms it makes true (facts, others); linear atoms by rate
        self.adds: list[list[int]] = [[] for _ in task.actions]
        self.rates: list[list[tuple[int, int, Fraction]]] = [[] for _ in task.actions]  # (atom, linear j, rate)
        self.varying: list[int] = []  # morphisms whose change of a number depends on the state
        by_fact = {f: a for f, a in self.facts.items()}
        for a_i, m in enumerate(d.morphisms.values()):
            writes: set[int] = set()
            deltas: dict[int, Fraction] = {}
            state_dependent = False
            for e in m.effects:
                i = task.index[e.resource]
                writes.add(i)
                if task.kinds[i] == "number":
                    if e.kind is not EffectKind.ASSIGN and isinstance(e.value, ir.Const):
                        c = Fraction(e.value.value)
                        deltas[i] = deltas.get(i, Fraction(0)) + (c if e.kind is EffectKind.INCREASE else -c)
                    else:
                        state_dependent = True
                elif e.kind is EffectKind.ASSIGN:
                    value = e.value.value if isinstance(e.value, ir.Const) else _constant(e.value)
                    atom = by_fact.get((i, value)) if value is not None else None
                    if atom is not None:
                        self.adds[a_i].append(atom)
            for atom in range(n):
                what, j = self.kind[atom]
                other = what == "other" and bool(self.reads[atom] & writes)
                if other or (what == "fact" and value_unknown(m, task, atom, self)):
                    self.adds[a_i].append(atom)
            if state_dependent:
                self.varying.append(a_i)
            else:
                for atom in range(n):
                    what, j = self.kind[atom]
                    if what == "linear":
                        w = self.linear[j][0]
                        rate = sum((c * deltas.get(i, 0) for i, c in w), Fraction(0))
                        if rate > 0:
                            self.rates[a_i].append((atom, j, rate))
        self.writes_numbers = {
            a_i: {task.index[e.resource] for e in m.effects if task.kinds[task.index[e.resource]] == "number"}
            for a_i, m in enumerate(d.morphisms.values())
        }

    def of(self, exprs: list[ir.Expr]) -> list[int]:
        out: list[int] = []
        todo = list(reversed(exprs))
        while todo:
            e = todo.pop()
            if isinstance(e, ir.BoolOp) and e.op is BoolOpKind.AND:
                todo.extend(reversed(e.args))
                continue
            out.extend(self._atom(e))
        return out

    def _new(self, kind: tuple[str, int], reads: frozenset[int]) -> int:
        self.kind.append(kind)
        self.reads.append(reads)
        return len(self.kind) - 1

    def _atom(self, e: ir.Expr) -> list[int]:
        task = self.task
        fact: tuple[int, Any] | None = None
        if isinstance(e, ir.ResourceRef) and task.kinds[task.index[e.name]] == "bool":
            fact = (task.index[e.name], True)
        elif (
            isinstance(e, ir.BoolOp)
            and e.op is BoolOpKind.NOT
            and isinstance(e.args[0], ir.ResourceRef)
            and task.kinds[task.index[e.args[0].name]] == "bool"
        ):
            fact = (task.index[e.args[0].name], False)
        elif isinstance(e, ir.Compare) and e.op is CmpOp.EQ and _kind(e.left.sort) == "symbol":
            ref, c = (e.left, e.right) if isinstance(e.left, ir.ResourceRef) else (e.right, e.left)
            if isinstance(ref, ir.ResourceRef) and isinstance(c, ir.Const):
                fact = (task.index[ref.name], c.value)
        if fact is not None:
            if fact not in self.facts:
                self.facts[fact] = self._new(("fact", len(self.facts)), frozenset({fact[0]}))
                i, v = fact
                self.tests.append((self.facts[fact], _holds(i, v)))
            return [self.facts[fact]]
        if isinstance(e, ir.Compare) and _kind(e.left.sort) == "number":
            left, right = _linear(e.left, task.index), _linear(e.right, task.index)
            if left is not None and right is not None:
                forms = []
                diff = _minus(right, left)  # right − left
                if e.op in (CmpOp.LE, CmpOp.LT):
                    forms.append((diff, e.op is CmpOp.LT))
                elif e.op in (CmpOp.GE, CmpOp.GT):
                    forms.append((_minus(left, right), e.op is CmpOp.GT))
                else:
                    forms += [(diff, False), (_minus(left, right), False)]
                out = []
                for (w, k), strict in forms:
                    terms = [(i, c) for i, c in w.items() if c != 0]
                    self.linear.append((terms, k, strict))
                    out.append(self._new(("linear", len(self.linear) - 1), frozenset(i for i, _ in terms)))
                return out
        atom = self._new(("other", 0), frozenset(task.index[n] for n in _reads(e)))
        self.tests.append((atom, _concrete(e, task.index)))
        return [atom]

    def hadd(self, s: State) -> int:
        cost: list[Any] = [_FAR] * len(self.kind)
        values = []
        for terms, k, _strict in self.linear:
            v: Any = k
            for i, w in terms:
                v += w * s[i]
            values.append(v)
        for atom, (what, j) in enumerate(self.kind):
            if what == "linear":
                v = values[j]
                if v > 0 or (v == 0 and not self.linear[j][2]):
                    cost[atom] = 0
        for atom, test in self.tests:
            try:
                if test(s):
                    cost[atom] = 0
            except ArithmeticError:
                pass
        rates = self.rates
        if self.varying:  # the change of a number in this state
            rates = list(rates)
            for a_i in self.varying:
                rates[a_i] = self._rates_at(a_i, s)
        changed = True
        while changed:
            changed = False
            for a_i, pre in enumerate(self.pre):
                c = 1
                for q in pre:
                    c += cost[q]
                if c >= _FAR:
                    continue
                for q in self.adds[a_i]:
                    if c < cost[q]:
                        cost[q] = c
                        changed = True
                for q, j, rate in rates[a_i]:
                    if cost[q] == 0:
                        continue
                    need = -values[j]
                    reps = need // rate + 1 if self.linear[j][2] else -(-need // rate)
                    r = c - 1 + max(int(reps), 1)
                    if r < cost[q]:
                        cost[q] = r
                        changed = True
        return int(min(sum(cost[q] for q in self.goal), _FAR))

    def _rates_at(self, a_i: int, s: State) -> list[tuple[int, int, Fraction]]:
        a = self.task.actions[a_i]
        deltas: dict[int, Any] = {}
        try:
            for i, mode, terms in a.effects:
                if self.task.kinds[i] != "number":
                    continue
                if mode == "assign":
                    deltas[i] = terms[0][1](s) - s[i]
                else:
                    deltas[i] = sum((sign * f(s) for sign, f in terms), 0)
        except ArithmeticError:
            return []
        out = []
        for atom, (what, j) in enumerate(self.kind):
            if what == "linear":
                rate = sum((c * deltas.get(i, 0) for i, c in self.linear[j][0]), Fraction(0))
                if rate > 0:
                    out.append((atom, j, rate))
        return out


def _holds(i: int, v: Any) -> Fn:
    return lambda s: s[i] == v


def value_unknown(m: ir.Morphism, task: _Task, atom: int, atoms: _Atoms) -> bool:
    """``m`` writes the fact's resource with a value that is not a constant (any value then)."""
    (i,) = atoms.reads[atom]
    name = task.names[i]
    return any(
        e.resource == name
        and e.kind is EffectKind.ASSIGN
        and not isinstance(e.value, ir.Const)
        and _constant(e.value) is None
        for e in m.effects
    )


def _minus(
    a: tuple[dict[int, Fraction], Fraction], b: tuple[dict[int, Fraction], Fraction]
) -> tuple[dict[int, Fraction], Fraction]:
    w = dict(a[0])
    for i, c in b[0].items():
        w[i] = w.get(i, Fraction(0)) - c
    return w, a[1] - b[1]


def _reads(e: ir.Expr) -> set[str]:
    out: set[str] = set()
    todo = [e]
    while todo:
        x = todo.pop()
        if isinstance(x, ir.ResourceRef):
            out.add(x.name)
        elif isinstance(x, (ir.Arith, ir.BoolOp)):
            todo.extend(x.args)
        elif isinstance(x, ir.Compare):
            todo += [x.left, x.right]
        elif isinstance(x, ir.Ite):
            todo += [x.cond, x.then, x.orelse]
    return out


def _constant(e: ir.Expr) -> bool | None:
    """The Boolean constant ``e`` folds to (UP's add-after-delete gives ``true ∨ …``), else None."""
    from catc.ir.fold import FoldError, fold_constant

    try:
        v = fold_constant(e)
    except FoldError:
        return None
    return v.value if isinstance(v, ir.Const) and isinstance(v.value, bool) else None


class _Strips:
    """A task of Boolean resources only, whose preconditions and goal are conjunctions of
    literals and whose effects assign constants (as imported classical PDDL is): a state is an
    int bitmask, a morphism four masks, and the relaxation two masks (may be true, may be
    false) — the same search, much faster per state."""

    def __init__(self, inst: ir.Instance) -> None:
        from catc.semantics.validate import initial_state

        d, p = inst.domain, inst.problem
        if d.holes or any(r.sort.kind is not SortKind.BOOL for r in d.resources.values()):
            raise _Unsupported("not Boolean resources only")
        self.bit = {n: 1 << i for i, n in enumerate(d.resources)}
        self.full = (1 << len(self.bit)) - 1
        init = initial_state(inst)
        self.init = sum(b for n, b in self.bit.items() if init.get(n) is True)
        self.names: list[str] = []
        self.masks: list[tuple[int, int, int, int]] = []
        for m in d.morphisms.values():
            if m.params or m.uses is not None:
                raise _Unsupported("parameters or use limits")
            lits = self._literals([lit.expr for lit in m.pre])
            if lits is None:
                continue  # a precondition that never holds: the morphism never fires
            add = dele = 0
            for e in m.effects:
                value = _constant(e.value) if e.kind is EffectKind.ASSIGN else None
                if value is None:
                    raise _Unsupported("an effect that is not a constant assignment")
                if value is True:
                    add |= self.bit[e.resource]
                else:
                    dele |= self.bit[e.resource]
            self.names.append(m.name)
            self.masks.append((lits[0], lits[1], add, dele))
        goal = self._literals([lit.expr for lit in p.goal])
        self.goal = goal if goal is not None else (self.full, self.full)  # never: both true and false

    def _literals(self, exprs: list[ir.Expr]) -> tuple[int, int] | None:
        """(must be true, must be false) masks of a conjunction; None when it is false."""
        pos = neg = 0
        todo = list(exprs)
        while todo:
            e = todo.pop()
            if isinstance(e, ir.ResourceRef):
                pos |= self.bit[e.name]
            elif isinstance(e, ir.BoolOp) and e.op is BoolOpKind.NOT and isinstance(e.args[0], ir.ResourceRef):
                neg |= self.bit[e.args[0].name]
            elif isinstance(e, ir.BoolOp) and e.op is BoolOpKind.AND:
                todo.extend(e.args)
            elif isinstance(e, ir.Const) and isinstance(e.value, bool):
                if not e.value:
                    return None
            else:
                raise _Unsupported("a condition that is not a conjunction of literals")
        return (pos, neg) if not pos & neg else None

    def successors(self, s: int) -> list[tuple[int, int]]:
        out = []
        for i, (pp, pn, add, dele) in enumerate(self.masks):
            if s & pp == pp and not s & pn:
                out.append((i, (s & ~dele) | add))
        return out

    def is_goal(self, s: int) -> bool:
        gp, gn = self.goal
        return s & gp == gp and not s & gn

    def h(self, s: int, cap: int) -> int | None:
        t, f = s, ~s & self.full
        gp, gn = self.goal
        todo = self.masks
        for layer in range(cap):
            if t & gp == gp and f & gn == gn:
                return layer
            nt, nf, rest = t, f, []
            for mask in todo:
                pp, pn, add, dele = mask
                if t & pp == pp and f & pn == pn:
                    nt |= add
                    nf |= dele
                else:
                    rest.append(mask)
            if nt == t and nf == f:
                return None
            t, f, todo = nt, nf, rest
        return cap

    def hadd(self, s: int) -> int:
        """h_add (inadmissible, for the greedy search): each literal's cost the cheapest
        morphism that makes it true plus the sum of that morphism's precondition costs;
        the goal's, the sum of its literals'. A literal no morphism reaches costs ``_FAR``."""
        n = len(self.bit)
        cost = [_FAR] * (2 * n)  # literal i: resource i true; n + i: false
        for i in range(n):
            cost[i if s >> i & 1 else n + i] = 0
        acts = self._hadd_acts()
        changed = True
        while changed:
            changed = False
            for pre, eff in acts:
                c = 1
                for q in pre:
                    c += cost[q]
                if c >= _FAR:
                    continue
                for q in eff:
                    if c < cost[q]:
                        cost[q] = c
                        changed = True
        return min(sum(cost[q] for q in self._goal_lits), _FAR)

    def _hadd_acts(self) -> list[tuple[list[int], list[int]]]:
        acts = getattr(self, "_acts", None)
        if acts is None:
            n = len(self.bit)

            def lits(pos: int, neg: int) -> list[int]:
                return [i for i in range(n) if pos >> i & 1] + [n + i for i in range(n) if neg >> i & 1]

            acts = [(lits(pp, pn), lits(add, dele)) for pp, pn, add, dele in self.masks]
            self._acts = acts
            self._goal_lits = lits(*self.goal)
        return acts


def _inline_statics(inst: ir.Instance) -> ir.Instance:
    """``inst`` with every numeric resource that no morphism writes replaced, in the
    preconditions, effects and goal, by its initial value, and the constant parts folded (the
    same states, steps and goal: such a resource holds its initial value in every state). A
    PDDL function that only the initial state sets (hydropower's ``value``, sailing's ``d``,
    counters' ``max_int``) becomes a constant, so a change by it is a constant change (h_add's
    rates, the counting bound, the bounds inferred from guards) and the relaxation evaluates
    less. Constant subexpressions are folded whether or not there is such a resource (UP's
    import leaves ``(* 1.05 1)``). ``inst`` itself where folding fails (a zero divisor)."""
    import dataclasses

    from catc.ir.fold import FoldError, fold
    from catc.semantics.validate import initial_state

    d, p = inst.domain, inst.problem
    written = {e.resource for m in d.morphisms.values() for e in m.effects}
    init = initial_state(inst)
    static = {
        n: ir.Const(Fraction(init[n]), r.sort)  # type: ignore[call-overload]
        for n, r in d.resources.items()
        if _kind(r.sort) == "number" and n not in written and n in init
    }

    def sub(e: ir.Expr) -> ir.Expr:
        if isinstance(e, ir.ResourceRef):
            return static.get(e.name, e)
        if isinstance(e, ir.Arith):
            return ir.Arith(e.op, tuple(sub(a) for a in e.args), e.sort, e.span)
        if isinstance(e, ir.Compare):
            return ir.Compare(e.op, sub(e.left), sub(e.right), e.span)
        if isinstance(e, ir.BoolOp):
            return ir.BoolOp(e.op, tuple(sub(a) for a in e.args), e.span)
        if isinstance(e, ir.Ite):
            return ir.Ite(sub(e.cond), sub(e.then), sub(e.orelse), e.sort, e.span)
        return e

    try:
        morphisms = {
            name: dataclasses.replace(
                m,
                pre=tuple(dataclasses.replace(lit, expr=fold(sub(lit.expr))) for lit in m.pre),
                effects=tuple(dataclasses.replace(e, value=fold(sub(e.value))) for e in m.effects),
            )
            for name, m in d.morphisms.items()
        }
        goal = tuple(dataclasses.replace(lit, expr=fold(sub(lit.expr))) for lit in p.goal)
    except FoldError:
        return inst
    return ir.Instance(dataclasses.replace(d, morphisms=morphisms), dataclasses.replace(p, goal=goal), inst.view)


def search(
    inst: ir.Instance,
    horizon: int,
    *,
    deadline: float | None = None,
    greedy: bool = True,
    prove: bool = True,
) -> SearchResult:
    """A composition of at most ``horizon`` steps, or a proof that there is none; ``deadline``
    is a ``time.monotonic()`` instant.

    With ``greedy`` a greedy best-first search guided by h_add looks for a composition (fast,
    not necessarily shortest) taking turns with A* (with ``prove``); if A* answers first, its
    answer is the answer; if the greedy search does, A* goes on below its composition's length,
    and when it finds none shorter the greedy one is proven shortest. When the time runs out
    first the greedy composition is the answer, ``shortest`` False.
    Without ``greedy``, A* alone (the shortest composition); without ``prove``, the greedy
    search alone (A* only when it found nothing)."""
    task: Any
    try:
        task = _Strips(inst)
    except _Unsupported:
        try:
            inst = _inline_statics(inst)
            task = _Task(inst)
        except _Unsupported as why:
            return SearchResult(SearchStatus.UNSUPPORTED, reason=str(why))
    atoms = None if isinstance(task, _Strips) else _Atoms(task, inst)
    if atoms is not None:
        task.counting = _Counting.build(task, atoms, inst)
        from catc.semantics.landmarks import LandmarkCounting

        task.landmarks = LandmarkCounting.build(task, atoms, inst)
    t0 = time.monotonic()
    h0 = task.h(task.init, horizon + 1)
    if h0 is None:
        return SearchResult(SearchStatus.NONE, final=True, reason="a dead end from the initial state")
    if h0 > horizon:
        return SearchResult(SearchStatus.NONE, reason=f"no composition within {horizon} steps (h^max)")
    if not greedy:
        return _astar(task, horizon, deadline)
    hadd: Callable[[Any], Any] = task.hadd if atoms is None else atoms.hadd
    if atoms is not None and task.counting is not None:
        hadd = _counting_first(task.counting, atoms.hadd)
    if not prove:
        bound = [horizon]
        found = _greedy(task, hadd, horizon, deadline)
        return _after_greedy(task, found, _astar_run(task, horizon, deadline, bound), bound, deadline, t0, prove)
    # the greedy search and A* take turns (SLICE expansions each) until one of them answers:
    # A* on its own finds the shortest composition where the greedy search's order misleads
    # it (hydropower: h_add prefers selling at any hour); a greedy plan first lowers A*'s
    # bound to one below its length, so that A* only has to prove nothing shorter exists
    bound = [horizon]
    greedy_run, astar_run = _greedy_run(task, hadd, horizon, deadline), _astar_run(task, horizon, deadline, bound)
    while True:
        try:
            next(greedy_run)
        except StopIteration as done:
            return _after_greedy(task, done.value, astar_run, bound, deadline, t0, prove)
        try:
            next(astar_run)
        except StopIteration as done:  # A* answered first: the shortest composition, or a proof of none
            better: SearchResult = done.value
            if better.status is SearchStatus.PLAN:
                better.first_plan = time.monotonic() - t0
            return better


def _after_greedy(
    task: Any, found: SearchResult, astar_run: Run, bound: list[int], deadline: float | None, t0: float, prove: bool
) -> SearchResult:
    """The answer once the greedy search has answered (``found``): A* (``astar_run``, under
    ``bound``) to its end where the greedy search has no plan and no proof; the greedy plan,
    shortened through its neighbourhood, and with ``prove`` A* below its length."""
    if found.status is SearchStatus.NONE and found.final:
        return found  # every reachable state seen, none cut by the horizon
    if found.status is not SearchStatus.PLAN:
        r = _finish(astar_run)
        r.expanded += found.expanded
        if r.status is SearchStatus.PLAN:
            r.first_plan = time.monotonic() - t0
        return r
    assert found.plan is not None
    found.first_plan = time.monotonic() - t0
    if len(found.plan.steps) > 1:
        until = None if deadline is None else time.monotonic() + (deadline - time.monotonic()) / 4
        found.plan = _improve(task, found.plan, until)
        found.length = len(found.plan.steps)
    length = len(found.plan.steps)
    if length == 0:
        return found
    if not prove:
        found.shortest = False
        found.reason = "the greedy search's composition (no proof that it is shortest was sought)"
        return found
    bound[0] = min(bound[0], length - 1)  # a shorter one, or a proof that there is none
    better = _finish(astar_run)
    better.expanded += found.expanded
    if better.status is SearchStatus.PLAN:
        better.first_plan = found.first_plan
        return better
    if better.status is SearchStatus.NONE:
        found.reason = f"no composition within {length - 1} steps (A*)"
        return found
    found.shortest = False
    found.reason = (
        f"not proven shortest: A* found no shorter composition before the time ran out ({better.expanded} states)"
    )
    return found


def _counting_first(counting: _Counting, hadd: Callable[[State], int]) -> Callable[[State], tuple[int, int]]:
    """The greedy search's order where the task has numeric goal conditions: the counting
    bound first (h_add counts a worker moved once per condition it helps, and plateaus where
    many moves are needed; the bound sees them all at once), h_add to break its ties. A dead
    end the bound proves goes last (not dropped: the greedy search's exhaustion stays a proof)."""

    def key(s: State) -> tuple[int, int]:
        c = counting.h(s)
        return (_FAR if c is None else c, hadd(s))

    return key


#: Expansions between two turns of the interleaved searches (:func:`search`).
SLICE = 16

Run = Generator[None, None, SearchResult]


def _finish(run: Run) -> SearchResult:
    """Drive a search to its end (its result)."""
    while True:
        try:
            next(run)
        except StopIteration as done:
            return done.value  # type: ignore[no-any-return]


def _greedy(task: Any, hadd: Callable[[Any], Any], horizon: int, deadline: float | None) -> SearchResult:
    """:func:`_greedy_run` to its end."""
    return _finish(_greedy_run(task, hadd, horizon, deadline))


def _greedy_run(task: Any, hadd: Callable[[Any], Any], horizon: int, deadline: float | None) -> Run:
    """Greedy best-first search on h_add (ties: the state generated first), every state once;
    the goal tested when a state is generated. Exhausting the states without cutting any at
    the horizon proves that there is no composition. A generator: it yields every ``SLICE``
    expansions (a turn of :func:`search`'s interleaving) and returns its result."""
    start = task.init
    if task.is_goal(start):
        return SearchResult(SearchStatus.PLAN, Plan([]))
    g_of: dict[Any, int] = {start: 0}
    parent: dict[Any, tuple[Any, int] | None] = {start: None}
    tie = itertools.count()
    heap: list[tuple[Any, int, Any]] = [(hadd(start), next(tie), start)]
    expanded = 0
    cut = False
    while heap:
        _, _, s = heapq.heappop(heap)
        expanded += 1
        if expanded % SLICE == 0:
            yield
        if len(g_of) > GREEDY_STATES or (deadline is not None and expanded % 64 == 0 and time.monotonic() >= deadline):
            return SearchResult(SearchStatus.STOPPED, expanded=expanded, reason="the greedy search's share")
        g2 = g_of[s] + 1
        for a_i, t in task.successors(s):
            if t in g_of:
                continue
            if g2 > horizon:
                cut = True
                continue
            g_of[t] = g2
            parent[t] = (s, a_i)
            if task.is_goal(t):
                return SearchResult(SearchStatus.PLAN, _plan(task, parent, t), expanded=expanded)
            heapq.heappush(heap, (hadd(t), next(tie), t))
    if cut:
        return SearchResult(SearchStatus.NONE, expanded=expanded, reason=f"no composition within {horizon} steps")
    return SearchResult(
        SearchStatus.NONE, final=True, expanded=expanded, reason=f"every reachable state ({len(g_of)}) was expanded"
    )


def _astar(task: Any, horizon: int, deadline: float | None) -> SearchResult:
    """:func:`_astar_run` to its end."""
    return _finish(_astar_run(task, horizon, deadline, [horizon]))


def _astar_run(task: Any, horizon: int, deadline: float | None, bound: list[int]) -> Run:
    """A* for the shortest composition of at most ``bound[0]`` (≤ ``horizon``) steps (module
    docstring). ``bound`` may be lowered while it runs (a composition of ``bound[0] + 1`` steps
    found meanwhile, :func:`search`): states beyond it are cut from then on, and once the least
    f in the queue exceeds it there is none within ``bound[0]`` (every f is a lower bound). A
    generator: it yields every ``SLICE`` expansions and returns its result."""
    start = task.init
    cap = horizon + 1
    h0 = task.h(start, cap)
    if h0 is None:
        return SearchResult(SearchStatus.NONE, final=True, reason="a dead end from the initial state")
    cut = h0 > horizon  # some state was cut by the horizon: no proof for longer plans
    if cut:
        return SearchResult(SearchStatus.NONE, reason=f"no composition within {horizon} steps (h^max)")
    # lazy A*: a state enters the queue with its parent's h − 1 and is evaluated only when it
    # comes out; if its f then grows it goes back in. Most generated states are never
    # evaluated. The heuristic need only be admissible: h(parent) ≤ h*(parent) ≤ 1 + h*(t)
    # for every successor t, so the estimate h(parent) − 1 is admissible for t too; every f in
    # the queue is a lower bound, a state reached more cheaply is queued again (no closed
    # set), and a goal comes out at its g (its estimate ≤ h* = 0): the first is shortest.
    g_of: dict[Any, int] = {start: 0}
    parent: dict[Any, tuple[Any, int] | None] = {start: None}
    tie = itertools.count()
    heap: list[tuple[int, int, int, int, Any, bool]] = [(h0, h0, next(tie), 0, start, True)]
    expanded = alive = 0
    while heap:
        f, h, _, g, s, evaluated = heapq.heappop(heap)
        if f > bound[0]:  # every entry left has f > bound: no composition within it
            return SearchResult(SearchStatus.NONE, expanded=expanded, reason=f"no composition within {bound[0]} steps")
        if g > g_of[s]:
            continue  # a stale entry: s was reached more cheaply since
        if not evaluated:
            h2 = task.h(s, cap - g)
            if h2 is None:
                continue  # a proven dead end
            if g + h2 > bound[0]:
                cut = True
                continue
            alive += 1
            if g + h2 > f:
                heapq.heappush(heap, (g + h2, h2, next(tie), g, s, True))
                continue
            h = h2
        elif s is start:
            alive += 1
        if task.is_goal(s):
            return SearchResult(SearchStatus.PLAN, _plan(task, parent, s), expanded=expanded)
        expanded += 1
        if expanded % SLICE == 0:
            yield
        if deadline is not None and time.monotonic() >= deadline:
            return SearchResult(SearchStatus.STOPPED, expanded=expanded, reason="timeout")
        g2, est = g + 1, max(h - 1, 0)
        for a_i, t in task.successors(s):
            old = g_of.get(t)
            if old is not None and old <= g2:
                continue
            g_of[t] = g2
            parent[t] = (s, a_i)
            heapq.heappush(heap, (g2 + est, est, next(tie), g2, t, False))
    if cut:
        return SearchResult(SearchStatus.NONE, expanded=expanded, reason=f"no composition within {bound[0]} steps")
    return SearchResult(
        SearchStatus.NONE,
        final=True,
        expanded=expanded,
        reason=f"every reachable state not proven a dead end ({alive}) was expanded",
    )


#: The most states the plan's neighbourhood (:func:`_improve`) may hold, and how many depths
#: past the last one that shortened the plan it tries.
NEIGHBOURHOOD_STATES = 100_000
IMPROVE_DEPTHS = 2


def _improve(task: Any, plan: Plan, deadline: float | None) -> Plan:
    """A shorter plan through the plan's neighbourhood (plan neighbourhood graph search,
    Nakhost & Müller 2010): the states within d steps of a state of the plan, d = 1, 2, …,
    searched breadth-first from the initial state for a goal state; a shorter plan found
    becomes the plan, and its neighbourhood is searched again. Every plan it returns is a path
    of successors from the initial state to a goal state (the validator replays it all the
    same). Stops at the deadline or when a neighbourhood outgrows ``NEIGHBOURHOOD_STATES``,
    keeping the best plan so far, or after ``IMPROVE_DEPTHS`` depths in a row found nothing
    shorter; it claims nothing about length."""
    by_name = {n: i for i, n in enumerate(_action_names(task))}
    steps = [by_name[step[0].morphism] for step in plan.steps]
    depth = last = 1
    while depth < last + IMPROVE_DEPTHS:
        states = [task.init]
        for a_i in steps:
            states.append(next(t for b, t in task.successors(states[-1]) if b == a_i))
        succ: dict[Any, list[tuple[int, Any]]] = {}
        frontier = list(dict.fromkeys(states))
        nodes = set(frontier)
        for d in range(depth + 1):
            nxt = []
            for s in frontier:
                if deadline is not None and time.monotonic() >= deadline:
                    return _as_plan(task, steps)
                succ[s] = task.successors(s)
                if d < depth:
                    for _, t in succ[s]:
                        if t not in nodes:
                            nodes.add(t)
                            nxt.append(t)
            if len(nodes) > NEIGHBOURHOOD_STATES:
                return _as_plan(task, steps)
            frontier = nxt
        better = _bfs(task, succ, nodes, len(steps) - 1)
        if better is not None:
            steps, last = better, depth
        else:
            depth += 1
    return _as_plan(task, steps)


def _bfs(task: Any, succ: dict[Any, list[tuple[int, Any]]], nodes: set[Any], limit: int) -> list[int] | None:
    """A shortest path of at most ``limit`` steps from the initial state to a goal state within
    ``nodes``, as action indices; None when there is none."""
    parent: dict[Any, tuple[Any, int] | None] = {task.init: None}
    layer = [task.init]
    for _ in range(limit):
        nxt = []
        for s in layer:
            for a_i, t in succ.get(s, ()):
                if t in nodes and t not in parent:
                    parent[t] = (s, a_i)
                    if task.is_goal(t):
                        out = []
                        link = parent[t]
                        while link is not None:
                            out.append(link[1])
                            link = parent[link[0]]
                        return out[::-1]
                    nxt.append(t)
        layer = nxt
    return None


def _action_names(task: Any) -> list[str]:
    return task.names if isinstance(task, _Strips) else [a.name for a in task.actions]


def _as_plan(task: Any, steps: list[int]) -> Plan:
    names = _action_names(task)
    return Plan([(Activation(names[a_i]),) for a_i in steps])


def _plan(task: Any, parent: dict[Any, tuple[Any, int] | None], s: Any) -> Plan:
    names = []
    link = parent[s]
    while link is not None:
        prev, a_i = link
        names.append(task.names[a_i] if isinstance(task, _Strips) else task.actions[a_i].name)
        link = parent[prev]
    return Plan([(Activation(n),) for n in reversed(names)])


def reachable_states(inst: ir.Instance, limit: int) -> tuple[list[str], list[tuple[Any, ...]]] | None:
    """Every state sequential compositions of any length reach (breadth first over the
    concrete step of :class:`_Task`), as the resource names and one value tuple per state:
    a certificate's invariant (issue 31). None when the search does not model the instance,
    a goal state is reachable, or there are more than ``limit`` states."""
    try:
        task = _Task(inst)
    except _Unsupported:
        return None
    seen: dict[Any, None] = {task.init: None}
    todo = [task.init]
    while todo:
        s = todo.pop()
        if task.is_goal(s):
            return None
        for _, t in task.successors(s):
            if t not in seen:
                if len(seen) >= limit:
                    return None
                seen[t] = None
                todo.append(t)
    return task.names, list(seen)
