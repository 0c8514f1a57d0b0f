"""``catc check`` without click, for the plain command lines :mod:`catc.interfaces.entry` sends
here: paths, ``--format text|json|github`` (``--json``), ``--strict``, ``-q``/``--quiet``.  Anything else
(help, ``--path``, ``--limit``, ``--memory``, an unknown option, colour on a terminal) is left
to the click command in :mod:`catc.interfaces.cli`, which prints the same for the same input
(``tests/test_startup.py`` compares the two routes).  Importing click costs about 20 ms, as
much as checking a small model.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Any, NoReturn

from catc.interfaces.command import EXIT_FAIL, EXIT_INPUT, EXIT_OK
from catgrammar import codes

FORMATS = ("text", "json", "github")

_UNREADABLE = {codes.UNREADABLE_FILE, codes.BINARY_FILE, codes.INVALID_UTF8, codes.NO_INPUT}


def parse_check(args: list[str]) -> dict[str, Any] | None:
    """The parameters of ``catc check ARGS``, or None to leave the command line to click."""
    params: dict[str, Any] = {"paths": [], "fmt": "text", "strict": False, "quiet": False}
    rest = iter(args)
    for arg in rest:
        if not arg.startswith("-"):
            if not arg:
                return None
            params["paths"].append(arg)
        elif arg == "--strict":
            params["strict"] = True
        elif arg in ("-q", "--quiet"):
            params["quiet"] = True
        elif arg == "--json":
            params["fmt"] = "json"
        elif arg == "--format" or arg.startswith("--format="):
            value = arg.partition("=")[2] if "=" in arg else next(rest, None)
            if value not in FORMATS:
                return None
            params["fmt"] = value
        else:
            return None
    if not params["paths"]:
        return None
    if params["fmt"] == "text" and sys.stdout.isatty() and not os.environ.get("NO_COLOR"):
        return None  # the coloured text is click's (it highlights with pygments)
    return params


def collect_files(paths: list[str] | tuple[str, ...], diags: Any) -> list[str]:
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


def run_check(paths: list[str], fmt: str, strict: bool, quiet: bool) -> NoReturn:
    """Check ``paths`` under the environment's limits, print the diagnostics and exit 0 (clean),
    1 (model errors) or 2 (unreadable input)."""
    from catc.frontend.session import check_files
    from catc.interfaces import command
    from catgrammar import limits
    from catgrammar.diagnostics import Diagnostics, format_github, format_json, format_text, summary_line

    diags = Diagnostics()
    files = collect_files(paths, diags)
    with limits.using(command.command_limits((), None, False)):
        check_files(files, diags, command.search_path())
    if strict:
        diags.promote_warnings()
    if fmt == "json":
        _write(sys.stdout, format_json(diags, files))
    elif fmt == "github":
        text = format_github(diags)
        if text:
            _write(sys.stdout, text)
    else:
        text = format_text(diags)
        if text:
            _write(sys.stdout, text)
        if not quiet:
            _write(sys.stderr, summary_line(diags, len(files)))
    found = {d.code for d in diags.errors}
    if found & _UNREADABLE:
        sys.exit(EXIT_INPUT)
    sys.exit(EXIT_FAIL if diags.has_errors else EXIT_OK)


def _write(stream: Any, text: str) -> None:
    stream.write(text + "\n")
    stream.flush()
