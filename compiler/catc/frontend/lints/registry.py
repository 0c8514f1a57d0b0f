"""The lints, by name (the code's name in :mod:`catgrammar.codes`), in the order they run.
Adding a lint: one module defining ``LINT`` (see :mod:`catc.frontend.lints.base`), and one
line here."""

from __future__ import annotations

import importlib

from catc.frontend.lints.base import Lint

LINTS: dict[str, str] = {
    "unbounded-parameter": "catc.frontend.lints.unbounded_parameter",
    "unused-resource": "catc.frontend.lints.unused_resource",
    "unused-sort": "catc.frontend.lints.unused_sort",
    "unwritable-goal": "catc.frontend.lints.unwritable_goal",
    "unreachable-morphism": "catc.frontend.lints.unreachable_morphism",
}


def names() -> list[str]:
    return list(LINTS)


def get(name: str) -> Lint:
    """The lint named ``name`` (KeyError when there is none)."""
    lint: Lint = importlib.import_module(LINTS[name]).LINT
    return lint
