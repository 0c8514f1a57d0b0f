"""``catc export pddl``: PDDL 2.1 numeric domain and problem, with an export report.

Exit codes follow docs/cli.md: 0 written; 1 ``--run`` found no plan; 2 usage errors,
unreadable input, or a model the export refuses (e.g. a real θ without a grid step), and a
missing ``baselines`` extra or Java; 3 ENHSP gave up (``--run``).
"""

from __future__ import annotations

import json
import sys
from fractions import Fraction
from pathlib import Path

import click


EXIT_OK, EXIT_FAIL, EXIT_INPUT, EXIT_UNKNOWN = 0, 1, 2, 3


def _grid(specs: tuple[str, ...]) -> dict[str, Fraction]:
    out: dict[str, Fraction] = {}
    for spec in specs:
        name, sep, step = spec.partition("=")
        try:
            if not sep or not name:
                raise ValueError
            value = Fraction(step)
        except (ValueError, ZeroDivisionError):
            raise click.BadParameter(f"expected PARAM=STEP (e.g. camera-driver.ram-req=0.25), got {spec!r}", param_hint="--grid") from None
        if value <= 0:
            raise click.BadParameter(f"grid step must be positive, got {spec!r}", param_hint="--grid")
        out[name] = value
    return out


def check_with_pddl_parser(domain_file: Path, problem_file: Path) -> None:
    """Parse the written files with the PyPI ``pddl`` package (a parser we did not write)."""
    try:
        from pddl import parse_domain, parse_problem
    except ImportError:
        raise click.ClickException(
            "the PyPI 'pddl' parser is missing: pip install --no-deps 'pddl==0.5.1' "
            "(it pins an older lark but works with catc's), or pass --no-check"
        ) from None
    parse_domain(str(domain_file))
    parse_problem(str(problem_file))


@click.group(name="export")
def export_command() -> None:
    """Export a model to other planners' formats (DESIGN §6)."""


@export_command.command(name="pddl")
@click.argument("paths", nargs=-1, required=True, type=click.Path())
@click.option("-o", "--output", "out_dir", required=True, type=click.Path(file_okay=False),
              help="Folder for domain.pddl, problem.pddl, report.md and actions.json.")
@click.option("--grid", "grid_specs", multiple=True, metavar="PARAM=STEP",
              help="Grid step for a real θ (MORPHISM.PARAM or PARAM); repeatable.")
@click.option("--flavor", type=click.Choice(["enhsp", "smtplan"]), default="enhsp", show_default=True)
@click.option("--horizon", "-k", type=click.IntRange(min=0), help="Bound the number of (sequential) actions with a counter.")
@click.option("--view", help="Export this view (overrides the problem's (:view ...)).")
@click.option("--path", "search_paths", multiple=True, type=click.Path(file_okay=False), help="Extra folder to search for domains.")
@click.option("--problem", "problem_name", help="The problem to use when the file defines several.")
@click.option("--no-check", is_flag=True, help="Do not parse the written files with the PyPI 'pddl' package.")
@click.option("--run", "run_planner", is_flag=True, help="Run ENHSP on the files and validate its plan with catc's validator.")
@click.option("--planner", default="sat-hadd", show_default=True, help="ENHSP -planner configuration (e.g. opt-blind).")
@click.option("--timeout", type=click.FloatRange(min=0, min_open=True), default=60.0, show_default=True, help="Seconds for ENHSP (--run).")
def pddl_command(paths, out_dir, grid_specs, flavor, horizon, view, search_paths, problem_name, no_check,
                 run_planner, planner, timeout) -> None:
    """Write PROBLEM (or DOMAIN PROBLEM) as PDDL 2.1 numeric planning files.

    Real parameters θ are discretised on --grid; whatever PDDL cannot express (holes, soft
    constraints, reserve values, parallel steps, ...) is listed in report.md.
    """
    from catc.cli import _instance
    from catc.export.pddl import ExportError, export_pddl

    grid = _grid(grid_specs)
    inst = _instance(paths, view, search_paths, problem_name, False)
    try:
        ex = export_pddl(inst, grid=grid, horizon=horizon, flavor=flavor)
    except ExportError as exc:
        click.echo(f"error: {exc}", err=True)
        sys.exit(EXIT_INPUT)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    dom, prob = out / "domain.pddl", out / "problem.pddl"
    dom.write_text(ex.domain)
    prob.write_text(ex.problem)
    report = ex.report.markdown(f"problem {inst.problem.name} of domain {inst.domain.name}")
    (out / "report.md").write_text(report)
    from catc.plan import value_to_json

    (out / "actions.json").write_text(json.dumps(
        {n: {"morphism": a.morphism, "params": {k: value_to_json(v) for k, v in a.params.items()}} for n, a in ex.actions.items()},
        indent=1) + "\n")
    click.echo(f"wrote {dom}, {prob} ({len(ex.actions)} ground actions), {out / 'report.md'}")
    click.echo(report.rstrip())
    if not no_check:
        try:
            check_with_pddl_parser(dom, prob)
        except click.ClickException as exc:
            click.echo(f"error: {exc.message}", err=True)
            sys.exit(EXIT_INPUT)
        except Exception as exc:  # the parser's own errors
            click.echo(f"error: the PyPI 'pddl' parser rejects the export: {exc}", err=True)
            sys.exit(EXIT_INPUT)
        click.echo("parsed by the PyPI 'pddl' package: ok")
    if run_planner:
        from catc.export.enhsp import BaselineMissing, run_enhsp
        from catc.validate import validate

        try:
            res = run_enhsp(dom, prob, planner=planner, timeout=timeout)
        except BaselineMissing as exc:
            click.echo(f"error: {exc}", err=True)
            sys.exit(EXIT_INPUT)
        click.echo(f"ENHSP ({planner}): {res.status.upper()} in {res.wall:.2f} s"
                   + (f", {len(res.actions)} actions, metric {res.metric}" if res.status == "sat" else ""))
        if res.status == "sat":
            plan = ex.plan_from_actions(res.actions)
            for i, name in enumerate(res.actions, 1):
                click.echo(f"  {i:3d}  {name}")
            rep = validate(inst, plan, horizon=len(plan), sequential=True)
            if not rep.ok:
                click.echo("catc's validator REJECTS the plan: " + "; ".join(str(v) for v in rep.violations[:5]), err=True)
                sys.exit(EXIT_FAIL)
            click.echo("catc's validator accepts the plan (sequential semantics)")
        elif res.status == "unsat":
            sys.exit(EXIT_FAIL)
        else:
            click.echo(res.output[-2000:], err=True)
            sys.exit(EXIT_UNKNOWN)
