"""The targets, by name.  Adding a target: one module defining ``TARGET`` (see
:mod:`catc.targets.base`), and one line here.  Modules are imported on first use, so
exporting to one target loads only its own module."""

from __future__ import annotations

from catc.targets.base import Target
from catgrammar.registry import Registry

TARGETS: dict[str, str] = {
    "pddl": "catc.targets.pddl_target",
    "pddlplus": "catc.targets.pddlplus_target",
    "smt2": "catc.targets.smt2",
    "cat": "catc.targets.cat",
    "ground": "catc.targets.ground",
}

REGISTRY: Registry[Target] = Registry("target", TARGETS, "TARGET")


def names() -> list[str]:
    return REGISTRY.names()


def get(name: str) -> Target:
    """The target named ``name`` (:class:`~catgrammar.registry.UnknownName`, a KeyError, when
    there is none)."""
    return REGISTRY.get(name)


def by_command(words: tuple[str, ...]) -> Target | None:
    """The target the command line spells ``words`` (``("export", "pddl")``, ``("compile",)``)."""
    for name in TARGETS:
        target = get(name)
        if target.command == words:
            return target
    return None
