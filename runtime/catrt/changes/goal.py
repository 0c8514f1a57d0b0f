"""``goal``: a new goal, one condition."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from catc import ir
from catrt.changes.base import Change, one_expression
from catrt.model import ModelState


def apply(
    state: ModelState, inst: ir.Instance, sources: Mapping[str, str], body: Mapping[str, Any], origins: dict[str, str]
) -> ModelState:
    one_expression(body["goal"], "goal")
    origins["goal"] = "goal"
    return state.with_problem(goal=body["goal"])


CHANGE = Change(("goal",), apply)
