"""``catc fmt``: the canonical layout of .cat files (:mod:`catc.frontend.formatter`)."""

from __future__ import annotations

import difflib
import sys

import click

from catc.frontend.formatter import format_file
from catc.interfaces.check_command import collect_files
from catc.interfaces.cli.options import limit_options, limited
from catgrammar.diagnostics import Diagnostics
from catgrammar.diagnostics import format_text as diag_text
from catgrammar.terminal import printable


@click.command("fmt")
@click.argument("paths", nargs=-1, required=True, type=click.Path())
@click.option("--check", is_flag=True, help="Write nothing: list the files that would change and exit 1 if any.")
@click.option("--diff", is_flag=True, help="Write nothing: print what would change as a unified diff; exit 1 if any.")
@limit_options
def fmt_command(
    paths: tuple[str, ...], check: bool, diff: bool, limit_specs: tuple[str, ...] = (), memory: int | None = None
) -> None:
    """Rewrite .cat files (and folders) in the canonical layout, keeping comments.

    With --check or --diff, nothing is written: the files that are not formatted are listed
    (--check) or their changes printed (--diff), and the exit code is 1.  Exit 2 when a file
    cannot be read or parsed (the diagnostics of catc check are printed).  The limits of
    catc check (--limit, --memory; docs/limits.md) hold.
    """
    diags = Diagnostics()
    files = collect_files(paths, diags)
    changed: list[str] = []
    with limited(limit_specs, memory):  # issue 28: fmt had none of check's limits
        results = [(f, format_file(f, diags)) for f in files]
    for f, r in results:
        if r is None:
            continue
        before, after = r
        if before == after:
            continue
        changed.append(f)
        if diff:
            lines = difflib.unified_diff(
                before.splitlines(keepends=True), after.splitlines(keepends=True), f"a/{f}", f"b/{f}"
            )
            click.echo(printable("".join(lines)), nl=False)
        elif check:
            click.echo(printable(f"would reformat {f}"))
        else:
            with open(f, "w", encoding="utf-8", newline="\n") as fh:
                fh.write(after)
            click.echo(printable(f"reformatted {f}"), err=True)
    if diags.has_errors:
        click.echo(diag_text(diags), err=True)
        sys.exit(2)
    if (check or diff) and changed:
        click.echo(f"{len(changed)} file(s) would be reformatted", err=True)
        sys.exit(1)
    sys.exit(0)
