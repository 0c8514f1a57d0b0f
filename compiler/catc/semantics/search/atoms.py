"""The conditions of a numeric task cut into atoms, and h_add over them (:class:`_Atoms`), for
the greedy search."""

from __future__ import annotations

import heapq
from fractions import Fraction
from typing import TYPE_CHECKING, Any

from catc import ir
from catc.ir import BoolOpKind, CmpOp, EffectKind
from catc.semantics.search.common import _FAR, Fn, State, _constant, _linear, _minus, _num, _reads
from catc.semantics.search.terms import _concrete, _kind

if TYPE_CHECKING:
    from catc.semantics.search.task import _Task


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

    def _prepare(self) -> None:
        """What :meth:`hadd` reads, built once: the linear forms and rates with whole numbers
        as ints (exact, and much faster than Fractions of denominator 1), the linear atoms,
        and for each atom the morphisms whose precondition names it (once per mention)."""
        self._lin = [([(i, _num(c)) for i, c in terms], _num(k)) for terms, k, _strict in self.linear]
        self._strict = [strict for _terms, _k, strict in self.linear]
        self._lin_atoms = [(atom, j) for atom, (what, j) in enumerate(self.kind) if what == "linear"]
        self._rates = [[(q, j, _num(rate)) for q, j, rate in rs] for rs in self.rates]
        self._watch: list[list[int]] = [[] for _ in self.kind]
        for a_i, pre in enumerate(self.pre):
            for q in pre:
                self._watch[q].append(a_i)
        self._free = [a_i for a_i, pre in enumerate(self.pre) if not pre]

    def hadd(self, s: State) -> int:
        """h_add: each atom's cost the least, over the morphisms that make it true, of 1 plus
        the sum of the morphism's precondition costs (a linear atom: the repetitions its rate
        needs, less one, added); the goal's, the sum of its atoms'. The least fixpoint of these
        equations, computed as Fast Downward does, by Dijkstra's order (Knuth's generalisation:
        a morphism's cost exceeds each of its preconditions', so an atom is final when it leaves
        the queue) with a counter of unmet preconditions per morphism: each morphism is
        evaluated once, when its last precondition becomes final. An atom no morphism reaches
        costs ``_FAR``."""
        if not hasattr(self, "_lin"):
            self._prepare()
        n = len(self.kind)
        cost: list[Any] = [_FAR] * n
        values = []
        for terms, k in self._lin:
            v: Any = k
            for i, w in terms:
                v += w * s[i]
            values.append(v)
        strict = self._strict
        for atom, j in self._lin_atoms:
            v = values[j]
            if v > 0 or (v == 0 and not strict[j]):
                cost[atom] = 0
        for atom, test in self.tests:
            try:
                if test(s):
                    cost[atom] = 0
            except ArithmeticError:
                pass
        rates = self._rates
        if self.varying:  # the change of a number in this state
            rates = list(rates)
            for a_i in self.varying:
                rates[a_i] = [(q, j, _num(rate)) for q, j, rate in self._rates_at(a_i, s)]
        adds, watch = self.adds, self._watch
        unmet = [len(pre) for pre in self.pre]
        total = [1] * len(self.pre)  # 1 + the precondition costs seen so far
        heap = [(0, q) for q in range(n) if cost[q] == 0]
        done = [False] * n
        goal = set(self.goal)
        left = len(goal)

        def fire(a_i: int, c: int) -> None:
            if c >= _FAR:
                return
            for q in adds[a_i]:
                if c < cost[q]:
                    cost[q] = c
                    heapq.heappush(heap, (c, q))
            for q, j, rate in rates[a_i]:
                if cost[q] == 0:
                    continue
                need = -values[j]
                reps = need // rate + 1 if strict[j] else -(-need // rate)
                r = c - 1 + max(int(reps), 1)
                if r < cost[q]:
                    cost[q] = r
                    heapq.heappush(heap, (r, q))

        for a_i in self._free:
            fire(a_i, 1)
        while heap and left:
            c, q = heapq.heappop(heap)
            if done[q] or c > cost[q]:
                continue
            done[q] = True
            if q in goal:
                left -= 1
            for a_i in watch[q]:
                total[a_i] += c
                unmet[a_i] -= 1
                if not unmet[a_i]:
                    fire(a_i, total[a_i])
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
