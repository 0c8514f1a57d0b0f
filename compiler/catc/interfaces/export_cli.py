"""``catc export pddl``: PDDL 2.1 numeric (``--flavor enhsp``) or PDDL+ (``--flavor smtplan``)
domain and problem, with an export report.

Exit codes follow docs/cli.md: 0 written; 1 ``--run`` found no plan; 2 usage errors,
unreadable input, or a model the export refuses (e.g. a real θ without a grid step in the
enhsp flavour), and a missing ``baselines`` extra, Java or SMTPlan+ binary; 3 the planner
gave up (``--run``).
"""

from __future__ import annotations

import json
import math
import sys
from fractions import Fraction
from pathlib import Path
from typing import Any

import click

from catc.interfaces.cli import limit_options, limited
from catc.interfaces.command import EXIT_FAIL, EXIT_UNKNOWN, argument_error
from catgrammar import codes
from catgrammar.terminal import printable


class MissingParser(RuntimeError):
    """A parser the export is checked with is not installed (the 'baselines' extra)."""


def _grid(specs: tuple[str, ...]) -> dict[str, Fraction]:
    out: dict[str, Fraction] = {}
    for spec in specs:
        name, sep, step = spec.partition("=")
        try:
            if not sep or not name:
                raise ValueError
            value = Fraction(step)
        except (ValueError, ZeroDivisionError):
            raise click.BadParameter(
                f"expected PARAM=STEP (e.g. camera-driver.ram-req=0.25), got {spec!r}", param_hint="--grid"
            ) from None
        if value <= 0:
            raise click.BadParameter(f"grid step must be positive, got {spec!r}", param_hint="--grid")
        out[name] = value
    return out


def check_pddl(domain_file: Path, problem_file: Path, strict: bool = False) -> list[str]:
    """Parse PDDL 2.1 files (the enhsp flavour) with parsers catc did not write, from the
    ``baselines`` extra: PyPI ``pddl-plus-parser`` (numeric PDDL; lax about unknown keywords;
    ~1 s for search-and-rescue's 545 ground actions) and, when ``strict``, unified-planning's
    ``PDDLReader`` too (a misspelt keyword is an error; ~10× slower on large groundings).
    Returns what was checked.

    (The PyPI ``pddl`` package, used before, pins lark<1.2 in every release while catc
    needs lark>=1.2: it cannot be installed beside catc without a conflict.)"""
    done = []
    try:
        from pddl_plus_parser.lisp_parsers import DomainParser, ProblemParser
    except ImportError:
        raise MissingParser(
            "pddl-plus-parser is missing (it parses the export): pip install 'catc-lang[baselines]', or pass --no-check"
        ) from None
    dom = DomainParser(domain_file).parse_domain()
    ProblemParser(problem_file, dom).parse_problem()
    done.append(f"pddl-plus-parser ({len(dom.actions)} actions)")
    if strict:
        try:
            from unified_planning.io import PDDLReader
        except ImportError:
            raise MissingParser(
                "unified-planning is missing (--strict-check parses the export with it): "
                "pip install 'catc-lang[baselines]'"
            ) from None
        problem = PDDLReader().parse_problem(str(domain_file), str(problem_file))
        done.append(f"unified-planning's PDDLReader ({len(problem.actions)} actions)")
    return done


def check_pddlplus(domain_file: Path, problem_file: Path) -> list[str]:
    """Parse PDDL+ files with unified-planning's reader (which supports processes and events)
    and, when installed, PyPI ``pddl-plus-parser``; returns what was checked.

    (Processes and events are PDDL+: the enhsp flavour's :func:`check_pddl` reads PDDL 2.1.)"""
    try:
        from unified_planning.io import PDDLReader
    except ImportError:
        raise MissingParser(
            "unified-planning is missing (it parses the PDDL+ export): "
            "pip install 'catc-lang[baselines]', or pass --no-check"
        ) from None
    problem = PDDLReader().parse_problem(str(domain_file), str(problem_file))
    done = [f"unified-planning's PDDLReader ({len(problem.actions)} actions, {len(problem.processes)} processes)"]
    try:
        from pddl_plus_parser.lisp_parsers import DomainParser, ProblemParser
    except ImportError:
        done.append("pddl-plus-parser not installed: skipped (pip install 'catc-lang[baselines]')")
        return done
    dom = DomainParser(domain_file).parse_domain()
    ProblemParser(problem_file, dom).parse_problem()
    done.append(f"pddl-plus-parser ({len(dom.actions)} actions; it skips :process blocks)")
    return done


@click.group(name="export")
def export_command() -> None:
    """Export a model to other planners' formats (docs/export.md)."""


@export_command.command(name="pddl")
@click.argument("paths", nargs=-1, required=True, type=click.Path())
@click.option(
    "-o",
    "--output",
    "out_dir",
    required=True,
    type=click.Path(file_okay=False),
    help="Folder for domain.pddl, problem.pddl, report.md and actions.json.",
)
@click.option(
    "--grid",
    "grid_specs",
    multiple=True,
    metavar="PARAM=STEP",
    help="Grid step for a real θ (MORPHISM.PARAM or PARAM); repeatable. Required for every real θ "
    "in the enhsp flavour; optional in the smtplan flavour (a θ without a step becomes a PDDL+ dial).",
)
@click.option(
    "--flavor",
    type=click.Choice(["enhsp", "smtplan"]),
    default="enhsp",
    show_default=True,
    help="enhsp: PDDL 2.1 numeric planning (ENHSP); smtplan: PDDL+ for SMTPlan+ (docs/export.md).",
)
@click.option(
    "--horizon", "-k", type=click.IntRange(min=0), help="Bound the number of (sequential) actions with a counter."
)
@click.option("--view", help="Export this view (overrides the problem's (:view ...)).")
@click.option(
    "--path",
    "search_paths",
    multiple=True,
    type=click.Path(file_okay=False),
    help="Extra folder to search for domains.",
)
@click.option("--problem", "problem_name", help="The problem to use when the file defines several.")
@click.option(
    "--no-check",
    is_flag=True,
    help="Do not parse the written files (with pddl-plus-parser, and unified-planning's reader for PDDL+: the 'baselines' extra).",
)
@click.option(
    "--strict-check",
    is_flag=True,
    help="Also parse a PDDL 2.1 export with unified-planning's reader, strict about keywords (slow on large groundings).",
)
@click.option(
    "--run",
    "run_planner",
    is_flag=True,
    help="Run ENHSP (enhsp) or an SMTPlan binary on PATH (smtplan) and validate its plan with catc's validator.",
)
@click.option("--planner", default="sat-hadd", show_default=True, help="ENHSP -planner configuration (e.g. opt-blind).")
@click.option(
    "--timeout",
    type=click.FloatRange(min=0, min_open=True),
    default=60.0,
    show_default=True,
    help="Seconds for the whole command: the export, the parsers' check and the planner (--run).",
)
@limit_options
def pddl_command(
    paths,
    out_dir,
    grid_specs,
    flavor,
    horizon,
    view,
    search_paths,
    problem_name,
    no_check,
    strict_check,
    run_planner,
    planner,
    timeout,
    limit_specs,
    memory,
) -> None:
    """Write PROBLEM (or DOMAIN PROBLEM) as PDDL planning files.

    --flavor enhsp: PDDL 2.1 numeric planning, real parameters θ discretised on --grid.
    --flavor smtplan: PDDL+ for SMTPlan+, a real θ without a --grid step is exact (a dial:
    a fluent raised by a process; docs/export.md).  Whatever PDDL cannot express (holes,
    soft constraints, reserve values, parallel steps, ...) is listed in report.md.
    """
    from catc.interfaces.command import instance
    from catc.targets.pddl import ExportError, export_pddl
    from catgrammar import limits

    grid = _grid(grid_specs)
    if len(paths) not in (1, 2):
        raise click.UsageError("give PROBLEM or DOMAIN PROBLEM")
    if not math.isfinite(timeout):
        argument_error(f"--timeout must be a finite number of seconds, got {timeout}", codes.BAD_ARGUMENT, False)
    with limited(limit_specs, memory), limits.deadline(timeout):
        inst = instance(paths, view, search_paths, problem_name, False)
        try:
            ex = export_pddl(inst, grid=grid, horizon=horizon, flavor=flavor)
        except ExportError as exc:
            argument_error(str(exc), codes.EXPORT_UNSUPPORTED, False)
        dom, prob = _write(Path(out_dir), inst, ex)
        if not no_check:
            _check(flavor, dom, prob, strict_check)
        left = max(0.001, limits.remaining() or timeout)
        if run_planner and flavor == "smtplan":
            _run_smtplan(inst, ex, dom, prob, left)
        elif run_planner:
            _run_enhsp(inst, ex, dom, prob, planner, left)


def _write(out: Path, inst: Any, ex: Any) -> tuple[Path, Path]:
    """domain.pddl, problem.pddl, report.md, actions.json (and dials.json for PDDL+)."""
    from catc.semantics.plan import value_to_json

    out.mkdir(parents=True, exist_ok=True)
    dom, prob = out / "domain.pddl", out / "problem.pddl"
    dom.write_text(ex.domain)
    prob.write_text(ex.problem)
    report = ex.report.markdown(f"problem {inst.problem.name} of domain {inst.domain.name}")
    (out / "report.md").write_text(report)
    actions = {
        n: {"morphism": a.morphism, "params": {k: value_to_json(v) for k, v in a.params.items()}}
        for n, a in ex.actions.items()
    }
    (out / "actions.json").write_text(json.dumps(actions, indent=1) + "\n")
    if ex.dials:  # smtplan flavour: how to read each real θ off a timed plan
        dials = {
            k: {
                "morphism": d.morphism,
                "param": d.param,
                "lower": value_to_json(d.lower),
                "upper": None if d.upper is None else value_to_json(d.upper),
                "fluent": d.fluent,
                "start": d.start,
                "stop": d.stop,
                "process": d.process,
                "lock": d.lock,
                "reset": d.reset,
            }
            for k, d in ex.dials.items()
        }
        (out / "dials.json").write_text(json.dumps(dials, indent=1) + "\n")
    click.echo(
        f"wrote {dom}, {prob} ({len(ex.actions)} ground actions{f', {len(ex.dials)} dials' if ex.dials else ''}), "
        f"{out / 'report.md'}, {out / 'actions.json'}" + (f", {out / 'dials.json'}" if ex.dials else "")
    )
    click.echo(printable(report.rstrip()))
    return dom, prob


def _check(flavor: str, dom: Path, prob: Path, strict: bool) -> None:
    """Parse the written files with parsers catc did not write."""
    try:
        checked = check_pddlplus(dom, prob) if flavor == "smtplan" else check_pddl(dom, prob, strict)
    except MissingParser as exc:
        argument_error(str(exc), codes.MISSING_EXTRA, False)
    except Exception as exc:  # the parsers' own errors
        which = "a PDDL+ parser" if flavor == "smtplan" else "a PDDL parser"
        argument_error(f"{which} rejects the export: {type(exc).__name__}: {exc}", codes.EXPORT_REJECTED, False)
    for line in checked:
        click.echo(f"parsed by {line}: ok" if "skipped" not in line else line)


def _run_enhsp(inst: Any, ex: Any, dom: Path, prob: Path, planner: str, timeout: float) -> None:
    """``--run``: ENHSP on the files, its plan replayed by catc's validator."""
    from catc.semantics.validate import validate
    from catc.targets.enhsp import BaselineMissing, run_enhsp

    try:
        res = run_enhsp(dom, prob, planner=planner, timeout=timeout)
    except BaselineMissing as exc:
        argument_error(str(exc), codes.BASELINE_UNAVAILABLE, False)
    click.echo(
        f"ENHSP ({planner}): {res.status.upper()} in {res.wall:.2f} s"
        + (f", {len(res.actions)} actions, metric {res.metric}" if res.status == "sat" else "")
    )
    if res.status == "sat":
        plan = ex.plan_from_actions(res.actions)
        for i, name in enumerate(res.actions, 1):
            click.echo(f"  {i:3d}  {name}")
        rep = validate(inst, plan, horizon=len(plan), sequential=True)
        if not rep.ok:
            click.echo(
                printable("catc's validator REJECTS the plan: " + "; ".join(map(str, rep.violations[:5]))), err=True
            )
            sys.exit(EXIT_FAIL)
        click.echo("catc's validator accepts the plan (sequential semantics)")
    elif res.status == "unsat":
        sys.exit(EXIT_FAIL)
    else:
        click.echo(printable(res.output[-2000:]), err=True)
        sys.exit(EXIT_UNKNOWN)


def _run_smtplan(inst, ex, dom: Path, prob: Path, timeout: float) -> None:
    """``--run --flavor smtplan``: only with an ``SMTPlan`` executable on PATH (no package
    of SMTPlan+ exists); its timed plan is read back with exact θ and validated."""
    from catc.semantics.validate import validate
    from catc.targets.pddlplus import SMTPLAN_HINT, PlanReadError, parse_timed_plan, run_smtplan, smtplan_binary

    if smtplan_binary() is None:
        argument_error(
            f"{SMTPLAN_HINT}; the files are written, --run needs the planner", codes.BASELINE_UNAVAILABLE, False
        )
    res = run_smtplan(dom, prob, timeout=timeout)
    click.echo(
        f"SMTPlan+: {res.status.upper()} in {res.wall:.2f} s"
        + (f", {len(res.actions)} timed actions" if res.status == "sat" else "")
    )
    if res.status == "nosolution":
        sys.exit(EXIT_FAIL)
    if res.status != "sat":
        click.echo(printable(res.output[-2000:]), err=True)
        sys.exit(EXIT_UNKNOWN)
    for a in res.actions:
        click.echo(f"  {a.time}: ({a.name})")
    try:
        plan = parse_timed_plan(ex, res.plan_text)
    except PlanReadError as exc:
        click.echo(printable(f"error: SMTPlan+'s plan cannot be read back: {exc}"), err=True)
        sys.exit(EXIT_FAIL)
    rep = validate(inst, plan, horizon=max(len(plan), 1), sequential=True)
    if not rep.ok:
        click.echo(printable("catc's validator REJECTS the plan: " + "; ".join(map(str, rep.violations[:5]))), err=True)
        sys.exit(EXIT_FAIL)
    click.echo("catc's validator accepts the plan (sequential semantics)")
