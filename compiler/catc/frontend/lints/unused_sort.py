"""W0102: a sort nothing uses — no parameter, resource, constant, subsort, nor an object of
the domain's problems checked in the same run."""

from __future__ import annotations

from collections.abc import Sequence

from catc import ir
from catc.frontend.lints.base import IsUser, Lint, Scope, base_sort, user
from catgrammar import codes
from catgrammar.diagnostics import Diagnostics


def run(domain: ir.Domain, problems: Sequence[ir.Problem], diags: Diagnostics, is_user: IsUser) -> None:
    used: set[str] = {o.sort.name for p in problems for o in p.objects.values()}
    for m in domain.morphisms.values():
        used |= {base_sort(p.sort) for p in m.params}
    used |= {base_sort(r.sort) for r in domain.resources.values()}
    used |= {c.sort.name for c in domain.constants.values()}
    used |= {s.parent for s in domain.sorts.values() if s.parent}
    for s in domain.sorts.values():
        if s.name not in used and s.span is not None and user(s.span, is_user):
            diags.report(codes.UNUSED_SORT, f"sort '{s.name}' is never used", s.span)


LINT = Lint(codes.UNUSED_SORT, Scope.DOMAIN, run)
