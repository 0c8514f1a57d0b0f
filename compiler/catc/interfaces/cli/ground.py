"""``catc ground``: from a composition to the artifacts a robot runs, and what changes between two.

    catc ground [DOMAIN] PROBLEM -o DIR [--plan PLAN.json]
    catc ground [DOMAIN] PROBLEM --diff OLD.json NEW.json

The command of the ``ground`` target (:mod:`catc.targets.ground`, its options and its pieces):
without ``--plan`` the problem is solved first (optimised when it has a metric or soft
constraints).  A morphism of the composition without an annotation is a warning (W0106; an
error with ``--strict``): nothing is written for it, and it is named.
"""

from __future__ import annotations

import json
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import click

from catc import ir
from catc.interfaces import command
from catc.interfaces.cli.options import limited
from catc.interfaces.cli.targets import loaded, prepared
from catc.present.console import counted, escape
from catc.queries.base import ExitCode
from catc.semantics.plan import Plan
from catc.targets import ground as target
from catc.targets.base import Target
from catgrammar import codes, limits
from catgrammar.diagnostics import Diagnostics, Note, format_text


def replayed(inst: ir.Instance, plan: Plan, where: str, *, diff_hint: bool = False) -> tuple[Mapping[str, object], ...]:
    """The validator's states for ``plan``, or exit 1 listing every violation."""
    try:
        return target.replayed(inst, plan, where)
    except target.InvalidComposition as exc:
        command.echo(f"invalid: {where} is not a composition of this model:", err=True)
        for v in exc.violations:
            command.echo(f"  {f'step {v.step}: ' if v.step is not None else ''}{v.kind}: {v.message}", err=True)
        if diff_hint:
            command.echo(
                "  (to compare with a composition of an earlier world, diff the two groundings instead: "
                "catc ground --diff OLD_DIR NEW_DIR, e.g. two of catrt's generation folders)",
                err=True,
            )
        sys.exit(ExitCode.FAIL)


def _sourced(diags: Diagnostics) -> Diagnostics:
    """Attach the text of every file the diagnostics point into (for their excerpts)."""
    from catgrammar.span import Source

    spans = [d.span for d in diags] + [n.span for d in diags for n in d.notes]
    for path in {s.file for s in spans if s is not None and s.file}:
        try:
            diags.add_source(Source(path, Path(path).read_text(encoding="utf-8")))
        except (OSError, UnicodeDecodeError):
            continue  # no excerpt, the location still stands
    return diags


def warn_missing(inst: ir.Instance, missing: Sequence[str], strict: bool) -> None:
    """W0106 for every morphism without grounding (located at its declaration); with
    ``strict``, errors and exit 2."""
    if not missing:
        return
    diags = Diagnostics()
    for name in dict.fromkeys(missing):
        diags.report(
            codes.UNGROUNDED_MORPHISM,
            f"morphism '{name}' has no (:ground ...) annotation: nothing is written for it",
            inst.morphisms[name].span,
        )
    if strict:
        diags.promote_warnings()
    command.echo(format_text(_sourced(diags)), err=True)
    if strict:
        sys.exit(ExitCode.INPUT)


def warn_unexecuted(inst: ir.Instance, grounded: Any, strict: bool) -> None:
    """W0108 when the composition has behaviours and no executor runs bt.xml (located at the
    first behaviour's annotation); with ``strict``, an error and exit 2."""
    if not target.unexecuted(grounded):
        return
    first = grounded.behaviours[0][0].morphism
    g = inst.morphisms[first].grounding
    diags = Diagnostics()
    diags.report(
        codes.UNEXECUTED_TREE,
        f"the composition runs behaviours ({', '.join(n.morphism for step in grounded.behaviours for n in step)}) "
        "but the domain names no executor: bt.xml is written and no service runs it; add "
        '(:deployment :executor "IMAGE") to the domain',
        g.span if g is not None else inst.morphisms[first].span,
    )
    if strict:
        diags.promote_warnings()
    command.echo(format_text(_sourced(diags)), err=True)
    if strict:
        sys.exit(ExitCode.INPUT)


def grounding(inst: ir.Instance, plan: Plan, states: tuple[Mapping[str, object], ...], as_json: bool) -> Any:
    """The :class:`catc.targets.ground.Grounding` of a replayed composition, or exit 2 with a
    located error when it cannot be grounded."""
    try:
        return target.grounding_of(inst, plan, states)
    except target.GroundingError as exc:
        diags = Diagnostics()
        diags.report(
            codes.BAD_GROUNDING, str(exc), exc.span, *([Note("the other one", exc.first)] if exc.first else [])
        )
        command.input_errors(_sourced(diags), as_json)
    except ValueError as exc:  # a value no artifact can carry (a real beyond a double)
        command.argument_error(str(exc), codes.BAD_GROUNDING, as_json)


def _plan_to_ground(inst: ir.Instance, plan_file: str | None, horizon: int | None, timeout: float | None) -> Plan:
    if plan_file is not None:
        try:
            given: Plan = command.read_plan_file(inst, plan_file)
        except command.PlanFileError as exc:
            command.argument_error(str(exc), exc.code, False, location=exc.location)
        return given
    try:
        return target.composition(inst, horizon, timeout)
    except target.NoComposition as exc:
        exc.query.render(command.console(), inst, exc.result, {})
        sys.exit(exc.result.exit_code)


def run_ground(ground: Target, paths: Sequence[str], values: dict[str, Any]) -> None:
    """``catc ground``: the options read as every target's, then ground (or diff)."""
    as_json = bool(values.get("as_json"))
    if values.get("diff") is not None and _diff_groundings(values["diff"], as_json):
        return
    if len(paths) not in (1, 2):
        raise click.UsageError("give PROBLEM or DOMAIN PROBLEM (only --diff of two groundings needs no model)")
    try:
        import yaml  # noqa: F401
    except ImportError:
        command.argument_error(
            "catc ground needs the 'grounding' extra: pip install 'catc-lang[grounding]'", codes.MISSING_EXTRA, as_json
        )
    prepared(ground, paths, values)
    with limited(values.get("limits") or (), values.get("memory")), limits.deadline(values.get("timeout")):
        inst = loaded(paths, values, as_json)
        strict = bool(values.get("strict"))
        if values.get("diff") is not None:
            _diff(inst, values["diff"], strict, as_json)
            return
        out = values.get("output")
        if out is None:
            raise click.UsageError("give -o DIR (where the artifacts go), or --diff OLD NEW")
        plan_file = values.get("plan_file")
        plan = _plan_to_ground(inst, plan_file, values.get("horizon"), values.get("timeout"))
        g = grounding(inst, plan, replayed(inst, plan, plan_file or "the solver's composition"), as_json)
        warn_missing(inst, g.grounded.missing, strict)
        warn_unexecuted(inst, g.grounded, strict)
        try:
            written = target.write_files(Path(out), g)
        except OSError as exc:
            command.argument_error(f"cannot write to {out}: {exc.strerror or exc}", codes.CANNOT_WRITE, as_json)
        if as_json:
            command.echo(json.dumps({**g.manifest, "directory": str(out)}, indent=2))
            return
        grounded = g.grounded
        console = command.console()
        console.print(
            f"[bold green]GROUNDED[/]  {counted(len(plan), 'step')} of problem {inst.problem.name}: "
            f"{counted(len(grounded.hardware), 'hardware step')}, {counted(len(grounded.services), 'service')}, "
            f"{counted(sum(len(s) for s in grounded.behaviours), 'behaviour node')}"
        )
        for path in written:
            digest = g.manifest["artifacts"].get(path.name, {}).get("sha256", "")
            console.print(f"  {escape(str(path))}" + (f"  sha256 {digest[:12]}…" if digest else ""))


def _diff_groundings(files: tuple[str, str], as_json: bool) -> bool:
    """``--diff`` of two groundings (folders or manifest.json files, e.g. two generations of
    the runtime): answered from their files, with no model — the old composition need not
    hold in today's world.  False when the two are not groundings (plan files)."""
    kinds = [target.is_grounding(f) for f in files]
    if not any(kinds):
        return False
    if not all(kinds):
        command.argument_error(
            "--diff takes two groundings (folders or manifest.json files) or two plan files, not one of each",
            codes.BAD_ARGUMENT,
            as_json,
        )
    try:
        old, new = (target.read_grounding(f) for f in files)
    except target.NotAGrounding as exc:
        command.argument_error(str(exc), codes.BAD_ARGUMENT, as_json)
    _show_diff(target.diff_artifacts(old, new), as_json)
    return True


def _diff(inst: ir.Instance, files: tuple[str, str], strict: bool, as_json: bool) -> None:
    grounded = []
    for name in files:
        try:
            plan = command.read_plan_file(inst, name)
        except command.PlanFileError as exc:
            command.argument_error(str(exc), exc.code, as_json, location=exc.location)
        grounded.append(grounding(inst, plan, replayed(inst, plan, name, diff_hint=True), as_json))
    warn_missing(
        inst, [*grounded[0].grounded.missing, *grounded[1].grounded.missing], strict
    )  # each morphism named once
    _show_diff(target.diff(grounded[0], grounded[1]), as_json)


def _show_diff(d: Any, as_json: bool) -> None:
    if as_json:
        doc = {
            "schema": "catc.ground-diff/1",
            **{k: list(getattr(d, k)) for k in ("added", "removed", "unmount", "mount", "stop", "start", "recreate")},
            "tree_changed": d.tree_changed,
            "commands": d.commands(),
        }
        command.echo(json.dumps(doc, indent=2))
        return
    _print_diff(d)


def _print_diff(d: Any) -> None:
    console = command.console()
    if d.empty:
        console.print("[bold green]NO CHANGE[/]  the two compositions ground to the same robot")
        return
    console.print(f"[bold yellow]CHANGES[/]  components added: {escape(', '.join(d.added)) or 'none'}; "
                  f"removed: {escape(', '.join(d.removed)) or 'none'}")  # fmt: skip
    rows = [
        ("unmount", d.unmount),
        ("mount", d.mount),
        ("stop", d.stop),
        ("start", d.start),
        ("recreate", d.recreate),
    ]
    for what, names in rows:
        if names:
            console.print(f"  {what:9} {escape(', '.join(names))}")
    console.print(f"  behaviour tree {'changed' if d.tree_changed else 'unchanged'}")
    for argv in d.commands():
        console.print("  $ " + escape(" ".join(argv)))
