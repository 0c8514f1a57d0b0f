"""``horizon``: a new horizon (the schema says it is a positive integer)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from catc import ir
from catrt.changes.base import Change
from catrt.model import ModelState


def apply(
    state: ModelState, inst: ir.Instance, sources: Mapping[str, str], body: Mapping[str, Any], origins: dict[str, str]
) -> ModelState:
    origins["horizon"] = "horizon"
    return state.with_problem(horizon=body["horizon"])


CHANGE = Change(("horizon",), apply)
