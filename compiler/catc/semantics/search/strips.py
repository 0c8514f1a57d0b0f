"""The fast path for classical tasks (:class:`_Strips`): states as bitmasks."""

from __future__ import annotations

from typing import Any

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
        self._succ, self._apply = self._compiled()

    #: the most morphisms for which successors and relaxed layers are compiled to code
    COMPILED = 20_000

    def _compiled(self) -> tuple[Any, Any]:
        """:meth:`successors` and one relaxed layer (:meth:`h`) as straight-line code, one
        line per morphism in the morphisms' order (the same successors in the same order, the
        same layers), with the masks as literals — several times faster than a loop over the
        mask tuples. A resource true initially and deleted by no morphism is true in every
        reachable state and in every layer from one; one false initially and added by none
        false in all: tests of such bits are left out, and a morphism needing the opposite
        never fires (its line is left out). None, None past ``COMPILED`` morphisms."""
        if len(self.masks) > self.COMPILED:
            return None, None
        ever_added = ever_deleted = 0
        for _pp, _pn, add, dele in self.masks:
            ever_added |= add
            ever_deleted |= dele
        always = self.init & ~ever_deleted  # true in every reachable state
        never = ~self.init & ~ever_added & self.full  # false in every reachable state
        succ = ["def successors(s):", "    out = []"]
        layer = ["def layer(t, f):", "    nt, nf = t, f"]
        for i, (need, shun, add, dele) in enumerate(self.masks):
            if need & never or shun & always:
                continue
            pp, pn = need & ~always, shun & ~never
            tests = ([f"s & {pp} == {pp}"] if pp else []) + ([f"not s & {pn}"] if pn else [])
            succ.append(f"    if {' and '.join(tests) or 'True'}: out.append(({i}, s & {~dele & self.full} | {add}))")
            rtests = ([f"t & {pp} == {pp}"] if pp else []) + ([f"f & {pn} == {pn}"] if pn else [])
            does = ([f"nt |= {add}"] if add else []) + ([f"nf |= {dele}"] if dele else [])
            if does:
                layer.append(f"    if {' and '.join(rtests) or 'True'}: {'; '.join(does)}")
        succ.append("    return out")
        layer.append("    return nt, nf")
        namespace: dict[str, Any] = {}
        exec(compile("\n".join(succ + layer) + "\n", "<catc.semantics.search.strips>", "exec"), namespace)
        return namespace["successors"], namespace["layer"]

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
        if self._succ is not None:
            return self._succ(s)  # type: ignore[no-any-return]
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
        layer_of = self._apply
        if layer_of is not None:
            for layer in range(cap):
                if t & gp == gp and f & gn == gn:
                    return layer
                nt, nf = layer_of(t, f)
                if nt == t and nf == f:
                    return None
                t, f = nt, nf
            return cap
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
