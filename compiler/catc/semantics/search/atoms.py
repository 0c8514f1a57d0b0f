"""The conditions of a numeric task cut into atoms, and h_add over them (:class:`_Atoms`), for
the greedy search."""

from __future__ import annotations

from fractions import Fraction
from typing import TYPE_CHECKING, Any

from catc import ir
from catc.ir import BoolOpKind, CmpOp, EffectKind
from catc.semantics.search.common import _FAR, Fn, State, _constant, _linear, _minus, _reads
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
