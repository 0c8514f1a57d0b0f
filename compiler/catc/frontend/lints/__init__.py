"""Warnings a modeller wants (errors under ``catc check --strict``): one module per lint,
found by :mod:`catc.frontend.lints.registry`.

Domain lints look at one checked domain; instance lints at a checked instance (the problem's
initial state included).  They run in the registry's order, so reports keep their order.
"""

from __future__ import annotations

from collections.abc import Sequence

from catc import ir
from catc.frontend.lints import registry
from catc.frontend.lints.base import DomainRun, InstanceRun, IsUser, Scope
from catgrammar.diagnostics import Diagnostics


def lint_domain(domain: ir.Domain, diags: Diagnostics, is_user: IsUser, problems: Sequence[ir.Problem] = ()) -> None:
    """``problems`` are this domain's problems checked in the same run: a sort used only
    for their objects is used."""
    for name in registry.names():
        lint = registry.get(name)
        if lint.scope is Scope.DOMAIN:
            run: DomainRun = lint.run  # type: ignore[assignment]
            run(domain, problems, diags, is_user)


def lint_instance(inst: ir.Instance, diags: Diagnostics, is_user: IsUser) -> None:
    for name in registry.names():
        lint = registry.get(name)
        if lint.scope is Scope.INSTANCE:
            run: InstanceRun = lint.run  # type: ignore[assignment]
            run(inst, diags, is_user)
