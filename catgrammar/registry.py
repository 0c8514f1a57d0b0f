"""A registry of named parts, each imported on first use: the one shape of catc's query,
target, lint and solver-backend registries (``catc.queries.registry``,
``catc.targets.registry``, ``catc.frontend.lints.registry``, ``catc.smt.backend``).

Each entry maps a name to ``"module:attribute"`` (or ``"module"``, read with the registry's
default attribute: ``QUERY``, ``TARGET``, ``LINT``).  The entries are a plain dict the
registry reads live, so adding a part is one line in it (and a test may add one for a
while).  Nothing is imported until a part is asked for, so answering one command loads only
the modules it uses."""

from __future__ import annotations

import importlib
from collections.abc import Iterator, MutableMapping
from typing import Any, Generic, TypeVar

T = TypeVar("T")


class UnknownName(KeyError):
    """No part of that name (a ``KeyError``, as a dict lookup would raise); its text names
    what there is."""

    def __init__(self, what: str, name: str, names: list[str]) -> None:
        super().__init__(name)
        self.what, self.name, self.names = what, name, names

    def __str__(self) -> str:
        return f"unknown {self.what} {self.name!r}; expected one of: {', '.join(sorted(self.names))}"


class Registry(Generic[T]):
    """``what``: the kind of part (for messages); ``entries``: name → ``"module:attr"`` or
    ``"module"``; ``attr``: the attribute read where an entry names none."""

    def __init__(self, what: str, entries: MutableMapping[str, str], attr: str = "") -> None:
        self.what, self.entries, self.attr = what, entries, attr

    def names(self) -> list[str]:
        """The names in registration order."""
        return list(self.entries)

    def __contains__(self, name: object) -> bool:
        return name in self.entries

    def __iter__(self) -> Iterator[str]:
        return iter(list(self.entries))

    def module(self, name: str) -> Any:
        """The module of ``name``, imported now if it was not (:class:`UnknownName`)."""
        return importlib.import_module(self._spec(name)[0])

    def get(self, name: str) -> T:
        """The part named ``name`` (:class:`UnknownName` when there is none)."""
        module, attr = self._spec(name)
        part: T = getattr(importlib.import_module(module), attr)
        return part

    def _spec(self, name: str) -> tuple[str, str]:
        spec = self.entries.get(name)
        if spec is None:
            raise UnknownName(self.what, name, list(self.entries))
        module, _, attr = spec.partition(":")
        return module, attr or self.attr


__all__ = ["Registry", "UnknownName"]
