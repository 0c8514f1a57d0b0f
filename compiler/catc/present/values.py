"""Values for people and for JSON: exact numbers, fresh symbols, states and steps.

Numbers are exact: an integer prints plainly, a terminating decimal as a decimal (``4.25``),
anything else as a fraction with an approximation (``1/3 (≈0.333333)``).  Fresh values from
the finite grounding are marked ``(fresh)``.  In JSON every number is an integer or a string
of an exact rational (``"17/4"``), never a float (schemas in docs/cli.md).
"""

from __future__ import annotations

from collections.abc import Mapping
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir.numbers import decimal_text, fraction_text
from catc.semantics.plan import Activation, Plan, value_to_json


def show_value(v: Any, fresh: Mapping[str, str] | None = None, unit: str | None = None) -> str:
    fresh = fresh or {}
    if isinstance(v, bool):
        text = "true" if v else "false"
    elif isinstance(v, Fraction):
        dec = decimal_text(v)
        text = dec if not dec.startswith("≈") else f"{fraction_text(v)} ({dec})"
    elif isinstance(v, frozenset):
        text = "{" + " ".join(f"{e} (fresh)" if e in fresh else e for e in sorted(v)) + "}"
    elif isinstance(v, str):
        text = f"{v} (fresh)" if v in fresh else v
    else:
        text = str(v)
    return f"{text} {unit}" if unit and isinstance(v, Fraction) else text


def params_text(params: Mapping[str, Any], fresh: Mapping[str, str], units: Mapping[str, str] | None = None) -> str:
    """``need = 1000 MB, out = image-raw``: values in their parameters' declared units."""
    units = units or {}
    return ", ".join(f"{k} = {show_value(v, fresh, units.get(k))}" for k, v in params.items())


def state_json(state: Mapping[str, Any]) -> dict:
    return {k: value_to_json(v) for k, v in state.items()}


def units_json(inst: ir.Instance) -> dict[str, str]:
    """The declared unit of every resource that has one (state values are in these units)."""
    return {r.name: r.unit for r in inst.resources.values() if r.unit}


def parameter_units_json(inst: ir.Instance) -> dict[str, dict[str, str]]:
    """``{morphism: {parameter: unit}}`` for the parameters declared with a unit."""
    out = {m.name: {p.name: p.unit for p in m.params if p.unit} for m in inst.morphisms.values()}
    return {name: units for name, units in out.items() if units}


def timings_json(timings: Mapping[str, float]) -> dict:
    return {k: round(v, 6) for k, v in timings.items()}


def steps_json(inst: ir.Instance, plan: Plan, *, kinds: bool = True) -> list:
    """The steps of a composition: each a list of ``{"morphism", ["kind",] "params"}``."""

    def activation(a: Activation) -> dict:
        doc: dict = {"morphism": a.morphism}
        if kinds:
            doc["kind"] = inst.morphisms[a.morphism].kind.value
        doc["params"] = {k: value_to_json(v) for k, v in a.params.items()}
        return doc

    return [[activation(a) for a in step] for step in plan.steps]
