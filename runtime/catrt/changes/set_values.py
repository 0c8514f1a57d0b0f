"""``set``: resources' values, as sensed — exact numbers (with a unit, converted as catc
converts a ``.cat`` literal), truth values, sets of symbols, symbols."""

from __future__ import annotations

import re
from collections.abc import Mapping
from fractions import Fraction
from typing import Any

from catc import ir
from catc.api import convert
from catc.ir.numbers import ratio_text
from catgrammar.diagnostics import did_you_mean
from catrt.changes.base import Change, Rejection, json_text
from catrt.events import exact, quantity
from catrt.model import ModelState, StoredValue


def apply(
    state: ModelState, inst: ir.Instance, sources: Mapping[str, str], body: Mapping[str, Any], origins: dict[str, str]
) -> ModelState:
    values: dict[str, StoredValue] = {}
    for name, value in body["set"].items():
        r = inst.resources.get(name)
        if r is None:
            raise Rejection(f"set.{name}: no resource named '{name}'{did_you_mean(name, inst.resources)}")
        values[name] = _stored(name, value, r)
        origins[f"init.{name}"] = f"set.{name}"
    return state.with_init(values)


def _stored(name: str, value: Any, r: ir.Resource) -> StoredValue:
    kind = r.sort.kind
    if r.sort.is_numeric:
        number = exact(value) if isinstance(value, str) else None
        with_unit = quantity(value) if isinstance(value, str) and number is None else None
        if with_unit is not None:
            number = _in_unit(name, value, with_unit, r)
        if number is None:
            raise Rejection(f"set.{name}: {name} is a number ({kind.value}); {json_text(value)} is not one")
        if kind is ir.SortKind.INT and number.denominator != 1:
            raise Rejection(f"set.{name}: {name} is an integer; {value} is not")
        return ratio_text(number)
    if kind is ir.SortKind.BOOL:
        if isinstance(value, bool):
            return value
        if value in ("true", "false"):
            return value == "true"
        raise Rejection(f"set.{name}: {name} is true or false; {json_text(value)} is not")
    if kind is ir.SortKind.SET:
        if not isinstance(value, list):
            raise Rejection(f"set.{name}: {name} is a set: give a list of symbols, not {json_text(value)}")
        bad = [v for v in value if not isinstance(v, str) or not _SYMBOL.fullmatch(v)]
        if bad:
            raise Rejection(f"set.{name}: {json_text(bad[0])} is not a symbol")
        return sorted(set(value))
    # a symbol is written into the problem's (:init ...) as it is: one name, nothing else
    if not isinstance(value, str) or not _SYMBOL.fullmatch(value):
        raise Rejection(f"set.{name}: {name} holds a symbol of {r.sort.name}; {json_text(value)} is not one")
    return value


def _in_unit(name: str, text: str, with_unit: tuple[Fraction, str], r: ir.Resource) -> Fraction:
    """``"2 GB"`` for a resource in MB: 2000, converted exactly as catc converts a ``.cat`` literal."""
    number, unit = with_unit
    if r.unit is None:
        raise Rejection(f"set.{name}: {name} has no unit; give a plain number, not '{text}'")
    try:
        return convert(number, unit, r.unit)
    except ValueError as exc:
        raise Rejection(f"set.{name}: '{text}': {exc}") from None


_SYMBOL = re.compile(r"[A-Za-z_][A-Za-z0-9_-]*")  # a name of the language (catgrammar.tokens)


CHANGE = Change(("set",), apply)
