"""How many steps a composition may take: the horizon and what bounds it."""

from __future__ import annotations

from catc import ir

#: The horizon when the problem names none and some morphism has no use limit.
DEFAULT_HORIZON = 10


def use_bound(inst: ir.Instance) -> int | None:
    """Σ uses over all morphisms, or None when some morphism is unlimited.  No composition
    has more non-idle steps than this."""
    total = 0
    for m in inst.morphisms.values():
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
