"""W0104: a goal literal that reads only resources no morphism writes (the initial state
alone decides it)."""

from __future__ import annotations

from catc import ir
from catc.frontend.lints.base import IsUser, Lint, Scope, user
from catgrammar import codes
from catgrammar.diagnostics import Diagnostics


def run(inst: ir.Instance, diags: Diagnostics, is_user: IsUser) -> None:
    written: set[str] = set()
    for m in inst.morphisms.values():
        written |= m.writes
    for lit in inst.problem.goal:
        reads = ir.resources_in(lit.expr)
        if reads and not (reads & written) and user(lit.span, is_user):
            names = ", ".join(f"'{r}'" for r in sorted(reads))
            diags.report(
                codes.UNWRITABLE_GOAL,
                f"this goal reads only {names}, which no morphism writes: the initial state alone decides it",
                lit.span,
            )


LINT = Lint(codes.UNWRITABLE_GOAL, Scope.INSTANCE, run)
