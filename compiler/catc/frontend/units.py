"""Units and dimensions: pint's registry, read exactly, with catc's definitions (``units.txt``).

A unit is its dimensionality (exponents of base dimensions: ``[information]``, ``[length]``,
``[currency]``, ...) and its *scale*, the exact size of one unit in the base units of that
dimensionality (1 GB = 8·10⁹ bit); conversions divide scales, products multiply them, so only
reading a unit's name needs pint.  pint is read with ``non_int_type=Fraction``: every
definition's decimal is an exact rational, so every scale is one too.

Reading a name goes to a generated index first (``_unit_index.py``: the usual units, made from
pint by ``python -m catc.frontend.units --write``; ``--check`` and ``tests/test_units.py`` fail
when it differs from what pint says), and to pint only for the others, so a model whose units
are all usual ones never imports pint (about 0.2-0.4 s).  A model without units never reads
this module's index either (``tests/test_entry.py``).  The rules the checker applies are in
docs/language.md §Units and dimensions.
"""

from __future__ import annotations

import functools
import os
import sys
from fractions import Fraction
from pathlib import Path
from typing import Any

DEFINITIONS = Path(__file__).with_name("units.txt")
INDEX = Path(__file__).with_name("_unit_index.py")

Dims = tuple[tuple[str, Fraction], ...]

#: Units a did-you-mean suggestion may offer, and the index holds (pint knows thousands).
COMMON = (
    "B", "kB", "MB", "GB", "TB", "KiB", "MiB", "GiB", "TiB", "bit", "kbit", "Mbit", "Gbit", "byte",
    "s", "ms", "us", "ns", "min", "h", "hour", "day", "Hz", "kHz", "MHz", "GHz",
    "m", "mm", "cm", "km", "mi", "ft", "inch", "rad", "deg", "degree", "sr", "kg", "g",
    "W", "mW", "kW", "Wh", "mWh", "kWh", "mAh", "Ah", "J", "kJ", "V", "mV", "A", "mA", "N", "K",
    "delta_degC", "Pa", "kPa", "lx",
    "USD", "US_cent", "EUR", "euro_cent", "GBP", "CHF", "JPY",
    "px", "MP", "frame", "fps", "msg", "FLOP", "FLOPS", "TFLOPS", "TOPS", "op", "token",
    "tokens_per_second", "core", "count", "percent", "dimensionless",
    "m/s", "km/h", "rad/s", "m/s^2", "Mbit/s", "Gbit/s", "MB/s", "GB/s", "W*h", "A*s", "N*m",
    "msg/s", "px/s",
)  # fmt: skip

# Names for derived dimensions, most useful first (pint's own names, several per dimensionality).
_DIMENSION_NAMES = (
    "energy",
    "power",
    "velocity",
    "acceleration",
    "frequency",
    "force",
    "area",
    "volume",
    "charge",
    "electric_potential",
    "resistance",
    "pressure",
    "density",
)


class UnitError(Exception):
    """A unit text pint cannot read, or one catc cannot use (offset units)."""


NEEDS_PINT = "units outside catc's index of the usual ones are read by pint, which is not installed"


@functools.cache
def registry() -> Any:
    """pint's registry with catc's definitions, rational (imported only when needed)."""
    try:
        import pint
    except ImportError as exc:
        raise UnitError(f"{NEEDS_PINT}: pip install 'catc-lang[units]'") from exc

    # pint's cache (~/.cache/pint) is shared by every process; CATC_PINT_CACHE names another
    # folder (the tests give each worker its own), or "off" for none (issue 28)
    folder = os.environ.get("CATC_PINT_CACHE", ":auto:")
    try:
        if folder.lower() in ("", "off"):
            raise OSError("pint's cache is off")
        reg: Any = pint.UnitRegistry(non_int_type=Fraction, cache_folder=folder, on_redefinition="ignore")
    except Exception:  # an unwritable cache folder, or none wanted
        reg = pint.UnitRegistry(non_int_type=Fraction, on_redefinition="ignore")
    reg.load_definitions(str(DEFINITIONS))
    # pint built its caches before units.txt redefined `bit`: rebuilt, or `kB` → `bit` fails
    # (it passed only when the registry came from pint's disk cache; issue 28)
    reg._build_cache()
    return reg


class Unit:
    """A unit as written (``text``), its dimensionality and its exact scale."""

    __slots__ = ("text", "dims", "scale")

    def __init__(self, text: str, dims: Dims, scale: Fraction) -> None:
        self.text = text
        self.dims = dims
        self.scale = scale

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
        return Unit(
            f"{_wrap(self.text)}*{_wrap(other.text)}", _combine(self.dims, other.dims, 1), self.scale * other.scale
        )

    def over(self, other: Unit) -> Unit:
        return Unit(
            f"{_wrap(self.text)}/{_wrap(other.text)}", _combine(self.dims, other.dims, -1), self.scale / other.scale
        )

    def inverse(self) -> Unit:
        return Unit(f"1/{_wrap(self.text)}", _combine((), self.dims, -1), 1 / self.scale)


def _wrap(text: str) -> str:
    return f"({text})" if any(c in text for c in "*/ ") else text


def _combine(a: Dims, b: Dims, sign: int) -> Dims:
    out = dict(a)
    for k, v in b:
        out[k] = out.get(k, Fraction(0)) + sign * v
    return tuple(sorted((k, v) for k, v in out.items() if v))


DIMENSIONLESS = Unit("dimensionless", (), Fraction(1))


@functools.cache
def parse(text: str) -> Unit:
    """The unit named by ``text`` (``GB``, ``W*h``, ``m/s``, ``USD``); UnitError when pint does
    not know it or it is an offset unit (``degC``: conversions would not be linear)."""
    from catc.frontend._unit_index import UNITS

    known = UNITS.get(text)
    if known is not None:
        dims, scale = known
        return Unit(text, tuple((k, Fraction(v)) for k, v in dims), Fraction(scale))
    dims_, scale_ = read_with_pint(text)
    return Unit(text, dims_, scale_)


def read_with_pint(text: str) -> tuple[Dims, Fraction]:
    """``text``'s dimensionality and exact scale, as pint (with units.txt) defines them."""
    reg = registry()  # UnitError without pint
    try:
        u = reg.parse_units(text)
    except Exception as exc:  # pint raises several kinds (undefined, syntax, ...)
        raise UnitError(f"unknown unit '{text}'") from exc
    one = reg.Quantity(Fraction(1), u)
    if not one._is_multiplicative:
        raise UnitError(f"'{text}' is an offset unit; use an absolute one (K, or delta_degC for differences)")
    dims = tuple(sorted((k, Fraction(v)) for k, v in dict(reg.get_dimensionality(u)).items() if v))
    return dims, Fraction(one.to_base_units().magnitude)


def is_unit(text: str) -> bool:
    try:
        parse(text)
    except UnitError:
        return False
    return True


def factor(source: Unit, target: Unit) -> Fraction:
    """The exact number ``f`` with ``1 source = f target`` (same dimension)."""
    return source.scale / target.scale


def dimension_name(dims: Dims) -> str:
    """``information``, ``currency``, ``energy``, ``frames/time``, ``dimensionless``."""
    if not dims:
        return "dimensionless"
    if len(dims) == 1 and dims[0][1] == 1:
        return _base_name(dims[0][0])
    from catc.frontend._unit_index import DIMENSIONS

    for name, known in DIMENSIONS:
        if tuple((k, Fraction(v)) for k, v in known) == dims:
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


# ---------------------------------------------------------------- the generated index


def index_text() -> str:
    """The text of ``_unit_index.py`` as pint says it should be."""
    reg = registry()
    lines = [
        '"""Generated by `python -m catc.frontend.units --write` from pint and units.txt: do not edit.',
        "",
        "UNITS: unit text -> (dimensionality as (base dimension, exponent) pairs, scale: the exact",
        "size of one unit in base units).  DIMENSIONS: names of derived dimensionalities.",
        '"""',
        "",
        "UNITS: dict[str, tuple[tuple[tuple[str, str], ...], str]] = {",
    ]
    for text in COMMON:
        dims, scale = read_with_pint(text)
        pairs = ", ".join(f"({k!r}, {str(v)!r})" for k, v in dims)
        lines.append(f"    {text!r}: (({pairs}{',' if len(dims) == 1 else ''}), {str(scale)!r}),")
    lines += ["}", "", "DIMENSIONS: tuple[tuple[str, tuple[tuple[str, str], ...]], ...] = ("]
    for name in _DIMENSION_NAMES:
        dims = tuple(sorted((k, Fraction(v)) for k, v in dict(reg.get_dimensionality(f"[{name}]")).items() if v))
        pairs = ", ".join(f"({k!r}, {str(v)!r})" for k, v in dims)
        lines.append(f"    ({name!r}, ({pairs}{',' if len(dims) == 1 else ''})),")
    lines += [")", ""]
    return "\n".join(lines)


def main(argv: list[str]) -> int:
    text = index_text()
    if "--write" in argv:
        INDEX.write_text(text)
        print(f"wrote {INDEX}")
        return 0
    if INDEX.exists() and INDEX.read_text() == text:
        return 0
    print(f"{INDEX} is stale: run python -m catc.frontend.units --write", file=sys.stderr)
    return 1


if __name__ == "__main__":  # pragma: no cover - the generator's command line
    sys.exit(main(sys.argv[1:]))
