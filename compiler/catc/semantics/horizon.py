"""How many steps a composition may take: the horizon and what bounds it."""

from __future__ import annotations

import math
from collections.abc import Callable, Collection
from fractions import Fraction
from typing import Any

from catc import ir
from catgrammar import limits

#: The horizon when the problem names none and some morphism has no use limit.
DEFAULT_HORIZON = 10


def use_bound(inst: ir.Instance, components: Collection[str] | None = None) -> int | None:
    """Σ uses over all morphisms (over ``components`` only, when the composition is fixed to
    them), or None when one of them is unlimited.  No composition has more non-idle steps."""
    total = 0
    for m in inst.morphisms.values():
        if components is not None and m.name not in components:
            continue
        if m.uses is None:
            return None
        total += m.uses
    return total


def default_horizon(inst: ir.Instance) -> int:
    """The problem's ``(:horizon ...)``, else the use bound, else :data:`DEFAULT_HORIZON`."""
    if inst.problem.horizon is not None:
        return inst.problem.horizon
    bound = use_bound(inst)
    return bound if bound is not None else DEFAULT_HORIZON


def horizon_of(inst: ir.Instance, horizon: int | None = None) -> int:
    """The horizon of a query: ``horizon`` when given (``--horizon``), else
    :func:`default_horizon` — checked against the horizon limit (:mod:`catgrammar.limits`):
    past it, a :class:`~catgrammar.limits.LimitExceeded` located where the horizon comes
    from (the problem's ``(:horizon ...)``, or the largest ``:uses`` of the sum)."""
    k = default_horizon(inst) if horizon is None else horizon
    check_horizon(inst, k, given=horizon is not None)
    return k


def check_horizon(inst: ir.Instance | None, k: int, given: bool = True) -> None:
    """Raise :class:`~catgrammar.limits.LimitExceeded` when ``k`` is past the horizon limit."""
    most = limits.current().horizon
    if k <= most:
        return
    limit = limits.BY_NAME["horizon"]
    steps = limits.count_text(k, "step")
    past = f"more than the horizon limit ({limits.count_text(most, 'step')}); {limit.how_to_raise}"
    if given or inst is None:
        raise limits.LimitExceeded(limit.code, f"--horizon {k} is {past}")
    if inst.problem.horizon is not None:
        raise limits.LimitExceeded(limit.code, f"the horizon, {steps}, is {past}", inst.problem.horizon_span)
    largest = max(inst.morphisms.values(), key=lambda m: m.uses or 0)
    raise limits.LimitExceeded(
        limit.code,
        f"the default horizon, the sum of the use limits ({steps}), is {past}; or give (:horizon ...) or --horizon",
        largest.span,
    )


def state_bound(inst: ir.Instance, most: int) -> int | None:
    """An upper bound N on the number of states a composition can visit, when it is at most
    ``most``, else None: a product over the resources of the values each can take.

    A Boolean takes 2 values, a symbol its sort's constants, a set every subset of its
    element sort's constants (where no morphism has a symbolic parameter: one may bring a
    value nobody named, :mod:`catc.smt.finite`'s reserves, and then there is no bound), a resource no morphism writes 1 (its initial value, or a value
    fixed for the whole composition). A number written only by constant changes (increase or
    decrease by c, or assignment of c) stays on the lattice v₀ + q·ℤ (v₀ its initial value,
    q the greatest common divisor of the changes and of c − v₀ for the assignments), within
    its bounds — the declared ones narrowed by those inferred from the guards of its changes
    (:func:`catc.semantics.bounds.numeric_ranges`, which every reachable state keeps): the
    lattice points within them. Any other number counts only as an int with both bounds
    declared (its integers within them); else there is no bound.

    What the bound is for: some shortest composition, if any exists, visits no state twice
    (cut the steps between two visits of one state: the remaining steps fire from the same
    states, use no morphism more often, and end in the same goal state), so it has at most
    N − 1 steps, and no composition within N − 1 steps proves none of any length. With
    parallel steps the states between steps are those of a sequential execution (the
    non-interference rules make a step's activations run in any order, :mod:`catc.smt.encoder`),
    so the inferred bounds, argued over sequential steps, hold there as well."""
    if inst.domain.holes:  # a hole's μ writes what no morphism does (catc synthesize): not counted here
        return None
    written = {e.resource for m in inst.morphisms.values() for e in m.effects}
    named_only = not any(p.sort.is_symbolic for m in inst.morphisms.values() for p in m.params)
    size = 1
    numbers: list[ir.Resource] = []
    for r in inst.resources.values():
        kind = r.sort.kind
        if r.name not in written:
            n = 1
        elif kind in (ir.SortKind.SYMBOL, ir.SortKind.SET) and not named_only:
            return None
        elif kind is ir.SortKind.BOOL:
            n = 2
        elif kind in (ir.SortKind.SYMBOL, ir.SortKind.ENUM):
            n = max(1, len(inst.constants_of(r.sort)))
        elif kind is ir.SortKind.SET:
            assert r.sort.element is not None  # a set sort's element sort
            n = 2 ** len(inst.constants_of(r.sort.element))
        elif kind in (ir.SortKind.INT, ir.SortKind.REAL):
            if not _constant_changes(inst, r.name) and not (
                kind is ir.SortKind.INT and r.lower is not None and r.upper is not None
            ):
                return None  # changed by a non-constant, and no declared range of integers
            numbers.append(r)
            continue
        else:
            return None
        size *= max(1, n)
        if size > most:
            return None
    if not numbers:
        return size
    # the inferred bounds only where needed
    from catc.semantics.bounds import ranges
    from catc.semantics.validate import initial_state

    init = initial_state(inst)
    needs = any(r.lower is None or r.upper is None for r in numbers)
    inferred = ranges(inst, init) if needs else {}
    for r in numbers:
        n_or_none = _number_values(inst, r, init.get(r.name), inferred.get(r.name, (None, None)))
        if n_or_none is None:
            return None
        size *= max(1, n_or_none)
        if size > most:
            return None
    return size


def _constant_changes(inst: ir.Instance, name: str) -> bool:
    """Every effect on resource ``name`` is by a constant number."""
    return all(
        isinstance(e.value, ir.Const) and isinstance(e.value.value, Fraction)
        for m in inst.morphisms.values()
        for e in m.effects
        if e.resource == name
    )


def _number_values(inst: ir.Instance, r: ir.Resource, v0: Any, inferred: tuple[Any, Any]) -> int | None:
    """How many values the written numeric resource ``r`` can take (:func:`state_bound`)."""
    lo = _tighter(r.lower, inferred[0], max)
    hi = _tighter(r.upper, inferred[1], min)
    if lo is None or hi is None:
        return None
    lo, hi = Fraction(lo), Fraction(hi)
    if lo > hi:
        return 1  # no valid value besides, at most, the initial one
    changes: list[Fraction] | None = []
    for m in inst.morphisms.values():
        for e in m.effects:
            if e.resource != r.name:
                continue
            if changes is None or not isinstance(e.value, ir.Const) or not isinstance(e.value.value, Fraction):
                changes = None
                continue
            if e.kind is ir.EffectKind.ASSIGN:
                if not isinstance(v0, Fraction | int):
                    changes = None
                    continue
                changes.append(e.value.value - Fraction(v0))
            else:
                changes.append(e.value.value)
    if changes is not None and isinstance(v0, Fraction | int) and not isinstance(v0, bool):
        q = Fraction(0)
        for c in changes:
            q = _gcd(q, abs(c))
        if q == 0:
            return 1
        v = Fraction(v0)
        first, last = -((v - lo) // q), (hi - v) // q  # ⌈(lo − v)/q⌉ and ⌊(hi − v)/q⌋
        return max(0, int(last - first) + 1)
    if r.sort.kind is ir.SortKind.INT:
        return max(0, math.floor(hi) - math.ceil(lo) + 1)
    return None


def _gcd(a: Fraction, b: Fraction) -> Fraction:
    """The greatest common divisor of two non-negative rationals (0 with 0 is 0)."""
    import math

    x, y = a, b
    den = x.denominator * y.denominator // math.gcd(x.denominator, y.denominator)
    return Fraction(math.gcd(int(x * den), int(y * den)), den)


def _tighter(a: Any, b: Any, pick: Callable[[Any, Any], Any]) -> Any:
    if a is None:
        return b
    if b is None:
        return a
    return pick(a, b)
