"""Reading compositions back from a model: activations and θ values, by symbol.

Symbols decode through the finite universes (an Int index into the root sort's universe);
reserve values that appear are recorded with their sort in the plan's ``fresh`` table.
Works with every backend that has models.
"""

from __future__ import annotations

from catc import ir
from catc.ir import SortKind
from catc.semantics.plan import Activation, Plan, Value
from catc.smt.backend import Backend
from catc.smt.encoder import Encoder, Term


def read_value(backend: Backend, enc: Encoder, term: Term, sort: ir.Sort, fresh: dict[str, str]) -> Value:
    """The value of the encoded variable ``term`` of IR sort ``sort``."""
    assert isinstance(term, str), "sets are not values of parameters"
    v = backend.value(term)
    if sort.kind is SortKind.BOOL:
        return v is True
    assert not isinstance(v, bool)
    if sort.kind in (SortKind.REAL, SortKind.INT):
        return v
    u = enc.finite.universe(sort)
    element = u.elements[int(v)]
    if element in u.fresh:
        fresh[element] = u.sort_of[element]
    return element


def read_plan(backend: Backend, enc: Encoder, steps: int) -> Plan:
    """The composition of the current model over its first ``steps`` steps (idle steps dropped)."""
    out = []
    fresh: dict[str, str] = {}
    for t in range(steps):
        step = []
        for m in enc.morphisms:
            if backend.value(enc.act[t][m.name]) is not True:
                continue
            params = {p.name: read_value(backend, enc, enc.theta[t][(m.name, p.name)], p.sort, fresh) for p in m.params}
            step.append(Activation(m.name, params))
        if step:
            out.append(tuple(step))
    return Plan(tuple(out), fresh)
