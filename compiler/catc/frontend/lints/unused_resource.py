"""W0101: a resource no morphism reads or writes."""

from __future__ import annotations

from collections.abc import Sequence

from catc import ir
from catc.frontend.lints.base import IsUser, Lint, Scope, user
from catgrammar import codes
from catgrammar.diagnostics import Diagnostics


def run(domain: ir.Domain, problems: Sequence[ir.Problem], diags: Diagnostics, is_user: IsUser) -> None:
    used: set[str] = set()
    for m in domain.morphisms.values():
        used |= m.reads | m.writes
    for r in domain.resources.values():
        if r.name not in used and user(r.span, is_user):
            diags.report(codes.UNUSED_RESOURCE, f"resource '{r.name}' is never read or written by any morphism", r.span)


LINT = Lint(codes.UNUSED_RESOURCE, Scope.DOMAIN, run)
