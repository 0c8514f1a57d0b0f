"""W0105: a real parameter without both bounds (optimisation over it may be unbounded, and
exports cannot grid it)."""

from __future__ import annotations

from collections.abc import Sequence

from catc import ir
from catc.frontend.lints.base import IsUser, Lint, Scope, user
from catgrammar import codes
from catgrammar.diagnostics import Diagnostics


def run(domain: ir.Domain, problems: Sequence[ir.Problem], diags: Diagnostics, is_user: IsUser) -> None:
    for m in domain.morphisms.values():
        for p in m.params:
            if p.sort.kind is ir.SortKind.REAL and (p.lower is None or p.upper is None) and user(p.span, is_user):
                missing = (
                    "no bounds"
                    if p.lower is None and p.upper is None
                    else ("no lower bound" if p.lower is None else "no upper bound")
                )
                diags.report(
                    codes.UNBOUNDED_PARAMETER,
                    f"real parameter '{p.name}' of '{m.name}' has {missing}; "
                    f"optimisation over it may be unbounded and exports cannot grid it",
                    p.span,
                )


LINT = Lint(codes.UNBOUNDED_PARAMETER, Scope.DOMAIN, run)
