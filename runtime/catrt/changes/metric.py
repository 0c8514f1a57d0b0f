"""``metric``: a new metric (one balanced expression), or none (``null``)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from catc import ir
from catrt.changes.base import Change, balanced
from catrt.model import ModelState


def apply(
    state: ModelState, inst: ir.Instance, sources: Mapping[str, str], body: Mapping[str, Any], origins: dict[str, str]
) -> ModelState:
    if body["metric"] is not None:
        balanced(body["metric"], "metric")
    origins["metric"] = "metric"
    return state.with_problem(metric=body["metric"])


CHANGE = Change(("metric",), apply)
