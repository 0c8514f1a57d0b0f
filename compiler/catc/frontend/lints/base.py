"""What a lint is: a warning code (a ``W01…`` code of :mod:`catgrammar.codes`), the scope it
looks at — one checked domain, or one checked instance (a problem with its domain) — and the
function that reports it.  Adding a lint: one module in this package defining ``LINT``, and
one line in :mod:`catc.frontend.lints.registry`."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from enum import Enum
from typing import NamedTuple

from catc import ir
from catgrammar.diagnostics import Diagnostics
from catgrammar.span import Span

#: A file name → whether it is the user's (lints never report on the standard library).
IsUser = Callable[[str], bool]


class Scope(str, Enum):
    DOMAIN = "domain"  # run(domain, problems, diags, is_user): ``problems`` are its problems checked in the same run
    INSTANCE = "instance"  # run(instance, diags, is_user)


DomainRun = Callable[[ir.Domain, Sequence[ir.Problem], Diagnostics, IsUser], None]
InstanceRun = Callable[[ir.Instance, Diagnostics, IsUser], None]


class Lint(NamedTuple):  # (not a dataclass: `catc solve` does not import dataclasses)
    code: str  # its W-code
    scope: Scope
    run: DomainRun | InstanceRun


def user(span: Span | None, is_user: IsUser) -> bool:
    """Whether ``span`` is in one of the user's files."""
    return span is not None and is_user(span.file)


def base_sort(sort: ir.Sort) -> str:
    """The sort a value of ``sort`` is made of: a set's element sort, else itself."""
    return sort.element.name if sort.kind is ir.SortKind.SET and sort.element else sort.name
