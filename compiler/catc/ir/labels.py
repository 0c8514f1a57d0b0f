"""Labels of source constructs: where each labelled constraint comes from, in words.

Every constraint the encoder files under a label (``pre/m/i``, ``eff/m/i``, ``init/r``,
``goal/i``, ``bound/m/p``, ``bounds/r``, ``uses/m``, ``horizon``) maps back to a span and a
sentence here, for diagnoses, relaxations and the language server.
"""

from __future__ import annotations

from dataclasses import dataclass

from catc import ir
from catc.ir.numbers import number_text
from catc.ir.text import effect_text, to_text
from catgrammar.span import Span


@dataclass(frozen=True)
class LabelInfo:
    label: str
    kind: str  # precondition | effect | initial value | goal | parameter bounds | resource bounds | use limit | horizon
    text: str  # the construct, as written (normalised)
    span: Span | None
    owner: str | None = None  # the morphism, resource or None
    declared: Span | None = None  # a default initial value (no span): where its resource is declared


def label_index(inst: ir.Instance) -> dict[str, LabelInfo]:
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
                label = f"bound/{m.name}/{p.name}"
                out[label] = LabelInfo(
                    label, "parameter bounds", f"{p.name} in [{lo}, {hi}]", p.bounds_span or p.span, m.name
                )
        if m.uses is not None:
            label = f"uses/{m.name}"
            out[label] = LabelInfo(label, "use limit", f":uses {m.uses}", m.span, m.name)
    for r in inst.resources.values():
        if r.lower is not None or r.upper is not None:
            lo = number_text(r.lower) if r.lower is not None else "*"
            hi = number_text(r.upper) if r.upper is not None else "*"
            label = f"bounds/{r.name}"
            out[label] = LabelInfo(label, "resource bounds", f"{r.name} in [{lo}, {hi}]", r.span, r.name)
    for name, init in inst.problem.init.items():
        if name in inst.resources:
            declared = inst.resources[name].span if init.span is None else None  # the default of its sort
            out[init.label] = LabelInfo(
                init.label, "initial value", f"(= {name} {to_text(init.value)})", init.span, name, declared
            )
    for lit in inst.problem.goal:
        out[lit.label] = LabelInfo(lit.label, "goal", to_text(lit.expr), lit.span)
    if inst.problem.horizon_span is not None or inst.problem.horizon is not None:
        out["horizon"] = LabelInfo(
            "horizon", "horizon", f"(:horizon {inst.problem.horizon})", inst.problem.horizon_span
        )
    else:
        out["horizon"] = LabelInfo("horizon", "horizon", "the horizon", None)
    return out
