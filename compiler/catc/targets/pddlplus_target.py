"""The ``pddlplus`` target: the PDDL+ export for SMTPlan+ (:mod:`catc.targets.pddlplus`) —
``model.export("pddlplus")`` and the language server's ``catc.export.pddlplus``.  On the
command line it is ``catc export pddl --flavor smtplan`` (one command, two flavours), so it
names no command of its own."""

from __future__ import annotations

from collections.abc import Mapping
from fractions import Fraction
from typing import Any

from catc import ir
from catc.targets import pddl_target
from catc.targets.base import Target
from catc.targets.pddl_base import Flavor


def export(
    inst: ir.Instance,
    *,
    grid: Mapping[str, Fraction | int | str] | None = None,
    horizon: int | None = None,
    timeout: float | None = None,
) -> Any:
    return pddl_target.export(inst, grid=grid, horizon=horizon, flavor=Flavor.SMTPLAN)


TARGET = Target(
    "pddlplus",
    command=(),
    summary="Write PROBLEM (or DOMAIN PROBLEM) as PDDL+ planning files for SMTPlan+.",
    description="A real θ without a --grid step is exact (a dial: a fluent raised by a process; docs/export.md).",
    options=tuple(o for o in pddl_target.OPTIONS if o.name not in ("flavor", "strict_check", "planner")),
    run=export,
    to_json=lambda inst, ex: {**pddl_target.to_json(inst, ex), "schema": "catc.export-pddlplus/1"},
    render=pddl_target.render,
    write=pddl_target.write,
    prepare=pddl_target.prepare,
)
