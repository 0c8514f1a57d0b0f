"""How many steps a composition may take: the horizon and what bounds it."""

from __future__ import annotations

from collections.abc import Collection

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
