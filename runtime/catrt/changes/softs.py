"""``softs``: the soft constraints, all of them, each one balanced expression."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from catc import ir
from catrt.changes.base import Change, balanced
from catrt.model import ModelState


def apply(
    state: ModelState, inst: ir.Instance, sources: Mapping[str, str], body: Mapping[str, Any], origins: dict[str, str]
) -> ModelState:
    for i, soft in enumerate(body["softs"]):
        balanced(soft, f"softs[{i}]")
        origins[f"softs.{i}"] = f"softs[{i}]"
    return state.with_problem(softs=tuple(body["softs"]))


CHANGE = Change(("softs",), apply)
