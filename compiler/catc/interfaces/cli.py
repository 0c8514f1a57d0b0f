"""The ``catc`` command line (click).

Every query of the registry (:mod:`catc.queries.registry`) is a command built from its
options; ``check``, ``compile``, ``fmt``, ``lsp``, ``export`` and ``bench`` are written out.
Commands load on first use (start-up time).

Exit codes (docs/cli.md): 0 success; 1 model errors (``check``) or infeasible (queries);
2 usage or unreadable input (and, for queries, any input error); 3 the solver gave up.
No command lets a Python traceback reach the user for bad input.
"""

from __future__ import annotations

import importlib
import math
import os
import re
import sys
from pathlib import Path
from typing import Any

import click

from catc import __version__
from catc.interfaces import command
from catc.interfaces.command import EXIT_FAIL, EXIT_INPUT, EXIT_OK
from catc.queries import registry
from catc.queries.base import Kind, Option, Query
from catgrammar import codes

_UNREADABLE = {codes.UNREADABLE_FILE, codes.BINARY_FILE, codes.INVALID_UTF8, codes.NO_INPUT}

#: Commands defined in their own modules, imported only when used (start-up time):
#: name → "module:attribute" of a click command.
LAZY_COMMANDS: dict[str, str] = {
    "fmt": "catc.interfaces.fmt_command:fmt_command",
    "lsp": "catc.interfaces.lsp:lsp_command",
    "export": "catc.interfaces.export_cli:export_command",
    "ground": "catc.interfaces.ground:ground_command",
    "bench": "catc.bench.cli:bench_command",
    "init": "catc.interfaces.conveniences:init_command",
    "explain": "catc.interfaces.conveniences:explain_command",
    "import": "catc.interfaces.import_cli:import_command",
}


class _Group(click.Group):
    """Usage errors exit 2 (click's default); unexpected exceptions become a one-line
    internal-error report with exit 70 instead of a traceback (set CATC_DEBUG=1 to see it).
    Query commands and those in :data:`LAZY_COMMANDS` are made on first use."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        lazy = {n for n in LAZY_COMMANDS if self._lazy(n) is not None}
        return sorted(set(super().list_commands(ctx)) | lazy | set(registry.names()))

    def get_command(self, ctx: click.Context, name: str) -> click.Command | None:
        found = super().get_command(ctx, name)
        if found is not None:
            return found
        if name in registry.QUERIES:
            return query_command(registry.get(name))
        return self._lazy(name)

    @staticmethod
    def _lazy(name: str) -> click.Command | None:
        target = LAZY_COMMANDS.get(name)
        if target is None:
            return None
        module, _, attr = target.partition(":")
        try:
            found: click.Command = getattr(importlib.import_module(module), attr)
        except ImportError:  # the command's module is not there (yet); optional extras report themselves
            return None
        return found

    def invoke(self, ctx: click.Context) -> Any:
        return command.guarded(
            self._invoke_limited, ctx, passthrough=(click.exceptions.Exit, click.exceptions.Abort, click.ClickException)
        )

    def _invoke_limited(self, ctx: click.Context) -> Any:
        """Every command runs under the limits of the environment (``CATC_LIMIT_*``); those
        with ``--limit``/``--memory`` refine them and cap the process's memory (:func:`limited`;
        ``bench``, ``fmt`` and ``lsp`` leave their process as it is)."""
        from catgrammar import limits

        with limits.using(command.command_limits((), None, False, cap_memory=False)):
            return super().invoke(ctx)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="catc")
def main() -> None:
    """catc — compile .cat robot-recomposition models and answer lifecycle queries."""


# ====================================================================== queries

_ORDER = "catc.option_order"


class _InOrder(click.Command):
    """A command that records the order its options occurred in (``ctx.meta``): click
    groups the values of each repeatable option, and ``--minimize a --maximize b
    --minimize c`` is a lexicographic order across the two options."""

    def make_parser(self, ctx: click.Context) -> Any:
        parser = super().make_parser(ctx)
        parse = parser.parse_args

        def parse_in_order(args: list[str]) -> Any:
            opts, rest, order = parse(args=args)
            ctx.meta[_ORDER] = [param.name for param in order]
            return opts, rest, order

        parser.parse_args = parse_in_order  # type: ignore[method-assign]
        return parser


_TYPES: dict[Kind, Any] = {
    Kind.COUNT: click.IntRange(min=0),
    Kind.POSITIVE: click.IntRange(min=1),
    Kind.SECONDS: click.FloatRange(min=0, min_open=True),
    Kind.FOLDERS: click.Path(file_okay=False),
    Kind.OUTPUT_FILE: click.Path(dir_okay=False, writable=True),
}


def click_params(option: Option) -> list[click.Parameter]:
    """The click parameters of one query option (``--minimize``/``--maximize``: two)."""
    kind, flags, name = option.kind, list(option.flags), option.name
    if kind is Kind.PLAN_FILE:
        return [click.Argument([name], metavar=option.flags[0], type=click.Path(dir_okay=False))]
    if kind is Kind.OBJECTIVES:
        helps = option.help.split("\n")
        return [
            click.Option([flag, f"{flag[2:]}_terms"], multiple=True, metavar=option.metavar, help=text)
            for flag, text in zip(option.flags, helps)
        ]
    extra: dict[str, Any] = {"help": option.help or None}
    if kind is Kind.FLAG:
        extra.update(is_flag=True, default=False)
    elif kind is Kind.NO_FLAG:
        extra.update(is_flag=True, flag_value=False, default=True)
    elif kind is Kind.CHOICE:
        extra.update(type=click.Choice(list(option.choices)), default=option.default, show_default=option.show_default)
    elif kind in (Kind.TEXTS, Kind.FOLDERS, Kind.WEIGHTS):
        extra.update(multiple=True, metavar=option.metavar)
        if kind in _TYPES:
            extra["type"] = _TYPES[kind]
    else:
        extra.update(metavar=option.metavar, type=_TYPES.get(kind))
        if option.default is not None:
            extra.update(default=option.default, show_default=option.show_default)
    return [click.Option([*flags, name], **extra)]


def query_command(query: Query) -> click.Command:
    """The click command of ``query``: ``PATHS`` (PROBLEM or DOMAIN PROBLEM), then its options."""
    params: list[click.Parameter] = [click.Argument(["paths"], nargs=-1, required=True, type=click.Path())]
    for option in query.options:
        params.extend(click_params(option))
    ordered = any(o.kind is Kind.OBJECTIVES for o in query.options)

    def callback(paths: tuple[str, ...], **params: Any) -> None:
        if len(paths) not in (1, 2):
            raise click.UsageError("give PROBLEM or DOMAIN PROBLEM")
        command.run_query(query.name, paths, raw_values(query, params, click.get_current_context()))

    cls = _InOrder if ordered else click.Command
    return cls(query.name, params=params, callback=callback, help=f"{query.summary}\n\n{query.description}")


def raw_values(query: Query, params: dict[str, Any], ctx: click.Context) -> dict[str, Any]:
    """click's parameters → the raw option values :func:`command.run_query` takes."""
    raw: dict[str, Any] = {}
    for option in query.options:
        if option.kind is Kind.OBJECTIVES:
            # in command-line order: each option's values in order, interleaved as the
            # options occurred (recorded by _InOrder while parsing)
            values = {f"{flag[2:]}_terms": iter(params[f"{flag[2:]}_terms"]) for flag in option.flags}
            order = [n for n in ctx.meta.get(_ORDER, ()) if n in values]
            raw[option.name] = [(n.removesuffix("_terms"), next(values[n])) for n in order] or None
        elif option.name in params:
            raw[option.name] = params[option.name]
    return raw


# ====================================================================== check, compile


def collect_files(paths: tuple[str, ...], diags: Any) -> list[str]:
    """The .cat files named, and those under the folders named."""
    files: list[str] = []
    for p in paths:
        path = Path(p)
        if path.is_dir():
            found = sorted(str(f) for f in path.rglob("*.cat") if f.is_file())
            if not found:
                diags.report(codes.NO_INPUT, f"no .cat files under '{p}'", None)
            files.extend(found)
        elif path.exists():
            files.append(str(path))
        else:
            diags.report(codes.UNREADABLE_FILE, f"cannot read '{p}': no such file or directory", None)
    return list(dict.fromkeys(files))


def _emit(diags: Any, files: list[str], fmt: str, quiet: bool) -> None:
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
        from catgrammar.lexer import terminal_highlighter

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

    def paint(m: re.Match[str]) -> str:
        sev = m.group(2)
        colour = {"error": "red", "warning": "yellow", "note": "cyan"}[sev]
        return m.group(1) + click.style(f"{sev}[{m.group(3)}]", fg=colour, bold=True) + ":"

    return re.sub(r"^(\S*: )?(error|warning|note)\[(\w+)\]:", paint, text, flags=re.M)


def limit_options(f: Any) -> Any:
    """``--limit NAME=N`` (repeatable) and ``--memory MB`` on a command (docs/limits.md)."""
    f = click.option(
        "--memory",
        type=click.IntRange(min=0),
        metavar="MB",
        help="The most memory the command may use, in MB (0: no limit; default 8192, or CATC_LIMIT_MEMORY).",
    )(f)
    return click.option(
        "--limit",
        "limit_specs",
        multiple=True,
        metavar="NAME=N",
        help="Set a limit: NAME=N, e.g. horizon=5000 (repeatable; the limits and their defaults: docs/limits.md).",
    )(f)


def limited(specs: tuple[str, ...], memory: int | None) -> Any:
    """The block runs under the environment's limits with ``--limit`` and ``--memory`` applied
    (E1111 when malformed), and the process's memory capped."""
    from catgrammar import limits

    found = command.command_limits(specs, memory, False)
    return limits.using(found)


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
@limit_options
def check(
    paths: tuple[str, ...],
    fmt: str,
    strict: bool,
    search_paths: tuple[str, ...],
    quiet: bool,
    limit_specs: tuple[str, ...],
    memory: int | None,
) -> None:
    """Type-check .cat files and folders (for CI).

    Every domain and problem in the given files is checked; a problem's domain is found by
    name among the given files, the problem's folder, --path and the standard library.
    Exit 0 when clean, 1 on model errors, 2 when input cannot be read.
    """
    from catc.frontend.session import check_files
    from catgrammar.diagnostics import Diagnostics

    diags = Diagnostics()
    files = collect_files(paths, diags)
    with limited(limit_specs, memory):
        check_files(files, diags, command.search_path(search_paths))
    if strict:
        diags.promote_warnings()
    _emit(diags, files, fmt, quiet)
    found = {d.code for d in diags.errors}
    if found & _UNREADABLE:
        sys.exit(EXIT_INPUT)
    sys.exit(EXIT_FAIL if diags.has_errors else EXIT_OK)


@main.command()
@click.argument("paths", nargs=-1, required=True, type=click.Path())
@click.option(
    "--horizon",
    "-k",
    type=click.IntRange(min=0),
    help="Most steps a composition may take (default: the problem's (:horizon), else the sum of use limits, else 10).",
)
@click.option("--view", help="Compile this view (overrides the problem's (:view ...)).")
@click.option(
    "--sequential", is_flag=True, help="One morphism per step (default: parallel steps with non-interference)."
)
@click.option(
    "--path",
    "search_paths",
    multiple=True,
    type=click.Path(file_okay=False),
    help="Extra folder to search for domains.",
)
@click.option("--problem", "problem_name", help="The problem to use when the file defines several.")
@click.option("--emit", type=click.Choice(["smt2"]), default="smt2", show_default=True, help="Output language.")
@click.option(
    "-o", "--output", type=click.Path(dir_okay=False, writable=True), help="Write here instead of standard output."
)
@click.option(
    "--timeout",
    type=click.FloatRange(min=0, min_open=True),
    help="Give up after this many seconds (exit 3, error E1109).",
)
@limit_options
def compile(
    paths: tuple[str, ...],
    horizon: int | None,
    view: str | None,
    sequential: bool,
    search_paths: tuple[str, ...],
    problem_name: str | None,
    emit: str,
    output: str | None,
    timeout: float | None,
    limit_specs: tuple[str, ...],
    memory: int | None,
) -> None:
    """Compile a problem to SMT-LIB2 (named assertions map cores back to source).

    PATHS is PROBLEM, or DOMAIN PROBLEM.
    """
    from catc.semantics.horizon import horizon_of
    from catc.smt.smtlib import emit_smt2
    from catgrammar import limits

    if len(paths) not in (1, 2):
        raise click.UsageError("give PROBLEM or DOMAIN PROBLEM")
    if timeout is not None and not math.isfinite(timeout):
        command.argument_error(
            f"--timeout must be a finite number of seconds, got {timeout}", codes.BAD_ARGUMENT, False
        )
    with limited(limit_specs, memory), limits.deadline(timeout):
        inst = command.instance(paths, view, search_paths, problem_name, False)
        text = emit_smt2(inst, horizon_of(inst, horizon), sequential=sequential)
    if output:
        Path(output).write_text(text, encoding="utf-8")
    else:
        click.echo(text, nl=False)


if __name__ == "__main__":  # pragma: no cover
    main()
