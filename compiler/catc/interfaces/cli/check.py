"""``catc check``: type-check .cat files and folders (for CI)."""

from __future__ import annotations

import os
import re
import sys
from typing import Any

import click

from catc.interfaces import command
from catc.interfaces.check_command import collect_files
from catc.interfaces.cli.options import limit_options, limited, option
from catc.interfaces.command import EXIT_FAIL, EXIT_INPUT, EXIT_OK
from catc.queries.base import load_options
from catgrammar import codes

_UNREADABLE = {codes.UNREADABLE_FILE, codes.BINARY_FILE, codes.INVALID_UTF8, codes.NO_INPUT}


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


@click.command()
@click.argument("paths", nargs=-1, required=True, type=click.Path())
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["text", "json", "github"]),
    default="text",
    show_default=True,
    help="Diagnostic format: compiler-style text, JSON (schema catc.check/1), or GitHub annotations.",
)
@click.option(
    "--json",
    "as_json",
    is_flag=True,
    help="The same as --format json (every other command spells its JSON output --json).",
)
@click.option("--strict", is_flag=True, help="Treat warnings as errors.")
@option(load_options("", path_help="Extra folder to search for domains (repeatable; also CATC_PATH).")[1])
@click.option("-q", "--quiet", is_flag=True, help="Do not print the summary line.")
@limit_options
def check(
    paths: tuple[str, ...],
    fmt: str,
    as_json: bool,
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

    if as_json:
        fmt = "json"
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
