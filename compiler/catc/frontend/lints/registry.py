"""The lints, by name (the code's name in :mod:`catgrammar.codes`), in the order they run.
Adding a lint: one module defining ``LINT`` (see :mod:`catc.frontend.lints.base`), and one
line here."""

from __future__ import annotations

from catc.frontend.lints.base import Lint
from catgrammar.registry import Registry

LINTS: dict[str, str] = {
    "unbounded-parameter": "catc.frontend.lints.unbounded_parameter",
    "unused-resource": "catc.frontend.lints.unused_resource",
    "unused-sort": "catc.frontend.lints.unused_sort",
    "unwritable-goal": "catc.frontend.lints.unwritable_goal",
    "unreachable-morphism": "catc.frontend.lints.unreachable_morphism",
}

REGISTRY: Registry[Lint] = Registry("lint", LINTS, "LINT")


def names() -> list[str]:
    return REGISTRY.names()


def get(name: str) -> Lint:
    """The lint named ``name`` (:class:`~catgrammar.registry.UnknownName`, a KeyError, when
    there is none)."""
    return REGISTRY.get(name)
