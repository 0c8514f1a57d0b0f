"""One step's state change over an abstract domain: the transfer function of the analyses.

The successor-state rule of docs/semantics.md, written once for the abstract analyses —
:mod:`catc.semantics.relaxed` (relaxed reachability) and :mod:`catc.smt.counting` (the
counting lower bound): a morphism's increments and set changes are applied in turn (so
increments are summed), then an assignment overrides them.  The front end forbids an
assignment combined with another write of the same resource in one morphism
(frontend/check.py, "written twice in one effect"), so the override only ever replaces the
resource's old value.

The domain supplies the values: how one increase, decrease, add or remove changes a value, and
the join of two values (for an effect that may or may not happen).  The independent validator
(:mod:`catc.semantics.validate`) and the SMT encoder keep their own copies of the rule on
purpose: they check each other (tests/test_differential*.py, the mutation tests).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Protocol, TypeAlias, TypeVar

from catc import ir

V = TypeVar("V")


class Domain(Protocol[V]):
    """An abstract domain for the transfer function."""

    def join(self, a: V, b: V) -> V:
        """A value covering both ``a`` and ``b``."""
        ...

    def change(self, kind: ir.EffectKind, old: V, amount: V) -> V:
        """``old`` after one effect of ``kind`` (not an assignment) by ``amount``."""
        ...


#: One write of a step: the effect, its value (amount, element, or assigned value) in the
#: domain, and whether it surely happens (False: it may or may not — a dropped effect).
Write: TypeAlias = tuple[ir.Effect, V, bool]


def post(domain: Domain[V], writes: Iterable[Write[V]], current: Callable[[str], V]) -> dict[str, V]:
    """The new value of each resource the ``writes`` touch, from the ``current`` values:
    increments (and set changes) applied in order, then an assignment overriding them.  An
    effect that may not happen joins its result with the value it would have changed; several
    assignments of one resource (not in checked models) join their values."""
    out: dict[str, V] = {}
    assigned: dict[str, V] = {}
    for effect, value, certain in writes:
        name = effect.resource
        if effect.kind is ir.EffectKind.ASSIGN:
            new = value if certain else domain.join(value, out.get(name, current(name)))
            assigned[name] = new if name not in assigned else domain.join(assigned[name], new)
            continue
        old = out.get(name, current(name))
        new = domain.change(effect.kind, old, value)
        out[name] = new if certain else domain.join(old, new)
    out.update(assigned)
    return out
