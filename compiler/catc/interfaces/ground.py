"""``catc ground``: from a composition to the artifacts a robot runs, and what changes between two.

    catc ground [DOMAIN] PROBLEM -o DIR [--plan PLAN.json]
    catc ground [DOMAIN] PROBLEM --diff OLD.json NEW.json

Without ``--plan`` the problem is solved first: optimised (as ``catc optimize``) when it has a
metric or soft constraints, else as ``catc solve``.  The composition is
replayed by the independent validator, its grounding annotations resolved
(:mod:`catc.targets.grounding`), and instructions.md, compose.yaml, params.yaml, bt.xml and
manifest.json written to DIR.  A morphism of the composition without an annotation is a
warning (W0106; an error with ``--strict``): nothing is written for it, and it is named.
"""

from __future__ import annotations

import hashlib
import json
import math
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import click

from catc import ir
from catc.interfaces import command
from catc.interfaces.cli import limit_options, limited
from catc.present.console import counted, escape
from catc.queries.base import ExitCode
from catc.semantics.plan import Plan
from catgrammar import codes, limits
from catgrammar.diagnostics import Diagnostics, Note, format_text


def model_sha256(inst: ir.Instance) -> str:
    """A hash of the model's source files (domain, imports, problem), independent of where
    they lie: the sha256 of their sorted sha256s."""
    files = {inst.domain.span.file if inst.domain.span else None, inst.problem.span.file if inst.problem.span else None}
    files |= {m.span.file for m in inst.morphisms.values() if m.span is not None}
    files |= {r.span.file for r in inst.resources.values() if r.span is not None}
    digests = []
    for name in files:
        if name is None:
            continue
        try:
            digests.append(hashlib.sha256(Path(name).read_bytes()).hexdigest())
        except OSError:
            continue
    return hashlib.sha256("\n".join(sorted(digests)).encode()).hexdigest()


def replayed(inst: ir.Instance, plan: Plan, where: str, *, diff_hint: bool = False) -> tuple[Mapping[str, object], ...]:
    """The validator's states for ``plan``, or exit 1 listing every violation."""
    from catc.semantics.validate import validate

    report = validate(inst, plan, horizon=max(len(plan), 1))
    if not report.ok:
        command.echo(f"invalid: {where} is not a composition of this model:", err=True)
        for v in report.violations:
            command.echo(f"  {f'step {v.step}: ' if v.step is not None else ''}{v.kind}: {v.message}", err=True)
        if diff_hint:
            command.echo(
                "  (to compare with a composition of an earlier world, diff the two groundings instead: "
                "catc ground --diff OLD_DIR NEW_DIR, e.g. two of catrt's generation folders)",
                err=True,
            )
        sys.exit(ExitCode.FAIL)
    return tuple(report.states)


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
    from catc.targets.grounding.resolve import unexecuted

    if not unexecuted(grounded):
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


def ground_artifacts(
    inst: ir.Instance, plan: Plan, states: Sequence[Mapping[str, object]], as_json: bool
) -> tuple[Any, dict, dict]:
    """(the resolved grounding, the artifacts' bytes by name, the manifest), or exit 2 with a
    located error when the composition cannot be grounded."""
    from catc.targets.grounding.artifacts import artifacts, manifest
    from catc.targets.grounding.resolve import GroundingError, ground

    try:
        grounded = ground(inst, plan, states)
        files = artifacts(grounded)
    except GroundingError as exc:
        diags = Diagnostics()
        diags.report(
            codes.BAD_GROUNDING, str(exc), exc.span, *([Note("the other one", exc.first)] if exc.first else [])
        )
        command.input_errors(_sourced(diags), as_json)
    except ValueError as exc:  # a value no artifact can carry (a real beyond a double)
        command.argument_error(str(exc), codes.BAD_GROUNDING, as_json)
    return grounded, files, manifest(grounded, files, model_sha256(inst), inst)


def _plan_to_ground(inst: ir.Instance, plan_file: str | None, horizon: int | None, timeout: float | None) -> Plan:
    if plan_file is not None:
        try:
            given: Plan = command.read_plan_file(inst, plan_file)
        except command.PlanFileError as exc:
            command.argument_error(str(exc), exc.code, False, location=exc.location)
        return given
    from catc.queries import registry

    query = registry.get(registry.deploy_query(inst))
    result = query.run(inst, horizon=horizon, timeout=timeout)
    if result.exit_code is not ExitCode.OK or getattr(result, "plan", None) is None:
        query.render(command.console(), inst, result, {})
        sys.exit(result.exit_code)
    plan: Plan = result.plan  # type: ignore[attr-defined]
    return plan


def ground_command_body(
    paths: tuple[str, ...],
    out: str | None,
    plan_file: str | None,
    diff: tuple[str, str] | None,
    strict: bool,
    as_json: bool,
    horizon: int | None,
    view: str | None,
    search_paths: tuple[str, ...],
    problem_name: str | None,
    timeout: float | None,
) -> None:
    if diff is not None and _diff_groundings(diff, as_json):
        return
    if not paths:
        raise click.UsageError("give PROBLEM or DOMAIN PROBLEM (only --diff of two groundings needs no model)")
    inst = command.instance(paths, view, search_paths, problem_name, as_json)
    if diff is not None:
        _diff(inst, diff, strict, as_json)
        return
    if out is None:
        raise click.UsageError("give -o DIR (where the artifacts go), or --diff OLD NEW")
    plan = _plan_to_ground(inst, plan_file, horizon, timeout)
    states = replayed(inst, plan, plan_file or "the solver's composition")
    grounded, files, doc = ground_artifacts(inst, plan, states, as_json)
    warn_missing(inst, grounded.missing, strict)
    warn_unexecuted(inst, grounded, strict)
    from catc.targets.grounding.artifacts import write

    try:
        written = write(Path(out), files, doc)
    except OSError as exc:
        command.argument_error(f"cannot write to {out}: {exc.strerror or exc}", codes.CANNOT_WRITE, as_json)
    if as_json:
        command.echo(json.dumps({**doc, "directory": str(out)}, indent=2))
        return
    console = command.console()
    console.print(
        f"[bold green]GROUNDED[/]  {counted(len(plan), 'step')} of problem {inst.problem.name}: "
        f"{counted(len(grounded.hardware), 'hardware step')}, {counted(len(grounded.services), 'service')}, "
        f"{counted(sum(len(s) for s in grounded.behaviours), 'behaviour node')}"
    )
    for path in written:
        digest = doc["artifacts"].get(path.name, {}).get("sha256", "")
        console.print(f"  {escape(str(path))}" + (f"  sha256 {digest[:12]}…" if digest else ""))


def _diff_groundings(files: tuple[str, str], as_json: bool) -> bool:
    """``--diff`` of two groundings (folders or manifest.json files, e.g. two generations of
    the runtime): answered from their files, with no model — the old composition need not
    hold in today's world.  False when the two are not groundings (plan files)."""
    from catc.targets.grounding.diff import NotAGrounding, diff_artifacts, is_grounding, read_grounding

    kinds = [is_grounding(f) for f in files]
    if not any(kinds):
        return False
    if not all(kinds):
        command.argument_error(
            "--diff takes two groundings (folders or manifest.json files) or two plan files, not one of each",
            codes.BAD_ARGUMENT,
            as_json,
        )
    try:
        old, new = (read_grounding(f) for f in files)
    except NotAGrounding as exc:
        command.argument_error(str(exc), codes.BAD_ARGUMENT, as_json)
    _show_diff(diff_artifacts(old, new), as_json)
    return True


def _diff(inst: ir.Instance, files: tuple[str, str], strict: bool, as_json: bool) -> None:
    from catc.targets.grounding.diff import ground_diff

    grounded = []
    for name in files:
        try:
            plan = command.read_plan_file(inst, name)
        except command.PlanFileError as exc:
            command.argument_error(str(exc), exc.code, as_json, location=exc.location)
        g, _, _ = ground_artifacts(inst, plan, replayed(inst, plan, name, diff_hint=True), as_json)
        grounded.append(g)
    warn_missing(inst, [*grounded[0].missing, *grounded[1].missing], strict)  # each morphism named once
    _show_diff(ground_diff(grounded[0], grounded[1]), as_json)


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


@click.command("ground")
@click.argument("paths", nargs=-1, type=click.Path())
@click.option("-o", "--output", "out", type=click.Path(file_okay=False), help="Folder for the artifacts (created).")
@click.option("--plan", "plan_file", type=click.Path(dir_okay=False), help="Ground this catc.plan/1 composition.")
@click.option("--diff", nargs=2, type=click.Path(), metavar="OLD NEW",
              help="What changes on the robot from OLD to NEW: two groundings (folders or manifest.json; no "
                   "model needed) or two catc.plan/1 files of this model.")  # fmt: skip
@click.option("--strict", is_flag=True, help="A morphism without grounding is an error (exit 2), not a warning.")
@click.option(
    "--json", "as_json", is_flag=True, help="Print the manifest (catc.ground/1) or the diff (catc.ground-diff/1)."
)
@click.option("--horizon", "-k", type=click.IntRange(min=0), help="Most steps when solving (no --plan).")
@click.option("--view", help="Ground in this view (overrides the problem's (:view ...)).")
@click.option(
    "--path", "search_paths", multiple=True, type=click.Path(file_okay=False), help="Extra folder for domains."
)
@click.option("--problem", "problem_name", help="The problem to use when the file defines several.")
@click.option(
    "--timeout",
    type=click.FloatRange(min=0, min_open=True),
    help="Give up after this many seconds (the whole command).",
)
@limit_options
def ground_command(
    paths: tuple[str, ...],
    out: str | None,
    plan_file: str | None,
    diff: tuple[str, str] | None,
    strict: bool,
    as_json: bool,
    horizon: int | None,
    view: str | None,
    search_paths: tuple[str, ...],
    problem_name: str | None,
    timeout: float | None,
    limit_specs: tuple[str, ...],
    memory: int | None,
) -> None:
    """Write the artifacts a robot runs for a composition (solved, or --plan), or --diff two.

    PATHS is PROBLEM, or DOMAIN PROBLEM.  Writes instructions.md, compose.yaml, params.yaml,
    bt.xml and manifest.json to -o DIR.  Exit 0 written (or diffed), 1 no composition or an
    invalid plan, 2 input error, 3 the solver gave up.  Needs the 'grounding' extra.
    """
    if len(paths) not in (1, 2) and not (diff is not None and not paths):
        raise click.UsageError("give PROBLEM or DOMAIN PROBLEM")
    try:
        import yaml  # noqa: F401
    except ImportError:
        command.argument_error(
            "catc ground needs the 'grounding' extra: pip install 'catc-lang[grounding]'", codes.MISSING_EXTRA, as_json
        )
    if timeout is not None and not math.isfinite(timeout):
        command.argument_error(
            f"--timeout must be a finite number of seconds, got {timeout}", codes.BAD_ARGUMENT, as_json
        )
    with limited(limit_specs, memory), limits.deadline(timeout):
        ground_command_body(
            paths, out, plan_file, diff, strict, as_json, horizon, view, search_paths, problem_name, timeout
        )
