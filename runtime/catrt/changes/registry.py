"""The kinds of change an event carries, by field, in the order they apply.  Adding a kind:
one module defining ``CHANGE`` (see :mod:`catrt.changes.base`), one line here (a field per
line; a module that reads two fields has two lines), and its field in the event schema.
Modules are imported on first use (reading an event's shape needs only the names)."""

from __future__ import annotations

import importlib
from collections.abc import Iterable
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # pragma: no cover
    from catrt.changes.base import Change

CHANGES: dict[str, str] = {
    "set": "catrt.changes.set_values",
    "goal": "catrt.changes.goal",
    "metric": "catrt.changes.metric",
    "softs": "catrt.changes.softs",
    "horizon": "catrt.changes.horizon",
    "catalog": "catrt.changes.catalog",
    "health": "catrt.changes.catalog",
}


def fields() -> tuple[str, ...]:
    return tuple(CHANGES)


def get(field: str) -> Change:
    """The change kind of the event field ``field`` (KeyError when there is none)."""
    change: Change = importlib.import_module(CHANGES[field]).CHANGE
    return change


def for_fields(given: Iterable[str]) -> list[Change]:
    """The kinds of change the fields ``given`` carry, each once, in the registry's order."""
    present = set(given)
    modules = dict.fromkeys(module for field, module in CHANGES.items() if field in present)
    return [importlib.import_module(module).CHANGE for module in modules]
