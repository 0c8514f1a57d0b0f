"""Bounds every reachable state keeps on the numeric resources, in the search's task order
(:func:`infer_bounds`; the derivation itself is :func:`catc.semantics.bounds.numeric_ranges`)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from catc import ir
from catc.semantics.bounds import numeric_ranges
from catc.semantics.search.common import _TaskShape


def _tighter(a: Any, b: Any, pick: Callable[[Any, Any], Any]) -> Any:
    return b if a is None else a if b is None else pick(a, b)


def infer_bounds(inst: ir.Instance, task: _TaskShape) -> list[tuple[Any, Any]]:
    """Bounds (lo, hi; None: none) that every reachable state keeps on each numeric resource,
    in the task's order: :func:`catc.semantics.bounds.numeric_ranges` (its docstring argues
    them sound), over the task's numbers and their initial values."""
    numbers = {n: v for n, v, k in zip(task.names, task.init, task.kinds) if k == "number"}
    ranges = numeric_ranges(inst, numbers)
    return [ranges.get(n, (None, None)) for n in task.names]
