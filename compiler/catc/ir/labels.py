"""Labels of source constructs: where each comes from, in words.

A constraint's label is a :class:`~catc.ir.label.Label` (defined, as data, in
:mod:`catc.ir.label`; named here too).  :func:`label_index` maps each label back to a span
and a sentence, for diagnoses, relaxations and the language server.
"""

from __future__ import annotations

from typing import NamedTuple

from catc import ir
from catc.ir.label import HORIZON, Label, LabelKind
from catc.ir.numbers import number_text
from catc.ir.text import effect_text, to_text
from catgrammar.span import Span

__all__ = ["HORIZON", "Label", "LabelInfo", "LabelKind", "label_index"]


class LabelInfo(NamedTuple):  # (not a dataclass: `catc solve` does not import dataclasses)
    label: str
    kind: str  # precondition | effect | initial value | goal | parameter bounds | resource bounds | use limit | horizon
    text: str  # the construct, as written (normalised)
    span: Span | None
    owner: str | None = None  # the morphism, resource or None
    declared: Span | None = None  # a default initial value (no span): where its resource is declared


def label_index(inst: ir.Instance, horizon: int | None = None) -> dict[str, LabelInfo]:
    """Every label of ``inst`` and what it stands for in the source; ``horizon``: the horizon
    in force, when a query knows it (the ``horizon`` label points at the problem's
    ``(:horizon k)`` only when that is the horizon in force)."""
    out: dict[str, LabelInfo] = {}
    for m in inst.morphisms.values():
        for lit in m.pre:
            out[lit.label] = LabelInfo(lit.label, "precondition", to_text(lit.expr), lit.span, m.name)
        for e in m.effects:
            out[e.label] = LabelInfo(e.label, "effect", effect_text(e), e.span, m.name)
        for p in m.params:
            if p.lower is not None or p.upper is not None:
                lo = number_text(p.lower) if p.lower is not None else "*"
                hi = number_text(p.upper) if p.upper is not None else "*"
                label = m.bound_label(p.name)
                out[label] = LabelInfo(
                    label, "parameter bounds", f"{p.name} in [{lo}, {hi}]", p.bounds_span or p.span, m.name
                )
        if m.uses is not None:
            label = m.uses_label
            out[label] = LabelInfo(label, "use limit", f":uses {m.uses}", m.span, m.name)
    for r in inst.resources.values():
        if r.lower is not None or r.upper is not None:
            lo = number_text(r.lower) if r.lower is not None else "*"
            hi = number_text(r.upper) if r.upper is not None else "*"
            label = r.bounds_label
            out[label] = LabelInfo(label, "resource bounds", f"{r.name} in [{lo}, {hi}]", r.span, r.name)
    for name, init in inst.problem.init.items():
        if name in inst.resources:
            declared = inst.resources[name].span if init.span is None else None  # the default of its sort
            out[init.label] = LabelInfo(
                init.label, "initial value", f"(= {name} {to_text(init.value)})", init.span, name, declared
            )
    for lit in inst.problem.goal:
        out[lit.label] = LabelInfo(lit.label, "goal", to_text(lit.expr), lit.span)
    if horizon is not None and horizon != inst.problem.horizon:
        given = f" (not the problem's {inst.problem.horizon}: given to the command)" if inst.problem.horizon else ""
        out[HORIZON] = LabelInfo(HORIZON, "horizon", f"the horizon {horizon}{given}", None)
    elif inst.problem.horizon_span is not None or inst.problem.horizon is not None:
        out[HORIZON] = LabelInfo(HORIZON, "horizon", f"(:horizon {inst.problem.horizon})", inst.problem.horizon_span)
    else:
        out[HORIZON] = LabelInfo(HORIZON, "horizon", "the horizon", None)
    return out
