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
"""

from __future__ import annotations

from fractions import Fraction


def exact_decimal(v: Fraction, max_places: int | None = None) -> str | None:
    """The exact decimal expansion of ``v`` (``-0.25``), or None when it does not terminate
    (or needs more than ``max_places`` digits after the point)."""
    if v.denominator == 1:
        return str(v.numerator)
    den, twos, fives = v.denominator, 0, 0
    while den % 2 == 0:
        den //= 2
        twos += 1
    while den % 5 == 0:
        den //= 5
        fives += 1
    places = max(twos, fives)
    if den != 1 or (max_places is not None and places > max_places):
        return None
    digits = str(abs(v.numerator) * 10**places // v.denominator).rjust(places + 1, "0")
    return f"{'-' if v < 0 else ''}{digits[:-places]}.{digits[-places:]}"


def number_text(v: Fraction, max_places: int | None = None) -> str:
    """``v`` as the language writes it: an integer, an exact decimal, or ``(/ n d)``."""
    return exact_decimal(v, max_places) or f"(/ {v.numerator} {v.denominator})"


def ratio_text(v: Fraction) -> str:
    """``v`` as an integer, an exact decimal, or ``n/d``."""
    return exact_decimal(v) or f"{v.numerator}/{v.denominator}"


def decimal_text(v: Fraction, places: int = 6) -> str:
    """A readable decimal: exact when it terminates within ``places`` digits, else an
    approximation marked ``≈`` with ``places`` significant digits."""
    return exact_decimal(v, places) or f"≈{float(v):.{places}g}"
