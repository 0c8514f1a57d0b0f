"""Statistics and verdicts: median and quartiles of wall times, and the outcome marker of an
answer (SAT, UNSAT, OPT, SUBOPT, ``BETTER ✗``, TIMEOUT, ERR, INVALID) judged exactly against
the expectation."""

from __future__ import annotations

import statistics
from collections.abc import Sequence
from fractions import Fraction
from typing import TYPE_CHECKING

from catc.bench.problems import fraction_text

if TYPE_CHECKING:
    from catc.bench.problems import Expected
    from catc.bench.runners import ToolRun


def quartiles(xs: Sequence[float]) -> tuple[float, float, float]:
    """(median, lower quartile, upper quartile) of ``xs`` (the quartiles by linear
    interpolation between order statistics, ``statistics.quantiles(method='inclusive')``);
    with one value all three are that value."""
    if not xs:
        raise ValueError("no measurements")
    if len(xs) == 1:
        return xs[0], xs[0], xs[0]
    q = statistics.quantiles(xs, n=4, method="inclusive")
    return statistics.median(xs), q[0], q[2]


def judge(
    status: str,
    expected_status: str | None,
    value: Fraction | None = None,
    optimum: Fraction | None = None,
    sense: str | None = None,
) -> str:
    """The outcome marker of one answer.

    ``status`` is the tool's answer: ``sat``/``opt``/``subopt`` (a composition was found),
    ``unsat``, ``timeout``, ``error`` or ``invalid``.  ``value`` is the composition's objective
    value and ``optimum`` the known optimum (both exact), ``sense`` ``minimize`` or
    ``maximize``.  Returns SAT, UNSAT, OPT, SUBOPT, ``BETTER ✗``, TIMEOUT, ERR or INVALID;
    ``✗`` is appended to SAT/UNSAT when the answer contradicts ``expected_status``."""
    if status == "timeout":
        return "TIMEOUT"
    if status == "invalid":
        return "INVALID"
    if status not in ("sat", "opt", "subopt", "unsat"):
        return "ERR"
    if status == "unsat":
        return "UNSAT ✗" if expected_status == "sat" else "UNSAT"
    if expected_status == "unsat":
        return "SAT ✗"
    if optimum is None:
        return "SAT"
    if value is None:
        return "SAT"  # a composition without an objective value (should not happen)
    value, optimum = Fraction(value), Fraction(optimum)
    if value == optimum:
        return "OPT"
    better = value > optimum if sense == "maximize" else value < optimum
    return "BETTER ✗" if better else "SUBOPT"


def consensus(runs: Sequence[ToolRun]) -> ToolRun | None:
    """The most common answer of the trials (the first run with it)."""
    if not runs:
        return None
    keys = [(r.status, r.value) for r in runs]
    best = max(set(keys), key=keys.count)
    return runs[keys.index(best)]


def marker(run: ToolRun | None, exp: Expected) -> str:
    """The marker of ``run`` against ``exp``, with the value after OPT, SUBOPT and ``BETTER ✗``."""
    if run is None:
        return "—"
    m = judge(run.status, exp.status, run.value, exp.optimum, exp.sense)
    if run.value is not None and m in ("OPT", "SUBOPT", "BETTER ✗"):
        m += f" {fraction_text(run.value)}"
    return m
