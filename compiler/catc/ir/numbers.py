"""Exact numbers as text: the one place a ``Fraction`` becomes a string.

Every number of the language is a rational.  Three spellings cover every use:

* :func:`number_text` — the language's own syntax, read back exactly: ``16``, ``4.25``,
  ``(/ 1 3)`` (IR printing, ``.cat`` skeletons, PDDL);
* :func:`ratio_text` — the same, with ``1/3`` for a fraction that has no finite decimal
  (messages, diagrams, values of a state);
* :func:`decimal_text` — for reading at a glance: the exact decimal when it has at most
  ``places`` digits after the point, else ``≈0.333333`` (tables, JSON ``decimal`` fields).

A terminating decimal is found by the factors 2 and 5 of the denominator, so a number with a
4,000-digit denominator costs a handful of big-integer operations, not 4,000 of them.

Integers are written by :func:`int_text` and read by :func:`int_value`, which take any
number of digits: Python's own ``str(int)`` and ``int(str)`` refuse more than 4,300 (a
value a solver computes may have more, and the limits of docs/limits.md may be raised).
"""

from __future__ import annotations

from fractions import Fraction

#: Integers below this (in magnitude) are converted by Python directly (its limit: 4,300 digits).
_DIRECT = 10**4000


def int_text(n: int) -> str:
    """The decimal digits of ``n``, however many there are."""
    if -_DIRECT < n < _DIRECT:
        return str(n)
    if n < 0:
        return "-" + int_text(-n)
    half = max(1, int(n.bit_length() * 0.30102999566398) // 2)
    high, low = divmod(n, 10**half)
    return int_text(high) + int_text(low).rjust(half, "0")


def int_value(text: str) -> int:
    """The integer written in ``text`` (decimal digits, an optional sign), however long."""
    text = text.strip()
    if len(text) <= 4000:
        return int(text)
    if text[0] in "+-":
        value = int_value(text[1:])
        return -value if text[0] == "-" else value
    half = len(text) // 2
    scale: int = 10 ** (len(text) - half)
    return int_value(text[:half]) * scale + int_value(text[half:])


def exact_decimal(v: Fraction, max_places: int | None = None) -> str | None:
    """The exact decimal expansion of ``v`` (``-0.25``), or None when it does not terminate
    (or needs more than ``max_places`` digits after the point)."""
    if v.denominator == 1:
        return int_text(v.numerator)
    den = v.denominator
    twos = (den & -den).bit_length() - 1
    den >>= twos
    fives = 0
    while den % 5 == 0:  # strip 5, 25, 625, ...: a few divisions, not one per factor
        power, k = 5, 1
        while den % (power * power) == 0:
            power, k = power * power, k * 2
        den //= power
        fives += k
    places = max(twos, fives)
    if den != 1 or (max_places is not None and places > max_places):
        return None
    digits = int_text(abs(v.numerator) * 10**places // v.denominator).rjust(places + 1, "0")
    return f"{'-' if v < 0 else ''}{digits[:-places]}.{digits[-places:]}"


def number_text(v: Fraction, max_places: int | None = None) -> str:
    """``v`` as the language writes it: an integer, an exact decimal, or ``(/ n d)``."""
    return exact_decimal(v, max_places) or f"(/ {int_text(v.numerator)} {int_text(v.denominator)})"


def ratio_text(v: Fraction) -> str:
    """``v`` as an integer, an exact decimal, or ``n/d``."""
    return exact_decimal(v) or fraction_text(v)


def fraction_text(v: Fraction) -> str:
    """``n/d`` (``n`` for an integer)."""
    return int_text(v.numerator) if v.denominator == 1 else f"{int_text(v.numerator)}/{int_text(v.denominator)}"


def decimal_text(v: Fraction, places: int = 6) -> str:
    """A readable decimal: exact when it terminates within ``places`` digits, else an
    approximation marked ``≈`` with ``places`` significant digits."""
    return exact_decimal(v, places) or f"≈{_approximate(v, places)}"


def _approximate(v: Fraction, places: int) -> str:
    """``v`` to ``places`` significant digits (also past the range of a float)."""
    try:
        return f"{float(v):.{places}g}"
    except OverflowError:  # |v| ≥ 1.8e308: the exponent from the integer part's digits
        whole = abs(v.numerator) // v.denominator
        digits = int_text(whole)
        exponent = len(digits) - 1
        mantissa = float(digits[: places + 2]) / 10 ** (min(len(digits), places + 2) - 1)
        sign = "-" if v < 0 else ""
        return f"{sign}{mantissa:.{max(0, places - 1)}f}e+{exponent}"
