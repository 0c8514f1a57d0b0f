"""Bounds every reachable state keeps on the numeric resources, inferred from the guards of
their changes (:func:`infer_bounds`)."""

from __future__ import annotations

from collections.abc import Callable
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir import BoolOpKind, CmpOp, EffectKind
from catc.semantics.search.common import _linear, _minus, _num, _TaskShape
from catc.semantics.search.terms import _kind


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


def infer_bounds(inst: ir.Instance, task: _TaskShape) -> list[tuple[Any, Any]]:
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
