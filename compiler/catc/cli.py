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

EXIT_OK = 0
EXIT_FAIL = 1
EXIT_INPUT = 2
EXIT_UNKNOWN = 3

_UNREADABLE = {"E0001", "E0002", "E0003", "E0005"}


class _Group(click.Group):
    """Usage errors exit 2 (click's default); unexpected exceptions become a one-line
    internal-error report with exit 70 instead of a traceback (set CATC_DEBUG=1 to see it)."""

    def invoke(self, ctx: click.Context):
        try:
            return super().invoke(ctx)
        except (click.exceptions.Exit, click.exceptions.Abort, click.ClickException, SystemExit):
            raise
        except RecursionError:
            click.echo("catc: error: input nests too deeply to process", err=True)
            sys.exit(EXIT_INPUT)
        except Exception as exc:  # pragma: no cover - a bug, reported without a traceback
            if os.environ.get("CATC_DEBUG"):
                raise
            click.echo(f"catc: internal error: {type(exc).__name__}: {exc} (set CATC_DEBUG=1 for details)", err=True)
            sys.exit(70)


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
@click.option("--format", "fmt", type=click.Choice(["text", "json", "github"]), default="text", show_default=True,
              help="Diagnostic format: compiler-style text, JSON (schema catc.check/1), or GitHub annotations.")
@click.option("--strict", is_flag=True, help="Treat warnings as errors.")
@click.option("--path", "search_paths", multiple=True, type=click.Path(file_okay=False),
              help="Extra folder to search for domains (repeatable; also CATC_PATH).")
@click.option("-q", "--quiet", is_flag=True, help="Do not print the summary line.")
def check(paths: tuple[str, ...], fmt: str, strict: bool, search_paths: tuple[str, ...], quiet: bool) -> None:
    """Type-check .cat files and folders (for CI).

    Every domain and problem in the given files is checked; a problem's domain is found by
    name among the given files, the problem's folder, --path and the standard library.
    Exit 0 when clean, 1 on model errors, 2 when input cannot be read.
    """
    from catc.session import check_files
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


if __name__ == "__main__":  # pragma: no cover
    main()
