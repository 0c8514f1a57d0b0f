"""The ground task over concrete states (:class:`_Task`): successors, the goal, and A*'s
admissible heuristic (h^max over the interval relaxation, the goal-achiever bound, the
counting bound); and the folding of static numbers into it (:func:`_inline_statics`)."""

from __future__ import annotations

import bisect
from collections.abc import Callable
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir import BoolOpKind, EffectKind, SortKind
from catc.semantics.search.bounds import _tighter, infer_bounds
from catc.semantics.search.common import Fn, State, _Bound, _constant, _num, _reads, _Unsupported
from catc.semantics.search.terms import Relaxed, _concrete, _join, _kind, _lo_add, _point, _redundant, _relaxed


class _Action:
    __slots__ = ("name", "pre", "effects", "rpre", "reffects", "constant", "rreads", "ereads", "shifts")
    #: ``rreads``: per test of ``rpre``, the resources it reads

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
        #: the resources the relaxed precondition reads, and those the relaxed effects' values
        #: depend on (what they read; a changed resource its own old value): a layer re-tests
        #: and re-applies a morphism only when one of these changed (:meth:`_Task._layer`)
        every = {index[n] for lit in m.pre for n in _reads(lit.expr)}
        self.rreads = [{index[n] for n in _reads(lit.expr)} for lit in m.pre]
        self.rreads += [every] * (len(self.rpre) - len(m.pre))  # the sums: at most what all read
        self.ereads: set[int] = set()
        #: the changes of a number by constants only (resource, the sum of the constants),
        #: which the relaxation applies per resource, not per morphism (:meth:`_Task._layer`);
        #: ``reffects`` and ``ereads`` hold the other effects
        self.shifts: list[tuple[int, Any]] = []
        for i, group in by_res.items():
            assigns = [e for e in group if e.kind is EffectKind.ASSIGN]
            if assigns and len(group) > 1:
                raise _Unsupported("one resource assigned and changed by one morphism")
            mode = "assign" if assigns else "step"
            terms = [(-1 if e.kind is EffectKind.DECREASE else 1, e) for e in group]
            self.effects.append((i, mode, [(sign, _concrete(e.value, index)) for sign, e in terms]))
            if mode == "step" or not isinstance(group[0].value, ir.Const):
                self.constant = False
            consts = [(sign, e.value.value) for sign, e in terms if isinstance(e.value, ir.Const)]
            if mode == "step" and len(consts) == len(terms):
                delta = sum((sign * Fraction(c) for sign, c in consts), Fraction(0))
                self.shifts.append((i, _num(delta)))
                continue
            self.reffects.append((i, mode, [(sign, _relaxed(e.value, index)) for sign, e in terms]))
            self.ereads |= {index[n] for e in group for n in _reads(e.value)}
            if mode == "step":
                self.ereads.add(i)


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
        self.counting: _Bound | None = None  # the counting bound, set by the caller
        self.landmarks: _Bound | None = None  # counting plus landmarks, set by the caller
        #: resource → (morphism, k) for the k-th test of the morphism's relaxed precondition
        #: that reads it; resource → morphisms whose effects read it
        self.pre_watch: list[list[tuple[int, int]]] = [[] for _ in self.names]
        self.eff_watch: list[list[int]] = [[] for _ in self.names]
        for a_i, a in enumerate(self.actions):
            for k, reads in enumerate(a.rreads):
                for i in reads:
                    self.pre_watch[i].append((a_i, k))
            for i in a.ereads:
                self.eff_watch[i].append(a_i)
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
        (:func:`_astar`). A fourth, ``landmarks`` (:mod:`catc.semantics.search.landmarks`: counting
        plus landmarks, with a case split on a gate fact), where :func:`search` builds one."""
        first: list[int] | None = [-1] * len(self.actions) if self.goal_facts else None
        h = self._hmax(s, cap, first)
        if h is None or h >= cap:
            return h
        if first is not None:
            h = min(max(h, self._achiever_bound(s, first)), cap)
        for bound in (self.counting, self.landmarks):
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
        enabled = [0] * len(self.actions)
        dirty: set[int] | None = None
        shifts: dict[int, list[Any]] = {}
        for layer in range(cap):
            rt = tuple(r)
            if all(f(rt)[0] for f in self.rgoal):
                return layer
            step = self._layer(rt, fired, first, layer, enabled, dirty, shifts)
            if step is None:
                return None
            r, dirty = step
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

    def _layer(
        self,
        rt: Relaxed,
        fired: set[int],
        first: list[int] | None,
        layer: int,
        enabled: list[int],
        dirty: set[int] | None,
        shifts: dict[int, list[Any]],
    ) -> tuple[list[Any], set[int]] | None:
        """The next layer: every morphism that may fire in ``rt`` applied (relaxed, joined),
        and the resources whose values changed; None when nothing changes (a fixpoint). With
        ``first``, a morphism seen to fire for the first time is marked with ``layer``.

        Incremental (as Fast Downward's h^max counts preconditions): ``enabled[a]`` is the
        number of a's relaxed precondition tests (``rpre``, a conjunction) seen to hold, in
        order — layers only grow and a relaxed test's "can hold" only grows with them, so a
        test that held holds now too; −1 once all of them held: a is enabled — and ``dirty`` the resources
        that changed from the previous layer (None: all, the first layer). A morphism not yet
        enabled is tested again, from its first test not seen to hold, only when a resource
        that test reads changed (the others' outcome is known or not needed yet); an enabled
        one re-applied only when a resource its effects read changed: otherwise its
        effects are those it had in the previous layer, already joined into ``rt``, and
        joining them again changes nothing. The layer is the same as testing and applying
        every morphism.

        Changes of a number x by a constant d (``_Action.shifts``) are applied per resource:
        ``shifts[x]`` holds the sorted d of the enabled morphisms (with repetitions). Each d
        gives the interval [lo + d, hi + d], cut by x's bounds [L, H] and skipped when the cut
        is empty, which is when d > H − lo or d < L − hi; the cut ends grow with d, so the hull
        of all of them is that of the least and the greatest d within [L − hi, H − lo] — the
        same join as applying each morphism."""
        changed: set[int] = set()
        moved: set[int] = set(shifts) if dirty is None else {i for i in dirty if i in shifts}
        new = list(rt)
        todo = range(len(self.actions)) if dirty is None else self._candidates(dirty, enabled)
        actions = self.actions
        for a_i in todo:
            if a_i in fired:
                continue
            a = actions[a_i]
            k, tests = enabled[a_i], a.rpre
            if k >= 0:
                while k < len(tests) and tests[k](rt)[0]:
                    k += 1
                if k < len(tests):
                    enabled[a_i] = k
                    continue
                enabled[a_i] = -1
                if first is not None and first[a_i] < 0:
                    first[a_i] = layer
                for i, d in a.shifts:
                    bisect.insort(shifts.setdefault(i, []), d)
                    moved.add(i)
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
                    changed.add(i)
        self._shift(rt, new, changed, moved, shifts)
        return (new, changed) if changed else None

    def _candidates(self, dirty: set[int], enabled: list[int]) -> list[int]:
        """The morphisms :meth:`_layer` looks at after the resources ``dirty`` changed: those
        not enabled whose first test not seen to hold reads one of them, and the enabled ones
        whose effects read one."""
        cand: set[int] = set()
        for i in dirty:
            for a_i, k in self.pre_watch[i]:
                if enabled[a_i] == k:
                    cand.add(a_i)
            for a_i in self.eff_watch[i]:
                if enabled[a_i] < 0:
                    cand.add(a_i)
        return sorted(cand)

    def _shift(
        self, rt: Relaxed, new: list[Any], changed: set[int], moved: set[int], shifts: dict[int, list[Any]]
    ) -> None:
        """The constant shifts of the resources ``moved`` (:meth:`_layer`) joined into ``new``."""
        for i in moved:
            ds = shifts[i]
            lo, hi = rt[i]
            bound_lo, bound_hi = self.bounds[i]
            if bound_lo is not None and bound_hi is not None and bound_lo > bound_hi:
                continue
            first_d = 0 if bound_lo is None or hi is None else bisect.bisect_left(ds, bound_lo - hi)
            last_d = len(ds) if bound_hi is None or lo is None else bisect.bisect_right(ds, bound_hi - lo)
            if first_d >= last_d:
                continue  # every cut is empty
            low = self._cut(i, (None if lo is None else lo + ds[first_d], None if hi is None else hi + ds[first_d]))
            high = self._cut(
                i, (None if lo is None else lo + ds[last_d - 1], None if hi is None else hi + ds[last_d - 1])
            )
            assert low is not None and high is not None
            joined = _join(new[i], (low[0], high[1]), "number")
            if joined != new[i]:
                new[i] = joined
                changed.add(i)

    def _dead(self, r: list[Any]) -> bool:
        """The goal can never hold from layer ``r``: the relaxation run to a fixpoint, each
        number bound that still moves widened to infinity (then cut by the resource's bounds),
        so that it ends; a goal that cannot hold there cannot hold in any later layer."""
        fired: set[int] = set()
        enabled = [0] * len(self.actions)
        dirty: set[int] | None = None
        shifts: dict[int, list[Any]] = {}
        while True:  # ends: each number bound widens once, Boolean and symbol sets only grow
            rt = tuple(r)
            if all(f(rt)[0] for f in self.rgoal):
                return False
            step = self._layer(rt, fired, None, 0, enabled, dirty, shifts)
            if step is None:
                return True
            new, dirty = step
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
