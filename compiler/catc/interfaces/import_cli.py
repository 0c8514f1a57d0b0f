"""``catc import pddl DOMAIN.pddl PROBLEM.pddl -o DIR``: a PDDL planning problem → ``.cat`` files.

The PDDL is read by unified-planning's ``PDDLReader`` (a maintained parser; the ``up`` extra),
converted to catc's IR by :func:`catc.frontend.up_import.up_to_instance` (grounded by UP's own
compilers, UP's sequential semantics kept), written by :mod:`catc.targets.catsource`, laid out
by ``catc fmt``'s formatter and checked again by ``catc check``. Besides ``domain.cat`` and
``problem.cat`` the folder gets ``import-report.md`` (what mapped to what, what was grounded,
how the sequential semantics are kept, what was refused and why) and ``actions.json`` (each
morphism → the PDDL action it stands for).

Exit codes (docs/cli.md): 0 imported; 2 the PDDL cannot be read (``E1210``, at the line and
column the reader gives), uses something catc cannot express (``E1201``, located at the PDDL
construct where it can be found, else at the file; the report is written and lists every
refusal), needs the ``up`` extra (``E1202``), or the written files do not check (``E1211``);
3 the grounding ran past ``--timeout`` (``E1109``).
"""

from __future__ import annotations

import json
import re
import sys
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import click

from catc import ir
from catc.interfaces.command import EXIT_INPUT, EXIT_UNKNOWN
from catgrammar import codes
from catgrammar.terminal import printable

__all__ = ["ImportFailed", "ImportResult", "import_command", "import_pddl", "write_cat"]

#: PDDL text that shows a refused UP feature (the first match locates the error).
_WHERE: dict[str, str] = {
    "CONTINUOUS_TIME": r"\(:durative-action\b",
    "DISCRETE_TIME": r"\(:durative-action\b",
    "INT_TYPE_DURATIONS": r":duration\s",
    "REAL_TYPE_DURATIONS": r":duration\s",
    "DURATION_INEQUALITIES": r":duration\s",
    "PROCESSES": r"\(:process\b",
    "EVENTS": r"\(:event\b",
    "INCREASE_CONTINUOUS_EFFECTS": r"#t\b",
    "DECREASE_CONTINUOUS_EFFECTS": r"#t\b",
    "NON_LINEAR_CONTINUOUS_EFFECTS": r"#t\b",
    "TIMED_EFFECTS": r"\(at\s+[\d.]+",
    "TIMED_GOALS": r"\(at\s+[\d.]+",
    "TIMED_INITIAL_LITERALS": r"\(at\s+[\d.]+",
    "HIERARCHICAL": r":(task|method)\b",
    "TASK_ORDER_PARTIAL": r":ordering\b",
    "TASK_ORDER_TOTAL": r":ordered-subtasks\b",
    "FLUENTS_IN_ACTIONS_COST": r"\(increase\s+\(total-cost\)\s+\(",
    "MAKESPAN": r"total-time",
    "TRAJECTORY_CONSTRAINTS": r":constraints\b",
    "UNDEFINED_INITIAL_NUMERIC": r"\(:init\b",
    "UNDEFINED_INITIAL_SYMBOLIC": r"\(:init\b",
}


class ImportFailed(Exception):
    """The import stops: ``code``, ``message``, ``location`` (``file:line:col`` or ``file``)."""

    def __init__(
        self,
        code: str,
        message: str,
        location: str | None = None,
        report: Path | None = None,
        refused: list[tuple[str, str]] | None = None,
    ) -> None:
        super().__init__(message)
        self.code, self.message, self.location, self.report = code, message, location, report
        self.refused: list[tuple[str, str]] = refused or []  # (construct, why) when the model is refused


@dataclass
class ImportResult:
    """What :func:`import_pddl` wrote and found."""

    instance: ir.Instance
    domain_file: Path
    problem_file: Path
    report_file: Path
    actions: dict[str, str]  # morphism → the PDDL ground action, "(move r1 l1 l2)"
    optimal_metric: str | None  # "cost" | "length" | "final" | "gain" | None
    warnings: int = 0
    notes: list[str] = field(default_factory=list)


def write_cat(inst: ir.Instance, out: Path, *, header: str | None = None) -> tuple[Path, Path]:
    """``out/domain.cat`` and ``out/problem.cat`` in catc fmt's layout (what ``catc fmt
    --check`` leaves unchanged): the ``cat`` target's files, laid out as every interface lays
    them out (:mod:`catc.interfaces.layout`).  Raises :class:`catc.queries.base.InputError`
    when the model cannot be written as ``.cat`` (the writer's own reason is its cause)."""
    from catc.interfaces.layout import export
    from catc.targets import registry as targets

    files = export(targets.get("cat"), inst, {"header": header})
    out.mkdir(parents=True, exist_ok=True)
    dom, prob = out / "domain.cat", out / "problem.cat"
    dom.write_text(files.domain, encoding="utf-8")
    prob.write_text(files.problem, encoding="utf-8")
    return dom, prob


def _up_reader() -> Any:
    from catc.frontend.up_import import MISSING

    try:
        import unified_planning.shortcuts as shortcuts
        from unified_planning.io import PDDLReader
    except ImportError:
        raise ImportFailed(codes.IMPORT_NEEDS_EXTRA, MISSING) from None
    shortcuts.get_environment().credits_stream = None
    return PDDLReader()


def _read(domain: Path, problem: Path) -> Any:
    for p in (domain, problem):
        if not p.is_file():
            raise ImportFailed(codes.UNREADABLE_FILE, f"cannot read '{p}': no such file")
    reader = _up_reader()
    try:
        dom_text = domain.read_text(encoding="utf-8")
        problem.read_text(encoding="utf-8")  # readable and UTF-8, as the reader needs
    except (OSError, UnicodeDecodeError) as exc:
        raise ImportFailed(codes.UNREADABLE_FILE, f"cannot read the PDDL: {exc}") from None
    try:
        # which file a syntax error is in: parse the domain alone first
        where = domain
        reader.parse_problem_string(dom_text, None)
        where = problem
        return reader.parse_problem(str(domain), str(problem))
    except RecursionError:
        raise ImportFailed(codes.PDDL_UNREADABLE, "the PDDL nests too deeply to read", str(where)) from None
    except Exception as exc:  # pyparsing's and unified-planning's own errors
        line, col = getattr(exc, "lineno", None), getattr(exc, "column", None)
        loc = f"{where}:{line}:{col}" if line is not None and col is not None else str(where)
        msg = getattr(exc, "msg", None) or str(exc).split("\n")[0] or type(exc).__name__
        raise ImportFailed(
            codes.PDDL_UNREADABLE, f"unified-planning's PDDL reader rejects it: {type(exc).__name__}: {msg}", loc
        ) from None


def _locate(feature: str, files: Iterable[Path]) -> str | None:
    pattern = _WHERE.get(feature)
    for f in files:
        text = f.read_text(encoding="utf-8")
        if pattern is not None:
            m = re.search(pattern, text, re.IGNORECASE)
            if m is not None:
                line = text.count("\n", 0, m.start()) + 1
                col = m.start() - (text.rfind("\n", 0, m.start()) + 1) + 1
                return f"{f}:{line}:{col}"
    return None


def _position(loc: str, domain: Path) -> tuple[int, int, int]:
    """``file:line:col`` → a key that orders the domain's locations before the problem's."""
    file, line, col = loc.rsplit(":", 2)
    return (0 if file == str(domain) else 1, int(line), int(col))


def _count(inst: ir.Instance) -> dict[str, int]:
    res = inst.domain.resources.values()
    return {
        "bool": sum(1 for r in res if r.sort.kind is ir.SortKind.BOOL),
        "numeric": sum(1 for r in res if r.sort.is_numeric),
        "symbolic": sum(1 for r in res if r.sort.is_symbolic),
    }


_METRIC_WORDS = {
    "cost": "`(:metric minimize (total-cost))` → `(:metric minimize (total-cost))`, each action's fixed cost as the "
    "morphism's `:cost` (costs that read changing functions: summed in a resource, see the notes)",
    "length": "minimise the plan length → `(:metric minimize (total-cost))` with `:cost 1` on every morphism",
    "final": "an expression over the final state → `(:metric minimize|maximize TERM)` over the ground fluents",
    "gain": "oversubscription goals → `(:soft GOAL :weight GAIN)`: the weight of the goals missed is minimised",
}


def _report(
    domain: Path,
    problem: Path,
    up_problem: Any,
    up_report: Any,
    inst: ir.Instance | None,
    refused: list[tuple[str, str, str | None]],
    written: tuple[Path, Path] | None,
) -> str:
    import unified_planning

    lines = [f"# Import report: `{domain.name}` + `{problem.name}`", ""]
    lines.append(
        f"Read by unified-planning {unified_planning.__version__}'s `PDDLReader`; converted by "
        "`catc.frontend.up_import` (grounded by `catc.frontend.up_ground`: UP's `QuantifiersRemover`, parameters "
        "chosen by their static preconditions, instances made by UP's `GrounderHelper`); "
        "written by `catc.targets.catsource` in `catc fmt`'s layout and checked again by `catc check`."
    )
    lines.append("")
    if refused:
        lines += ["## Refused", "", "catc cannot express this problem; nothing was written but this report.", ""]
        lines += ["| construct | why | where |", "|---|---|---|"]
        lines += [f"| {what} | {why} | {where or '(the files)'} |" for what, why, where in refused]
        lines.append("")
    if up_problem is not None:
        kind = sorted(up_problem.kind.features)
        lines += ["## The PDDL", ""]
        lines.append(
            f"{len(list(up_problem.user_types))} types, {len(list(up_problem.all_objects))} objects, "
            f"{len(up_problem.fluents)} predicates and functions, {len(up_problem.actions)} actions, "
            f"{len(up_problem.quality_metrics)} metric(s)."
        )
        lines.append(f"UP problem kind: {', '.join(f'`{k}`' for k in kind)}.")
        lines.append("")
    if inst is not None and written is not None:
        n = _count(inst)
        d = inst.domain
        lines += ["## What mapped to what", "", "| PDDL | catc | count |", "|---|---|---|"]
        lines.append(
            f"| types | open symbolic sorts (kept only when an object-valued fluent needs them) | {len(d.sorts)} |"
        )
        lines.append(f"| objects and constants | constants (as above) | {len(d.constants)} |")
        lines.append(f"| ground predicates read or written | `bool` resources | {n['bool']} |")
        lines.append(f"| ground functions read or written | `int`/`real` resources | {n['numeric']} |")
        lines.append(f"| ground object-valued fluents | symbolic resources | {n['symbolic']} |")
        lines.append(f"| ground actions (UP's grounder) | morphisms without parameters | {len(d.morphisms)} |")
        lines.append(f"| goal conjuncts | `(:goal ...)` literals | {len(inst.problem.goal)} |")
        lines.append("")
        lines += ["## What was grounded", ""]
        lines.append(
            "catc's resources hold one value each, so every PDDL fluent with arguments is grounded: each ground "
            "fluent an action, the goal or the metric reads or writes becomes one resource (`at(r1, l2)` → "
            "`at_r1_l2`), each ground action one morphism (its `:doc` names the PDDL action). Ground actions whose "
            "static preconditions are false are never instantiated; static fluents (written by no action) are "
            "replaced by their initial values. Quantifiers are expanded over the objects before grounding. "
            "`actions.json` maps every morphism back to its PDDL action."
        )
        lines.append("")
        if up_report.optimal_metric is not None:
            lines += ["## The metric", "", _METRIC_WORDS.get(up_report.optimal_metric, up_report.optimal_metric), ""]
        lines += ["## Sequential semantics", ""]
        lines.append(
            "PDDL plans are sequences; catc's steps may hold several morphisms at once. Run the queries with "
            "`--sequential` (one morphism per step): then a composition of k steps is a PDDL plan of k actions, "
            "and the effects of each step follow UP's sequential semantics (effects read the state before the "
            "action; add-after-delete on predicates; two assignments of different values to one function, or an "
            "assignment and an increase, make the action inapplicable, as in UP's simulator). Without "
            "`--sequential`, a step may merge actions that do not interfere; reachability is the same but a step "
            "count is not a plan length. The problem has no `(:horizon ...)` unless `--horizon` was given: pass "
            "`-k` to the queries (the default is 10 steps)."
        )
        lines.append("")
        lines.append(
            f"    catc solve --sequential -k 50 {written[1]}\n"
            f"    catc export pddl {written[1]} -o OUT --run   # the round trip through ENHSP"
        )
        lines.append("")
        if up_report.notes:
            lines += ["## Notes", ""] + [f"- {x}" for x in up_report.notes] + [""]
    return "\n".join(lines).rstrip("\n") + "\n"


def import_pddl(
    domain: Path, problem: Path, out: Path, *, horizon: int | None = None, timeout: float | None = None
) -> ImportResult:
    """Import ``domain`` + ``problem`` into ``out`` (see the module docstring); raises
    :class:`ImportFailed` with the code, message and location of the first reason to stop
    (the report is written when the model was read). ``timeout`` (seconds) bounds the
    grounding: past it, ``E1109``."""
    from catc.frontend.session import load_checked
    from catc.frontend.up_import import UpImportError, UpImportStopped, UpMissing, up_to_instance
    from catc.queries.base import InputError
    from catgrammar.diagnostics import Diagnostics

    up_problem = _read(domain, problem)
    out.mkdir(parents=True, exist_ok=True)
    report_file = out / "import-report.md"
    try:
        inst, rep = up_to_instance(up_problem) if timeout is None else up_to_instance(up_problem, timeout=timeout)
    except UpMissing as exc:
        raise ImportFailed(codes.IMPORT_NEEDS_EXTRA, str(exc)) from None
    except UpImportStopped:
        raise ImportFailed(
            codes.TIME_LIMIT, f"the time ran out while grounding the problem (--timeout {timeout:g} s)", str(problem)
        ) from None
    except UpImportError as exc:
        refused = [(w, r, _locate(w, (domain, problem))) for w, r in exc.report.refused]
        report_file.write_text(_report(domain, problem, up_problem, exc.report, None, refused, None), encoding="utf-8")
        # the first in the files: the domain's before the problem's
        first = min((loc for _, _, loc in refused if loc), key=lambda loc: _position(loc, domain), default=None)
        reasons = "; ".join(f"{w}: {r}" for w, r, _ in refused)
        raise ImportFailed(
            codes.IMPORT_UNSUPPORTED,
            f"catc cannot express this problem: {reasons}",
            first or str(domain),
            report_file,
            list(exc.report.refused),
        ) from None
    if horizon is not None:
        inst = ir.Instance(inst.domain, _with_horizon(inst.problem, horizon))
    header = f"Imported by `catc import pddl` from {domain.name} and {problem.name}: see import-report.md.\nSolve with --sequential (PDDL plans are sequences)."
    try:
        written = write_cat(inst, out, header=header)
    except InputError as exc:  # the .cat writer's reason (the cause), as before the cat target
        raise ImportFailed(codes.IMPORT_UNSPELLABLE, str(exc.__cause__ or exc), str(domain)) from None
    actions = {m: _pddl_action(a) for m, a in rep.actions.items()}
    (out / "actions.json").write_text(json.dumps(actions, indent=1) + "\n", encoding="utf-8")
    report_file.write_text(_report(domain, problem, up_problem, rep, inst, [], written), encoding="utf-8")
    diags = Diagnostics()
    checked = load_checked(written[1], written[0], diags)
    if checked is None or diags.has_errors:
        err = next(iter(diags.errors), None)
        span = err.span if err is not None else None
        where = f"{span.file}:{span.line}:{span.column}" if span is not None else str(written[0])
        raise ImportFailed(
            codes.IMPORT_RECHECK_FAILED,
            "the written .cat files do not check (a bug in catc import: please report it): "
            + (err.message if err is not None else "no instance"),
            where,
        )
    return ImportResult(
        checked,
        written[0],
        written[1],
        report_file,
        actions,
        rep.optimal_metric,
        warnings=len(list(diags)) - len(list(diags.errors)),
        notes=list(rep.notes),
    )


def _with_horizon(p: ir.Problem, k: int) -> ir.Problem:
    from catgrammar.record import replace

    return replace(p, horizon=k)


def _pddl_action(ai: Any) -> str:
    """A UP action instance as a PDDL plan step: ``(move r1 l1 l2)``."""
    args = " ".join(str(a) for a in ai.actual_parameters)
    return f"({ai.action.name}{' ' + args if args else ''})"


@click.group(name="import")
def import_command() -> None:
    """Import planning problems from other tools as .cat files (docs/interop.md)."""


@import_command.command(name="pddl")
@click.argument("domain", type=click.Path(dir_okay=False))
@click.argument("problem", type=click.Path(dir_okay=False))
@click.option(
    "-o",
    "--output",
    "out_dir",
    required=True,
    type=click.Path(file_okay=False),
    help="Folder for domain.cat, problem.cat, import-report.md and actions.json.",
)
@click.option(
    "--horizon", "-k", type=click.IntRange(min=0), help="Write (:horizon K) into the problem (the most PDDL actions)."
)
@click.option(
    "--timeout",
    type=click.FloatRange(min=0, min_open=True),
    help="Give up grounding after this many seconds (exit 3, error[E1109]).",
)
def pddl_command(domain: str, problem: str, out_dir: str, horizon: int | None, timeout: float | None) -> None:
    """Import a PDDL 2.1 DOMAIN and PROBLEM (non-temporal, numeric fluents, action costs) as .cat.

    Read by unified-planning's PDDL reader (pip install 'catc-lang[up]'), grounded, written as
    domain.cat and problem.cat (catc fmt's layout) and checked again; import-report.md says what
    mapped to what and what was refused. Solve the result with --sequential. Exit 0 imported,
    2 refused or unreadable (a located error[CODE] and the report).
    """
    try:
        res = import_pddl(Path(domain), Path(problem), Path(out_dir), horizon=horizon, timeout=timeout)
    except ImportFailed as exc:
        click.echo(printable(f"{exc.location or 'catc'}: error[{exc.code}]: {exc.message}"), err=True)
        if exc.report is not None:
            click.echo(printable(f"the import report: {exc.report}"), err=True)
        sys.exit(EXIT_UNKNOWN if exc.code == codes.TIME_LIMIT else EXIT_INPUT)
    d = res.instance.domain
    click.echo(
        printable(
            f"wrote {res.domain_file} ({len(d.resources)} resources, {len(d.morphisms)} morphisms), "
            f"{res.problem_file}, {res.report_file}, {res.domain_file.parent / 'actions.json'}"
        )
    )
    k = "" if horizon is not None else "-k 50 "  # no (:horizon ...) written: the queries' default is 10 steps
    click.echo(
        f"checked: ok ({res.warnings} warnings); solve with --sequential: catc solve --sequential {k}{res.problem_file}"
    )
