"""Ranges every reachable state keeps on numbers, inferred from the task's guards, changes and
initial values: the one derivation the forward search, the state bound and the churn search use.

Imported PDDL numbers are unbounded reals, and many models declare no bound on a budget that
every purchase checks first; :func:`numeric_ranges` finds the range such a number cannot leave.
Its users (each narrows what it proves with the ranges, none widens anything):

* :func:`catc.semantics.search.infer_bounds` — the forward search's relaxation and counting
  heuristic cut by them (dead ends proven, admissible estimates raised);
* :func:`catc.semantics.horizon.state_bound` — the lattice points within a number's range in
  the reachable-state bound that makes the SMT route's "no composition" final;
* :func:`catc.queries.churn_search.tightened` — a lower bound made explicit for the counting
  relaxation and the consumption abstraction of ``catc recompose``.
"""

from __future__ import annotations

from collections.abc import Mapping
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir import ArithOp, BoolOpKind, CmpOp, EffectKind

#: a linear form Σ w·x + k over resource names
Linear = tuple[dict[str, Fraction], Fraction]


def numeric_ranges(inst: ir.Instance, numbers: Mapping[str, Any]) -> dict[str, tuple[Any, Any]]:
    """Bounds (lo, hi; None: none) that every reachable state keeps on each resource of
    ``numbers`` (the numeric resources taking part, with their initial values; any other
    resource is no number here: no bound, never read as a constant). Declared bounds are not
    read: the caller narrows them by these.

    For a resource x written by the morphisms M_x, with initial value v₀:

    * lo = min(v₀, every constant that a morphism of M_x assigns to x, and k − d for every
      morphism of M_x that decreases x by a constant d > 0 and whose precondition has a
      conjunct implying x ≥ k); no lo when a morphism of M_x changes x by a non-constant, or
      decreases it without such a conjunct;
    * hi symmetrically (max; increases by d > 0 under x ≤ k give k + d).

    A morphism's changes of one resource are summed (two ``increase`` effects by 2 and 3 are
    one change by 5); a morphism that assigns x and also changes it gives no bound.

    Soundness, by induction over the steps of any execution: the initial state has x = v₀
    within [lo, hi]. A step that does not write x keeps it. A step that assigns the constant
    c leaves c, within the bounds by their definition. A step that changes x by a constant
    d ≥ 0 keeps x ≥ lo (x grows) and, if d > 0, fired from a state where its precondition held,
    so x ≤ k before and x + d ≤ k + d ≤ hi after; d ≤ 0 symmetrically. The precondition
    conjuncts are read as linear inequalities (a strict one as the weaker non-strict one, an
    equality as both) over one written resource, the other resources they mention replaced by
    their initial values only where no morphism writes those (static: the same in every
    state); a conjunct of any other shape is not read (no bound from it, never a wrong one).
    With parallel steps the states between steps are those of a sequential execution (the
    non-interference rules make a step's activations run in any order,
    :mod:`catc.smt.encoder`), so the bounds hold there as well. Every reachable state
    therefore lies within the bounds, and cutting a relaxation or a count of states by them
    loses no reachable state: what they prove unreachable is unreachable."""
    d = inst.domain
    written = {e.resource for m in d.morphisms.values() for e in m.effects}
    static = {n: v for n, v in numbers.items() if n not in written}
    lo: dict[str, Any] = dict(numbers)
    hi: dict[str, Any] = dict(numbers)
    pre: dict[str, dict[str, list[Any]]] = {}
    for m in d.morphisms.values():
        by_res: dict[str, list[ir.Effect]] = {}
        for e in m.effects:
            by_res.setdefault(e.resource, []).append(e)
        for name, group in by_res.items():
            if name not in numbers or (lo[name] is None and hi[name] is None):
                continue
            values = [e.value.value for e in group if isinstance(e.value, ir.Const)]
            if len(values) < len(group) or (len(group) > 1 and any(e.kind is EffectKind.ASSIGN for e in group)):
                lo[name] = hi[name] = None
                continue
            if group[0].kind is EffectKind.ASSIGN:
                v = whole(values[0])
                lo[name] = None if lo[name] is None else min(lo[name], v)
                hi[name] = None if hi[name] is None else max(hi[name], v)
                continue
            delta = Fraction(0)
            for e, c in zip(group, values):
                delta += -Fraction(c) if e.kind is EffectKind.DECREASE else Fraction(c)
            if delta == 0:
                continue
            if m.name not in pre:
                pre[m.name] = guard_bounds(m, numbers, static)
            k_lo, k_hi = pre[m.name].get(name, [None, None])
            if delta < 0:
                lo[name] = None if lo[name] is None or k_lo is None else min(lo[name], whole(k_lo + delta))
            else:
                hi[name] = None if hi[name] is None or k_hi is None else max(hi[name], whole(k_hi + delta))
    return {n: (lo[n], hi[n]) for n in numbers}


def ranges(inst: ir.Instance, init: Mapping[str, Any]) -> dict[str, tuple[Any, Any]]:
    """:func:`numeric_ranges` over every numeric resource with a value in ``init`` (the initial
    state, :func:`catc.semantics.validate.initial_state`): a number without one is no number
    here (no bound, never static)."""
    numbers = {n: init.get(n) for n, r in inst.resources.items() if r.sort.is_numeric and init.get(n) is not None}
    return numeric_ranges(inst, numbers)


def guard_bounds(m: ir.Morphism, numbers: Mapping[str, Any], static: Mapping[str, Any]) -> dict[str, list[Any]]:
    """The bounds ``m``'s precondition puts on single numeric resources: each conjunct that is
    linear over one resource of ``numbers`` not in ``static`` (the static ones replaced by
    their values), as ``{resource: [lo, hi]}`` (None: no bound). A strict inequality gives the
    non-strict bound (weaker, still implied); a comparison of anything but numbers is not read."""
    out: dict[str, list[Any]] = {}
    todo = [lit.expr for lit in m.pre]
    while todo:
        e = todo.pop()
        if isinstance(e, ir.BoolOp) and e.op is BoolOpKind.AND:
            todo.extend(e.args)
            continue
        if not isinstance(e, ir.Compare) or not e.left.sort.is_numeric:
            continue
        left, right = linear(e.left), linear(e.right)
        if left is None or right is None:
            continue
        forms = []
        if e.op in (CmpOp.LE, CmpOp.LT, CmpOp.EQ):
            forms.append(_minus(right, left))  # right − left ≥ 0
        if e.op in (CmpOp.GE, CmpOp.GT, CmpOp.EQ):
            forms.append(_minus(left, right))
        for w, k in forms:  # Σ w·x + k ≥ 0
            rest = {n: c for n, c in w.items() if c != 0 and n not in static}
            if len(rest) != 1:
                continue
            ((n, c),) = rest.items()
            if n not in numbers:
                continue  # a resource that is no number here (no initial value): nothing to bound
            k_all = k + sum((c2 * static[n2] for n2, c2 in w.items() if n2 in static), Fraction(0))
            b = whole(-k_all / c)
            lo_hi = out.setdefault(n, [None, None])
            if c > 0:  # x ≥ −k/c
                lo_hi[0] = b if lo_hi[0] is None else max(lo_hi[0], b)
            else:  # x ≤ −k/c
                lo_hi[1] = b if lo_hi[1] is None else min(lo_hi[1], b)
    return out


def linear(e: ir.Expr) -> Linear | None:
    """``e`` as Σ w·x + k over numeric resources (by name), or None when it is not linear."""
    if isinstance(e, ir.Const) and isinstance(e.value, Fraction):
        return {}, e.value
    if isinstance(e, ir.ResourceRef):
        return {e.name: Fraction(1)}, Fraction(0)
    if isinstance(e, ir.Arith) and e.op in (ArithOp.ADD, ArithOp.SUB, ArithOp.MUL):
        parts = [linear(a) for a in e.args]
        if any(x is None for x in parts):
            return None
        if e.op is ArithOp.MUL:
            w: dict[str, Fraction] = {}
            k = Fraction(1)
            for x in parts:
                assert x is not None
                if x[0] and w:
                    return None  # a product of two resources
                if x[0]:
                    w = {n: c * k for n, c in x[0].items()}
                    k = k * x[1]
                else:
                    w = {n: c * x[1] for n, c in w.items()}
                    k = k * x[1]
            return w, k
        first = parts[0]
        assert first is not None
        w, k = dict(first[0]), first[1]
        if e.op is ArithOp.SUB and len(parts) == 1:
            return {n: -c for n, c in w.items()}, -k
        sign = 1 if e.op is ArithOp.ADD else -1
        for x in parts[1:]:
            assert x is not None
            for n, c in x[0].items():
                w[n] = w.get(n, Fraction(0)) + sign * c
            k += sign * x[1]
        return w, k
    return None


def _minus(a: Linear, b: Linear) -> Linear:
    w = dict(a[0])
    for n, c in b[0].items():
        w[n] = w.get(n, Fraction(0)) - c
    return w, a[1] - b[1]


def whole(v: Any) -> Any:
    """An int for a whole Fraction (not a bool), the value itself otherwise."""
    if isinstance(v, Fraction) and v.denominator == 1:
        return int(v.numerator)
    return v


def conserved_sums(inst: ir.Instance, numbers: Mapping[str, Any]) -> list[tuple[tuple[str, ...], Fraction, int]]:
    """Sums of numbers that never grow or never shrink: ``(S, c, sign)`` says Σ_{x∈S} x ≤ c
    in every reachable state when ``sign`` is −1, ≥ c when +1 (c: the initial Σ).

    S is a group of resources of ``numbers`` that morphisms move between (linked when one
    morphism changes both), every change of which is an ``increase``/``decrease`` by a
    constant (a group with any other change of a member is left out), with more than one
    member (a single one is a range, :func:`numeric_ranges`), less the members no morphism
    moves the other way (for a sum that never grows, those only raised). Let Δ_S(m) be the sum of
    morphism m's changes of S's members: when Δ_S(m) ≤ 0 for every m, no step raises Σ_S
    (by induction over the steps, as in :func:`numeric_ranges`; parallel steps are the
    sequential executions of their activations), so it stays ≤ its initial value; when
    Δ_S(m) ≥ 0 for every m, symmetrically ≥. Workers moved between farms, some lost on the
    way, are such a group: their total never grows."""
    parent = {n: n for n in numbers}

    def root(n: str) -> str:
        while parent[n] != n:
            parent[n] = parent[parent[n]]
            n = parent[n]
        return n

    bad: set[str] = set()
    deltas: list[dict[str, Fraction]] = []
    for m in inst.domain.morphisms.values():
        delta: dict[str, Fraction] = {}
        for e in m.effects:
            if e.resource not in numbers:
                continue
            c = e.value.value if isinstance(e.value, ir.Const) else None
            if e.kind is EffectKind.ASSIGN or not isinstance(c, Fraction | int) or isinstance(c, bool):
                bad.add(e.resource)
                continue
            delta[e.resource] = delta.get(e.resource, Fraction(0)) + (
                -Fraction(c) if e.kind is EffectKind.DECREASE else Fraction(c)
            )
        names = list(delta)
        for a in names[1:]:
            parent[root(a)] = root(names[0])
        deltas.append(delta)
    groups: dict[str, list[str]] = {}
    for n in numbers:
        groups.setdefault(root(n), []).append(n)
    out: list[tuple[tuple[str, ...], Fraction, int]] = []
    for group in groups.values():
        if any(n in bad or numbers[n] is None for n in group):
            continue
        for sign in (-1, 1):
            # a member no morphism lowers (for a sum that should never grow; raises, for one that
            # should never shrink) is left out: that only moves each Δ_S(m) the wanted way
            members = [n for n in group if any(d.get(n, 0) * sign > 0 for d in deltas)]
            if len(members) < 2:
                continue
            nets = [sum((d.get(n, Fraction(0)) for n in members), Fraction(0)) for d in deltas]
            if all(x * sign >= 0 for x in nets):
                total = sum((Fraction(numbers[n]) for n in members), Fraction(0))
                out.append((tuple(members), total, sign))
    return out


def sum_refutation(inst: ir.Instance, init: Mapping[str, Any]) -> str | None:
    """Why no reachable state satisfies the goal, by a conserved sum (:func:`conserved_sums`),
    or None: the goal's conjuncts that bound one member of a group from below (above, for a
    sum that never shrinks), each member otherwise at the lower end of its range (declared, or
    :func:`ranges`), add up past what the sum can be. Sound: every reachable state keeps the
    ranges and the sums, and a goal state would have each member at least its bound."""
    numbers = {n: init.get(n) for n, r in inst.resources.items() if r.sort.is_numeric and init.get(n) is not None}
    sums = conserved_sums(inst, numbers)
    if not sums:
        return None
    rng = numeric_ranges(inst, numbers)
    # the goal's single-resource linear bounds: name → [lo, lo strict, hi, hi strict]
    goal: dict[str, list[Any]] = {}
    todo = [lit.expr for lit in inst.problem.goal]
    while todo:
        e = todo.pop()
        if isinstance(e, ir.BoolOp) and e.op is BoolOpKind.AND:
            todo.extend(e.args)
            continue
        if not isinstance(e, ir.Compare) or not e.left.sort.is_numeric or e.op not in _ORDER:
            continue
        left, right = linear(e.left), linear(e.right)
        if left is None or right is None:
            continue
        strict = e.op in (CmpOp.LT, CmpOp.GT)
        forms = []
        if e.op in (CmpOp.LE, CmpOp.LT, CmpOp.EQ):
            forms.append(_minus(right, left))  # right − left ≥ 0 (> 0 when strict)
        if e.op in (CmpOp.GE, CmpOp.GT, CmpOp.EQ):
            forms.append(_minus(left, right))
        for w, k in forms:
            rest = {n: c for n, c in w.items() if c != 0}
            if len(rest) != 1:
                continue
            ((n, c),) = rest.items()
            b = -k / c
            cur = goal.setdefault(n, [None, False, None, False])
            if c > 0 and (cur[0] is None or b > cur[0] or (b == cur[0] and strict)):
                cur[0], cur[1] = b, strict  # x ≥ b (x > b)
            elif c < 0 and (cur[2] is None or b < cur[2] or (b == cur[2] and strict)):
                cur[2], cur[3] = b, strict  # x ≤ b (x < b)
    for members, total, sign in sums:
        least, strict = Fraction(0), False
        for n in members:
            res = inst.resources[n]
            if sign < 0:  # the least each member can be in a goal state
                g, g_strict, declared, inferred = *goal.get(n, [None, False])[:2], res.lower, rng[n][0]
            else:  # the most
                g, g_strict, declared, inferred = *goal.get(n, [None, False, None, False])[2:], res.upper, rng[n][1]
            options = [
                (Fraction(v), s) for v, s in ((g, g_strict), (declared, False), (inferred, False)) if v is not None
            ]
            if not options:
                break
            v, s = max(options) if sign < 0 else min(options, key=lambda o: (o[0], not o[1]))
            least += v
            strict = strict or s
        else:
            past = (
                least > total or (least == total and strict)
                if sign < 0
                else least < total or (least == total and strict)
            )
            if past:
                side, what = ("at least", "never grows") if sign < 0 else ("at most", "never shrinks")
                return (
                    f"the goal needs {' + '.join(members)} to be {side} {_fmt(least)}, but that sum {what} "
                    f"from its initial {_fmt(total)}"
                )
    return None


_ORDER = (CmpOp.LE, CmpOp.LT, CmpOp.GE, CmpOp.GT, CmpOp.EQ)


def _fmt(v: Fraction) -> str:
    return str(v.numerator) if v.denominator == 1 else f"{v.numerator}/{v.denominator}"
