"""The ``catc`` command line.

Exit codes (docs/cli.md): 0 success; 1 model errors (``check``) or infeasible (queries);
2 usage or unreadable input (and, for queries, any input error); 3 the solver gave up.
No command lets a Python traceback reach the user for bad input.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import click

from catc import __version__
from catc.interfaces import command
from catc.interfaces.command import EXIT_FAIL, EXIT_INPUT, EXIT_OK, EXIT_UNKNOWN
from catc.interfaces.command import console as _console
from catc.interfaces.command import input_error as _input_error
from catc.interfaces.command import progress as _progress
from catc.interfaces.command import write_diagram as _write_diagram

_UNREADABLE = {"E0001", "E0002", "E0003", "E0005"}


#: Commands defined in their own modules, imported only when used (start-up time):
#: name → "module:attribute" of a click command.
LAZY_COMMANDS: dict[str, str] = {
    "fmt": "catc.frontend.formatter:fmt_command",
    "lsp": "catc.interfaces.lsp:lsp_command",
    "export": "catc.interfaces.export_cli:export_command",
    "bench": "catc.bench.harness:bench_command",
}


class _Group(click.Group):
    """Usage errors exit 2 (click's default); unexpected exceptions become a one-line
    internal-error report with exit 70 instead of a traceback (set CATC_DEBUG=1 to see it).
    Commands in :data:`LAZY_COMMANDS` load on first use."""

    def list_commands(self, ctx):
        return sorted(set(super().list_commands(ctx)) | {n for n in LAZY_COMMANDS if self._lazy(n) is not None})

    def get_command(self, ctx, name):
        return super().get_command(ctx, name) or self._lazy(name)

    @staticmethod
    def _lazy(name: str):
        import importlib

        target = LAZY_COMMANDS.get(name)
        if target is None:
            return None
        module, _, attr = target.partition(":")
        try:
            return getattr(importlib.import_module(module), attr)
        except ImportError:  # the command's module is not there (yet); optional extras report themselves
            return None

    def invoke(self, ctx: click.Context):
        return command.guarded(
            super().invoke, ctx, passthrough=(click.exceptions.Exit, click.exceptions.Abort, click.ClickException)
        )


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="catc")
def main() -> None:
    """catc — compile .cat robot-recomposition models and answer lifecycle queries."""


def _collect(paths: tuple[str, ...], diags) -> list[str]:
    files: list[str] = []
    for p in paths:
        path = Path(p)
        if path.is_dir():
            found = sorted(str(f) for f in path.rglob("*.cat") if f.is_file())
            if not found:
                diags.report("E0005", f"no .cat files under '{p}'", None)
            files.extend(found)
        elif path.exists():
            files.append(str(path))
        else:
            diags.report("E0001", f"cannot read '{p}': no such file or directory", None)
    return list(dict.fromkeys(files))


def _emit(diags, files: list[str], fmt: str, quiet: bool) -> None:
    from catgrammar.diagnostics import format_github, format_json, format_text, summary_line

    if fmt == "json":
        click.echo(format_json(diags, files))
        return
    if fmt == "github":
        text = format_github(diags)
        if text:
            click.echo(text)
        return
    colour = sys.stdout.isatty() and not os.environ.get("NO_COLOR")
    if colour:
        from catgrammar.diagnostics import terminal_highlighter

        text = format_text(diags, highlight=terminal_highlighter())
    else:
        text = format_text(diags)
    if text:
        click.echo(_colour(text), err=False)
    if not quiet:
        click.echo(summary_line(diags, len(files)), err=True)


def _colour(text: str) -> str:
    if not sys.stdout.isatty() or os.environ.get("NO_COLOR"):
        return text
    import re

    def paint(m: re.Match) -> str:
        sev = m.group(2)
        colour = {"error": "red", "warning": "yellow", "note": "cyan"}[sev]
        return m.group(1) + click.style(f"{sev}[{m.group(3)}]", fg=colour, bold=True) + ":"

    return re.sub(r"^(\S*: )?(error|warning|note)\[(\w+)\]:", paint, text, flags=re.M)


@main.command()
@click.argument("paths", nargs=-1, required=True, type=click.Path())
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["text", "json", "github"]),
    default="text",
    show_default=True,
    help="Diagnostic format: compiler-style text, JSON (schema catc.check/1), or GitHub annotations.",
)
@click.option("--strict", is_flag=True, help="Treat warnings as errors.")
@click.option(
    "--path",
    "search_paths",
    multiple=True,
    type=click.Path(file_okay=False),
    help="Extra folder to search for domains (repeatable; also CATC_PATH).",
)
@click.option("-q", "--quiet", is_flag=True, help="Do not print the summary line.")
def check(paths: tuple[str, ...], fmt: str, strict: bool, search_paths: tuple[str, ...], quiet: bool) -> None:
    """Type-check .cat files and folders (for CI).

    Every domain and problem in the given files is checked; a problem's domain is found by
    name among the given files, the problem's folder, --path and the standard library.
    Exit 0 when clean, 1 on model errors, 2 when input cannot be read.
    """
    from catc.frontend.session import check_files
    from catgrammar.diagnostics import Diagnostics

    diags = Diagnostics()
    files = _collect(paths, diags)
    check_files(files, diags, search_paths)
    if strict:
        diags.promote_warnings()
    _emit(diags, files, fmt, quiet)
    codes = {d.code for d in diags.errors}
    if codes & _UNREADABLE:
        sys.exit(EXIT_INPUT)
    sys.exit(EXIT_FAIL if diags.has_errors else EXIT_OK)


# ====================================================================== queries


def _check_paths(paths: tuple[str, ...]) -> None:
    if len(paths) not in (1, 2):
        raise click.UsageError("give PROBLEM or DOMAIN PROBLEM")


def _instance(paths: tuple[str, ...], view: str | None, search_paths, problem: str | None, as_json: bool):
    """Files → checked instance with its view applied, or exit 2 with the diagnostics."""
    _check_paths(paths)
    return command.instance(paths, view, search_paths, problem, as_json)


def _with_progress(as_json: bool, run, *args, **kwargs):
    """``run(*args, **kwargs)`` with a status line on a terminal: what the query is doing
    and for how long (``progress`` messages; nothing with ``--json`` or when piped)."""
    with _progress(not as_json) as status:
        return run(*args, **kwargs, progress=command.reporter(status))


_ORDER = "catc.option_order"


class _InOrder(click.Command):
    """A command that records the order its options occurred in (``ctx.meta``): click
    groups the values of each repeatable option, and ``--minimize a --maximize b
    --minimize c`` is a lexicographic order across the two options."""

    def make_parser(self, ctx: click.Context):
        parser = super().make_parser(ctx)
        parse = parser.parse_args

        def parse_in_order(args):
            opts, rest, order = parse(args=args)
            ctx.meta[_ORDER] = [param.name for param in order]
            return opts, rest, order

        parser.parse_args = parse_in_order
        return parser


_common_query_options = [
    click.argument("paths", nargs=-1, required=True, type=click.Path()),
    click.option(
        "--horizon",
        "-k",
        type=click.IntRange(min=0),
        help="Most steps a composition may take (default: the problem's (:horizon), else the sum of use limits, else 10).",
    ),
    click.option("--view", help="Solve in this view (overrides the problem's (:view ...))."),
    click.option(
        "--sequential", is_flag=True, help="One morphism per step (default: parallel steps with non-interference)."
    ),
    click.option(
        "--path",
        "search_paths",
        multiple=True,
        type=click.Path(file_okay=False),
        help="Extra folder to search for domains.",
    ),
    click.option("--problem", "problem_name", help="The problem to use when the file defines several."),
]


def _query_options(f):
    for opt in reversed(_common_query_options):
        f = opt(f)
    return f


@main.command()
@_query_options
@click.option(
    "--timeout", type=click.FloatRange(min=0, min_open=True), help="Give up after this many seconds (exit 3)."
)
@click.option(
    "--strategy",
    type=click.Choice(["incremental", "single"]),
    default="incremental",
    show_default=True,
    help="incremental: deepen the horizon one step at a time (shortest composition); single: one check of the whole horizon.",
)
@click.option("--json", "as_json", is_flag=True, help="Print a catc.solve/1 JSON document.")
@click.option(
    "--diagram", type=click.Path(dir_okay=False, writable=True), help="Write the composition as an SVG string diagram."
)
@click.option(
    "--no-prune", is_flag=True, help="Keep activations the composition does not need (as the solver found them)."
)
def solve(paths, horizon, view, sequential, search_paths, problem_name, timeout, strategy, as_json, diagram, no_prune):
    """Find the shortest composition that reaches the goal.

    PATHS is PROBLEM, or DOMAIN PROBLEM.  Exit 0 SAT, 1 UNSAT, 2 input error, 3 unknown/timeout.
    """
    _check_paths(paths)
    command.solve(
        paths, horizon, view, sequential, search_paths, problem_name, timeout, strategy, as_json, diagram, no_prune
    )


@main.command(cls=_InOrder)
@_query_options
@click.option(
    "--minimize",
    "minimize_terms",
    multiple=True,
    metavar="EXPR",
    help="Minimise this term (repeatable; with --maximize, in the order given: lexicographic).",
)
@click.option("--maximize", "maximize_terms", multiple=True, metavar="EXPR", help="Maximise this term (repeatable).")
@click.option(
    "--timeout",
    type=click.FloatRange(min=0, min_open=True),
    help="Stop after this many seconds; the best composition so far is reported (exit 3).",
)
@click.option("--json", "as_json", is_flag=True, help="Print a catc.optimize/1 JSON document.")
@click.option(
    "--diagram", type=click.Path(dir_okay=False, writable=True), help="Write the composition as an SVG string diagram."
)
@click.option(
    "--strategy",
    type=click.Choice(["deepen", "single"]),
    default="deepen",
    show_default=True,
    help="deepen: optimise over the shortest feasible horizon, then prove nothing longer is better; "
    "single: one encoding of the whole horizon.",
)
@click.pass_context
def optimize(
    ctx,
    paths,
    horizon,
    view,
    sequential,
    search_paths,
    problem_name,
    minimize_terms,
    maximize_terms,
    timeout,
    as_json,
    diagram,
    strategy,
):
    """Find the best composition for the problem's (:metric ...) and soft constraints.

    PATHS is PROBLEM, or DOMAIN PROBLEM.  --minimize/--maximize replace the metric.  Exit 0
    optimum (OPT), 1 infeasible or unbounded, 2 input error, 3 stopped early (best-so-far
    reported as SUBOPT) or unknown.
    """
    import json

    from catc.queries.optimize import OptStatus, objectives_of
    from catc.queries.optimize import optimize as run_optimize
    from catc.semantics.validate import ValidationFailure

    inst = _instance(paths, view, search_paths, problem_name, as_json)
    objectives = _cli_objectives(ctx, inst, as_json)
    if objectives is None and not objectives_of(inst) and not inst.problem.softs:
        _input_error(
            "nothing to optimise: the problem has no (:metric ...) or (:soft ...); give --minimize or --maximize",
            as_json,
        )
    try:
        result = _with_progress(
            as_json,
            run_optimize,
            inst,
            objectives,
            horizon=horizon,
            sequential=sequential,
            timeout=timeout,
            strategy=strategy,
        )
    except ValidationFailure as exc:
        click.echo(f"catc: internal error: {exc}", err=True)
        sys.exit(70)
    from catc.present.report import optimize_json, print_optimize

    if as_json:
        click.echo(json.dumps(optimize_json(inst, result), indent=2))
    else:
        print_optimize(_console(False), inst, result)
    _write_diagram(diagram, inst, result.plan, result.states, as_json)
    sys.exit(
        {
            OptStatus.OPT: EXIT_OK,
            OptStatus.SUBOPT: EXIT_UNKNOWN,
            OptStatus.UNKNOWN: EXIT_UNKNOWN,
            OptStatus.UNSAT: EXIT_FAIL,
            OptStatus.UNBOUNDED: EXIT_FAIL,
        }[result.status]
    )


def _cli_objectives(ctx, inst, as_json):
    """--minimize/--maximize terms in command-line order, checked; None when none given."""
    from catc import ir
    from catc.frontend.check import check_objective_text
    from catgrammar.diagnostics import Diagnostics

    # the terms in command-line order: each option's values in order, interleaved as the
    # options occurred (recorded by _InOrder while parsing)
    values = {
        "minimize_terms": iter(ctx.params["minimize_terms"]),
        "maximize_terms": iter(ctx.params["maximize_terms"]),
    }
    raw = [(name.removesuffix("_terms"), next(values[name])) for name in ctx.meta.get(_ORDER, ()) if name in values]
    if not raw:
        return None
    diags = Diagnostics()
    out = []
    for sense, text in raw:
        term = check_objective_text(text, inst, diags, f"<--{sense}>")
        if term is not None:
            out.append(ir.Objective(ir.Sense(sense), term))
    if diags.has_errors:
        command.input_errors(diags, as_json)
    return out


def _excerpt_fn():
    """Source excerpts for spans, reading files on demand."""
    from catgrammar.diagnostics import _excerpt
    from catgrammar.span import Source

    cache: dict[str, Source | None] = {}

    def excerpt(span):
        if span is None:
            return []
        if span.file not in cache:
            try:
                cache[span.file] = Source(span.file, Path(span.file).read_text(encoding="utf-8"))
            except OSError:
                cache[span.file] = None
        return _excerpt(cache[span.file], span)

    return excerpt


def _parse_components(text: str | None) -> list[str] | None:
    if text is None:
        return None
    return [c for c in text.replace(",", " ").split() if c]


def _check_components(inst, names, as_json):
    unknown = [n for n in names if n not in inst.morphisms]
    if unknown:
        _input_error(f"unknown morphism(s) in the composition: {', '.join(unknown)}", as_json)


@main.command()
@_query_options
@click.option(
    "--relative-to",
    "relative_to",
    metavar="COMPONENTS",
    help="Diagnose relative to this composition (comma-separated morphisms; default: the problem's (:deployed ...); 'none' for none).",
)
@click.option(
    "--all", "all_cores", is_flag=True, help="Enumerate several distinct cores (bounded by --max and --timeout)."
)
@click.option("--max", "max_cores", type=click.IntRange(min=1), default=5, show_default=True)
@click.option("--timeout", type=click.FloatRange(min=0, min_open=True))
@click.option("--json", "as_json", is_flag=True, help="Print a catc.diagnose/1 JSON document.")
def diagnose(
    paths, horizon, view, sequential, search_paths, problem_name, relative_to, all_cores, max_cores, timeout, as_json
):
    """Explain infeasibility: an irreducible set of conflicting source constructs.

    Exit 0 when a core is found, 1 when the problem is feasible (nothing to diagnose),
    2 input error, 3 unknown.
    """
    import json

    from catc.ir.labels import label_index
    from catc.present.report import diagnosis_json, print_diagnosis
    from catc.queries.diagnose import diagnose as run_diagnose

    inst = _instance(paths, view, search_paths, problem_name, as_json)
    rel = None
    if relative_to is not None:
        rel = [] if relative_to.strip().lower() == "none" else _parse_components(relative_to)
        _check_components(inst, rel, as_json)
    result = _with_progress(
        as_json,
        run_diagnose,
        inst,
        horizon=horizon,
        sequential=sequential,
        relative_to=rel,
        all_cores=all_cores,
        max_cores=max_cores,
        timeout=timeout,
    )
    index = label_index(inst)
    if as_json:
        click.echo(json.dumps(diagnosis_json(inst, result, index), indent=2))
    else:
        print_diagnosis(_console(False), inst, result, index, _excerpt_fn())
    sys.exit({"unsat": EXIT_OK, "sat": EXIT_FAIL}.get(result.status, EXIT_UNKNOWN))


@main.command()
@_query_options
@click.option(
    "--only",
    multiple=True,
    metavar="LABEL|RESOURCE",
    help="Relax only these requirements (a label, a label prefix such as init/, or a resource name; repeatable).",
)
@click.option(
    "--weights",
    "weight_specs",
    multiple=True,
    metavar="KEY=W",
    help="Weight of the slack on matching requirements (default 1; repeatable).",
)
@click.option("--discrete", is_flag=True, help="Return a minimum set of requirements to drop instead of numeric slack.")
@click.option(
    "--relative-to",
    "relative_to",
    metavar="COMPONENTS",
    help="Keep this composition (default: the problem's (:deployed ...); 'none' for any).",
)
@click.option("--timeout", type=click.FloatRange(min=0, min_open=True))
@click.option("--json", "as_json", is_flag=True, help="Print a catc.relax/1 JSON document.")
def relax(
    paths,
    horizon,
    view,
    sequential,
    search_paths,
    problem_name,
    only,
    weight_specs,
    discrete,
    relative_to,
    timeout,
    as_json,
):
    """The least weakening of the requirements that makes the problem feasible.

    Exit 0 when a relaxation is found, 1 when none helps or the problem is already
    feasible, 2 input error, 3 unknown.
    """
    import json
    from fractions import Fraction

    from catc.ir.labels import label_index
    from catc.present.report import print_relax, relax_json
    from catc.queries.relax import relax as run_relax

    inst = _instance(paths, view, search_paths, problem_name, as_json)
    weights = {}
    for spec in weight_specs:
        key, _, value = spec.partition("=")
        try:
            weights[key] = Fraction(value)
        except (ValueError, ZeroDivisionError):
            _input_error(f"--weights expects KEY=NUMBER, got {spec!r}", as_json)
    rel = None
    if relative_to is not None:
        rel = [] if relative_to.strip().lower() == "none" else _parse_components(relative_to)
        _check_components(inst, rel, as_json)
    result = _with_progress(
        as_json,
        run_relax,
        inst,
        horizon=horizon,
        sequential=sequential,
        only=only,
        weights=weights,
        discrete=discrete,
        relative_to=rel,
        timeout=timeout,
    )
    index = label_index(inst)
    if as_json:
        click.echo(json.dumps(relax_json(inst, result, index), indent=2))
    else:
        print_relax(_console(False), inst, result, index)
    if result.status == "relaxed" and not result.proven:
        sys.exit(EXIT_UNKNOWN)
    sys.exit({"relaxed": EXIT_OK, "sat": EXIT_FAIL, "unsat": EXIT_FAIL}.get(result.status, EXIT_UNKNOWN))


@main.command()
@_query_options
@click.option(
    "--deployed",
    metavar="COMPONENTS",
    help="The deployed composition (comma-separated morphisms; default: the problem's (:deployed ...)).",
)
@click.option(
    "--priority",
    type=click.Choice(["stability", "objective"]),
    default="stability",
    show_default=True,
    help="stability: least churn first, then the mission objective; objective: the reverse.",
)
@click.option("--timeout", type=click.FloatRange(min=0, min_open=True))
@click.option("--json", "as_json", is_flag=True, help="Print a catc.recompose/1 JSON document.")
@click.option(
    "--diagram", type=click.Path(dir_okay=False, writable=True), help="Write the composition as an SVG string diagram."
)
def recompose(
    paths, horizon, view, sequential, search_paths, problem_name, deployed, priority, timeout, as_json, diagram
):
    """A new composition with the least weighted churn against the deployed one.

    Exit 0 optimum, 1 infeasible, 2 input error, 3 stopped early.
    """
    import json

    from catc.present.report import print_recompose, recompose_json
    from catc.queries.optimize import OptStatus
    from catc.queries.recompose import recompose as run_recompose

    inst = _instance(paths, view, search_paths, problem_name, as_json)
    components = _parse_components(deployed)
    if components is not None:
        _check_components(inst, components, as_json)
    elif not inst.problem.deployed:
        _input_error("no deployed composition: add (:deployed ...) to the problem or pass --deployed", as_json)
    rec = _with_progress(
        as_json,
        run_recompose,
        inst,
        deployed=components,
        priority=priority,
        horizon=horizon,
        sequential=sequential,
        timeout=timeout,
    )
    if as_json:
        click.echo(json.dumps(recompose_json(inst, rec), indent=2))
    else:
        print_recompose(_console(False), inst, rec)
    _write_diagram(diagram, inst, rec.result.plan, rec.result.states, as_json)
    status = rec.result.status
    sys.exit(
        {OptStatus.OPT: EXIT_OK, OptStatus.UNSAT: EXIT_FAIL, OptStatus.UNBOUNDED: EXIT_FAIL}.get(status, EXIT_UNKNOWN)
    )


@main.command(cls=_InOrder)
@_query_options
@click.option(
    "--minimize",
    "minimize_terms",
    multiple=True,
    metavar="EXPR",
    help="An objective to minimise (repeatable; replaces the metric).",
)
@click.option(
    "--maximize", "maximize_terms", multiple=True, metavar="EXPR", help="An objective to maximise (repeatable)."
)
@click.option(
    "--max-points", type=click.IntRange(min=1), default=100, show_default=True, help="Stop after this many points."
)
@click.option("--timeout", type=click.FloatRange(min=0, min_open=True))
@click.option(
    "--plot",
    "plot_path",
    type=click.Path(dir_okay=False, writable=True),
    help="Draw the front (first two objectives; a third as colour) to FILE.png or FILE.svg (needs the 'plots' extra).",
)
@click.option("--json", "as_json", is_flag=True, help="Print a catc.pareto/1 JSON document.")
@click.pass_context
def pareto(
    ctx,
    paths,
    horizon,
    view,
    sequential,
    search_paths,
    problem_name,
    minimize_terms,
    maximize_terms,
    max_points,
    timeout,
    plot_path,
    as_json,
):
    """Every non-dominated composition for two or more objectives.

    Objectives come from the problem's (:metric pareto ...) or from --minimize/--maximize.
    Exit 0 with a front, 1 infeasible, 2 input error, 3 stopped before the front was complete.
    """
    import json

    from catc.ir.text import to_text
    from catc.queries.pareto import ascii_plot
    from catc.queries.pareto import pareto as run_pareto
    from catc.queries.pareto import plot as draw

    inst = _instance(paths, view, search_paths, problem_name, as_json)
    objectives = _cli_objectives(ctx, inst, as_json)
    if objectives is None:
        metric = inst.problem.metric
        objectives = list(metric.objectives) if metric is not None else []
    if len(objectives) < 2:
        _input_error(
            "a Pareto front needs at least two objectives: use (:metric pareto ...) or --minimize/--maximize", as_json
        )
    result = run_pareto(
        inst, objectives, horizon=horizon, sequential=sequential, max_points=max_points, timeout=timeout
    )
    labels = [f"{o.sense.value} {to_text(o.term)}" for o in objectives]
    if plot_path and result.points:
        try:
            draw(result, labels, plot_path)
        except RuntimeError as exc:
            click.echo(f"catc: error: {exc}", err=True)
            sys.exit(EXIT_INPUT)
    if as_json:
        from catc.present.report import pareto_json

        click.echo(json.dumps(pareto_json(inst, result), indent=2))
    else:
        from catc.present.report import Table, show_value

        console = _console(False)
        if result.status == "unsat":
            console.print(f"UNSAT  no composition within {result.horizon} steps")
        else:
            done = "complete" if result.complete else "incomplete: stopped by --max-points or --timeout"
            console.print(
                f"FRONT  {len(result.points)} non-dominated compositions ({done}) for problem "
                f"{inst.problem.name} of domain {inst.domain.name}"
            )
            table = Table("#", *labels, "components", right=tuple(range(len(labels) + 1)))
            for n, p in enumerate(result.points, 1):
                table.add_row(str(n), *[show_value(v) for v in p.values], " ".join(sorted(p.plan.components)))
            console.print(table)
            if result.points:
                console.print()
                console.print(ascii_plot(result, labels))
        if plot_path and result.points:
            click.echo(f"plot written to {plot_path}", err=True)
    sys.exit(
        EXIT_OK
        if result.status == "front" and result.complete
        else EXIT_FAIL
        if result.status == "unsat"
        else EXIT_UNKNOWN
    )


@main.command()
@_query_options
@click.option("--hole", "hole_name", help="The hole to fill (default: the domain's only one).")
@click.option(
    "--emit",
    type=click.Choice(["text", "cat"]),
    default="text",
    show_default=True,
    help="cat: print only the (:morphism ...) skeleton, ready to paste into the domain.",
)
@click.option("--timeout", type=click.FloatRange(min=0, min_open=True))
@click.option("--json", "as_json", is_flag=True, help="Print a catc.synthesize/1 JSON document.")
def synthesize(paths, horizon, view, sequential, search_paths, problem_name, hole_name, emit, timeout, as_json):
    """The weakest specification of a missing component (a hole μ) that makes the problem feasible.

    Exit 0 when synthesised (or no hole is needed), 1 when even a hole cannot help,
    2 input error, 3 unknown.
    """
    import json

    from catc.queries.synthesize import synthesize as run_synthesize
    from catc.queries.synthesize import to_cat

    inst = _instance(paths, view, search_paths, problem_name, as_json)
    try:
        result = run_synthesize(inst, hole_name, horizon=horizon, sequential=sequential, timeout=timeout)
    except ValueError as exc:
        _input_error(str(exc), as_json)
    skeleton = to_cat(result.morphism, result.hole) if result.morphism is not None else None
    if as_json:
        from catc.present.report import synthesize_json

        click.echo(json.dumps(synthesize_json(result), indent=2))
    elif emit == "cat":
        if skeleton is None:
            click.echo(f"; no skeleton: {result.status}", err=True)
        else:
            click.echo(skeleton, nl=False)
    else:
        console = _console(False)
        if result.status == "not-needed":
            console.print(f"SAT  no hole needed: a composition exists without '{result.hole.name}'")
        elif result.status == "synthesised":
            console.print(
                f"SYNTHESISED  hole '{result.hole.name}'"
                + (f" in view '{result.hole.view}'" if result.hole.view else "")
                + f": {len(result.morphism.effects)} effect(s) it must provide, "
                f"{len(result.morphism.pre)} precondition(s) it may assume; applied at step {result.step}"
            )
            console.print(skeleton.rstrip())
            from types import SimpleNamespace

            from catc.present.report import print_solve

            console.print("\nthe composition it completes:")
            shim = SimpleNamespace(
                status=SimpleNamespace(value="sat"),
                plan=result.plan,
                states=result.states,
                timings={},
                horizons_tried=1,
            )
            print_solve(console, result.instance, shim, timings=False, header=False)
        else:
            console.print(
                f"UNSAT  even a component in hole '{result.hole.name}' cannot make the problem feasible"
                if result.status == "unsat"
                else "UNKNOWN  the solver gave up"
            )
    sys.exit({"synthesised": EXIT_OK, "not-needed": EXIT_OK, "unsat": EXIT_FAIL}.get(result.status, EXIT_UNKNOWN))


@main.command()
@_query_options
@click.argument("plan_file", type=click.Path(dir_okay=False))
@click.option("--json", "as_json", is_flag=True, help="Print a catc.validate/1 JSON document.")
def validate(paths, horizon, view, sequential, search_paths, problem_name, plan_file, as_json):
    """Replay a composition from elsewhere (a catc.plan/1 JSON file) and report every violation.

    PATHS is PROBLEM, or DOMAIN PROBLEM.  Exit 0 valid, 1 invalid, 2 input error.
    """
    import json

    from catc.semantics.plan import PlanFormatError, plan_from_json
    from catc.semantics.validate import validate as run_validate

    inst = _instance(paths, view, search_paths, problem_name, as_json)
    try:
        doc = json.loads(Path(plan_file).read_text(encoding="utf-8"))
        sorts = {
            m.name: {p.name: (p.sort.kind.value if not p.sort.is_symbolic else "symbol") for p in m.params}
            for m in inst.morphisms.values()
        }
        plan = plan_from_json(doc, sorts)
    except (OSError, UnicodeDecodeError) as exc:
        click.echo(f"{plan_file}: error[E0001]: cannot read the plan: {exc}", err=True)
        sys.exit(EXIT_INPUT)
    except json.JSONDecodeError as exc:
        click.echo(f"{plan_file}:{exc.lineno}:{exc.colno}: error[E0101]: not JSON: {exc.msg}", err=True)
        sys.exit(EXIT_INPUT)
    except PlanFormatError as exc:
        click.echo(f"{plan_file}: error[E0101]: {exc}", err=True)
        sys.exit(EXIT_INPUT)
    report = run_validate(inst, plan, horizon=horizon, sequential=sequential)
    if as_json:
        from catc.present.report import validate_json

        click.echo(json.dumps(validate_json(report), indent=2))
    elif report.ok:
        click.echo(f"valid: {len(plan)} steps reach the goal of '{inst.problem.name}'")
    else:
        click.echo(f"invalid: {len(report.violations)} violation{'s' if len(report.violations) != 1 else ''}")
        for v in report.violations:
            where = f"step {v.step}: " if v.step is not None else ""
            click.echo(f"  {where}{v.kind}: {v.message}")
    sys.exit(EXIT_OK if report.ok else EXIT_FAIL)


@main.command()
@_query_options
@click.option("--emit", type=click.Choice(["smt2"]), default="smt2", show_default=True, help="Output language.")
@click.option(
    "-o", "--output", type=click.Path(dir_okay=False, writable=True), help="Write here instead of standard output."
)
def compile(paths, horizon, view, sequential, search_paths, problem_name, emit, output):
    """Compile a problem to SMT-LIB2 (named assertions map cores back to source).

    PATHS is PROBLEM, or DOMAIN PROBLEM.
    """
    from catc.semantics.horizon import default_horizon
    from catc.smt.smtlib import emit_smt2

    inst = _instance(paths, view, search_paths, problem_name, False)
    k = default_horizon(inst) if horizon is None else horizon
    text = emit_smt2(inst, k, sequential=sequential)
    if output:
        Path(output).write_text(text, encoding="utf-8")
    else:
        click.echo(text, nl=False)


if __name__ == "__main__":  # pragma: no cover
    main()
