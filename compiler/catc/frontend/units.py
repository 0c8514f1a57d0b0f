"""Units and dimensions: pint's registry, read exactly, with catc's definitions (``units.txt``).

Imported only when a model declares a ``:unit`` or writes a literal with a unit, so checking
or solving a model without units never imports pint (``tests/test_entry.py``).  pint is read
with ``non_int_type=Fraction``: every definition's decimal is an exact rational, so every
conversion factor is one too.  The rules the checker applies are in docs/language.md §Units.
"""

from __future__ import annotations

import functools
from fractions import Fraction
from pathlib import Path
from typing import Any

DEFINITIONS = Path(__file__).with_name("units.txt")

# Names for derived dimensions, most useful first (pint's own names, several per dimensionality).
_DIMENSION_NAMES = (
    "energy",
    "power",
    "velocity",
    "acceleration",
    "frequency",
    "force",
    "torque",
    "area",
    "volume",
    "charge",
    "electric_potential",
    "resistance",
    "pressure",
    "density",
)


#: Units a did-you-mean suggestion may offer (pint knows thousands; these are the usual ones).
COMMON = (
    "B", "kB", "MB", "GB", "TB", "KiB", "MiB", "GiB", "TiB", "bit", "Mbit", "Gbit", "Mbit/s", "Gbit/s",
    "s", "ms", "us", "ns", "min", "h", "day", "Hz", "kHz", "MHz", "GHz",
    "m", "mm", "cm", "km", "m/s", "km/h", "rad", "deg", "kg", "g",
    "W", "mW", "kW", "Wh", "kWh", "mAh", "Ah", "J", "V", "A", "N", "N*m",
    "USD", "EUR", "GBP", "CHF", "JPY", "px", "MP", "fps", "frame", "msg", "FLOP", "TFLOPS", "TOPS",
    "token", "core", "count", "percent",
)  # fmt: skip


class UnitError(Exception):
    """A unit text pint cannot read, or one catc cannot use (offset units)."""


class MissingUnits(UnitError):
    """pint is not installed."""


@functools.cache
def registry() -> Any:
    try:
        import pint
    except ImportError as exc:  # pragma: no cover - pint is a core dependency
        raise MissingUnits("units need the pint package: pip install pint") from exc
    try:
        reg: Any = pint.UnitRegistry(non_int_type=Fraction, cache_folder=":auto:", on_redefinition="ignore")
    except Exception:  # pragma: no cover - an unwritable cache folder
        reg = pint.UnitRegistry(non_int_type=Fraction, on_redefinition="ignore")
    reg.load_definitions(str(DEFINITIONS))
    return reg


class Unit:
    """A unit as declared (``text``), with pint's unit and its dimensionality."""

    __slots__ = ("text", "pint", "dims")

    def __init__(self, text: str, pint_unit: Any, dims: tuple[tuple[str, Fraction], ...]) -> None:
        self.text = text
        self.pint = pint_unit
        self.dims = dims

    def __repr__(self) -> str:
        return f"Unit({self.text!r})"

    @property
    def dimension(self) -> str:
        return dimension_name(self.dims)

    def show(self) -> str:
        """``GB: information`` — the unit and its dimension, as diagnostics name them."""
        return f"{self.text}: {self.dimension}"

    def same_dimension(self, other: Unit) -> bool:
        return self.dims == other.dims

    @property
    def dimensionless(self) -> bool:
        return not self.dims

    def times(self, other: Unit) -> Unit:
        return _make(f"{_wrap(self.text)}*{_wrap(other.text)}", self.pint * other.pint)

    def over(self, other: Unit) -> Unit:
        return _make(f"{_wrap(self.text)}/{_wrap(other.text)}", self.pint / other.pint)

    def inverse(self) -> Unit:
        return _make(f"1/{_wrap(self.text)}", 1 / self.pint)


def _wrap(text: str) -> str:
    return f"({text})" if any(c in text for c in "*/ ") else text


def _dims_of(pint_unit: Any) -> tuple[tuple[str, Fraction], ...]:
    reg = registry()
    dims = reg.get_dimensionality(pint_unit)
    return tuple(sorted((k, Fraction(v)) for k, v in dict(dims).items() if v))


def _make(text: str, pint_unit: Any) -> Unit:
    return Unit(text, pint_unit, _dims_of(pint_unit))


DIMENSIONLESS_TEXT = "1"


@functools.cache
def parse(text: str) -> Unit:
    """The unit named by ``text`` (``GB``, ``W*h``, ``m/s``, ``USD``); UnitError when pint does
    not know it or it is an offset unit (``degC``: conversions would not be linear)."""
    reg = registry()
    try:
        u = reg.parse_units(text)
    except Exception as exc:  # pint raises several kinds (undefined, syntax, ...)
        raise UnitError(_undefined_message(text, exc)) from exc
    if not reg.Quantity(Fraction(1), u)._is_multiplicative:
        raise UnitError(f"'{text}' is an offset unit; use an absolute one (K, or delta_degC for differences)")
    return Unit(text, u, _dims_of(u))


def is_unit(text: str) -> bool:
    try:
        parse(text)
    except UnitError:
        return False
    return True


def _undefined_message(text: str, exc: Exception) -> str:
    return f"unknown unit '{text}'"


def factor(source: Unit, target: Unit) -> Fraction:
    """The exact number ``f`` with ``1 source = f target`` (same dimension)."""
    reg = registry()
    mag = reg.Quantity(Fraction(1), source.pint).to(target.pint).magnitude
    return Fraction(mag)


def dimension_name(dims: tuple[tuple[str, Fraction], ...]) -> str:
    """``information``, ``currency``, ``energy``, ``length/time``, ``dimensionless``."""
    if not dims:
        return "dimensionless"
    if len(dims) == 1 and dims[0][1] == 1:
        return _base_name(dims[0][0])
    reg = registry()
    for name in _DIMENSION_NAMES:
        try:
            known = reg.get_dimensionality(f"[{name}]")
        except Exception:  # pragma: no cover - every name above is pint's
            continue
        if tuple(sorted((k, Fraction(v)) for k, v in dict(known).items() if v)) == dims:
            return name.replace("_", " ")
    num = [_power(_base_name(k), v) for k, v in dims if v > 0]
    den = [_power(_base_name(k), -v) for k, v in dims if v < 0]
    top = "·".join(num) or "1"
    return top + ("/" + "·".join(den) if den else "")


def _base_name(key: str) -> str:
    name = key.strip("[]")
    if name.startswith("currency_"):
        return f"currency {name[len('currency_') :]}"
    return name.replace("_", " ")


def _power(name: str, exp: Fraction) -> str:
    return name if exp == 1 else f"{name}^{exp}"
