"""The fast path for classical tasks (:class:`_Strips`): states as bitmasks."""

from __future__ import annotations

from catc import ir
from catc.ir import BoolOpKind, EffectKind, SortKind
from catc.semantics.search.common import _FAR, _constant, _Unsupported


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
