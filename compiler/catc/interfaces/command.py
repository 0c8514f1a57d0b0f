"""What the command line does, without click.

:mod:`catc.interfaces.cli` defines the commands with click; :mod:`catc.interfaces.entry` runs a plain
``catc solve`` command line without importing click at all (click's import is about a
fifth of a small solve's whole run, docs/benchmarks.md).  Both call the functions here,
so a command behaves the same whichever way it was parsed: the same output, exit codes
and error handling.  Nothing here may import click.

Exit codes (docs/cli.md): 0 success; 1 model errors (``check``) or infeasible (queries);
2 usage or unreadable input (and, for queries, any input error); 3 the solver gave up;
70 an internal error.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, NoReturn

EXIT_OK = 0
EXIT_FAIL = 1
EXIT_INPUT = 2
EXIT_UNKNOWN = 3
EXIT_INTERNAL = 70


def echo(text: str = "", err: bool = False) -> None:
    """``click.echo`` for text: one line to standard output (or error), flushed."""
    stream = sys.stderr if err else sys.stdout
    stream.write(text + "\n")
    stream.flush()


def guarded(
    call: Callable[..., Any], *args: Any, passthrough: tuple[type[BaseException], ...] = (), **kwargs: Any
) -> Any:
    """Run a command so that no traceback reaches the user: a closed pipe (``catc solve |
    head``) stops quietly, input nesting too deeply is an input error, and anything else
    unexpected is a one-line internal-error report with exit 70 (``CATC_DEBUG=1`` shows
    the traceback).  ``passthrough`` exceptions (click's own) propagate unchanged."""
    try:
        return call(*args, **kwargs)
    except (SystemExit, *passthrough):
        raise
    except BrokenPipeError:  # stop quietly, as Unix tools do
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        sys.exit(EXIT_FAIL)
    except RecursionError:
        echo("catc: error: input nests too deeply to process", err=True)
        sys.exit(EXIT_INPUT)
    except Exception as exc:  # a bug, reported without a traceback
        if os.environ.get("CATC_DEBUG"):
            raise
        echo(f"catc: internal error: {type(exc).__name__}: {exc} (set CATC_DEBUG=1 for details)", err=True)
        sys.exit(EXIT_INTERNAL)


# ---------------------------------------------------------------- shared by the queries


def instance(paths: tuple[str, ...], view: str | None, search_paths, problem: str | None, as_json: bool):
    """PROBLEM or DOMAIN PROBLEM (the caller checks there are one or two paths) → the
    checked instance with its view applied, or exit 2 with the diagnostics."""
    from catc.interfaces.api import load_checked
    from catgrammar.diagnostics import Diagnostics

    domain_path, problem_path = (None, paths[0]) if len(paths) == 1 else paths
    diags = Diagnostics()
    inst = load_checked(problem_path, domain_path, diags, view=view, problem_name=problem, search_paths=search_paths)
    if inst is None:
        input_errors(diags, as_json)
    return inst


def input_errors(diags, as_json: bool) -> NoReturn:
    """Report located input errors — a catc.error/1 document with ``--json``, compiler-style
    text on standard error otherwise — and exit 2."""
    if as_json:
        import json

        echo(
            json.dumps(
                {"schema": "catc.error/1", "status": "error", "diagnostics": [d.to_json() for d in diags.sorted()]},
                indent=2,
            )
        )
    else:
        from catgrammar.diagnostics import format_text

        echo(format_text(diags), err=True)
    sys.exit(EXIT_INPUT)


def console(as_json: bool = False):
    """Rich on a terminal; plain aligned text when piped (no colour codes, faster start)."""
    if sys.stdout.isatty() and not os.environ.get("NO_COLOR"):
        from rich.console import Console

        return Console(highlight=False)
    from catc.present.report import PlainConsole

    return PlainConsole(echo)


def progress(enabled: bool):
    """A rich status line on a terminal (stderr), showing what the query is doing."""
    import contextlib

    if not enabled or not sys.stderr.isatty():
        return contextlib.nullcontext(None)
    from rich.console import Console

    return Console(stderr=True).status("solving…")


def reporter(status) -> Callable[[str], None] | None:
    """A ``progress(message)`` callback for a query, showing ``message`` on the status line
    with the time since the query started, kept current while the solver works (rich
    redraws the line from its own thread); None without a status line."""
    if status is None:
        return None
    import time

    from rich.text import Text

    start = time.perf_counter()

    class Live:
        def __init__(self, message: str) -> None:
            self.message = message

        def __rich__(self) -> Text:
            return Text(f"{self.message} ({time.perf_counter() - start:.1f} s)")

    return lambda message: status.update(Live(message))


def input_error(message: str, as_json: bool) -> NoReturn:
    """A bad command-line argument found after parsing (an objective, a weight, ...): exit 2."""
    if as_json:
        import json

        echo(
            json.dumps(
                {
                    "schema": "catc.error/1",
                    "status": "error",
                    "diagnostics": [
                        {
                            "code": "E0505",
                            "name": "bad-objective",
                            "severity": "error",
                            "message": message,
                            "location": None,
                            "notes": [],
                        }
                    ],
                },
                indent=2,
            )
        )
    else:
        echo(f"catc: error[E0505]: {message}", err=True)
    sys.exit(EXIT_INPUT)


def write_diagram(path, inst, plan, states, as_json: bool) -> None:
    if not path or plan is None:
        return
    from catc.present.diagram import render_svg

    Path(path).write_text(
        render_svg(inst, plan, states=list(states), title=f"{inst.problem.name} ({inst.domain.name})"), encoding="utf-8"
    )
    if not as_json:
        echo(f"diagram written to {path}", err=True)


# ---------------------------------------------------------------- catc solve


def solve(
    paths: tuple[str, ...],
    horizon: int | None = None,
    view: str | None = None,
    sequential: bool = False,
    search_paths: tuple[str, ...] = (),
    problem_name: str | None = None,
    timeout: float | None = None,
    strategy: str = "incremental",
    as_json: bool = False,
    diagram: str | None = None,
    no_prune: bool = False,
) -> NoReturn:
    """``catc solve``: print the shortest composition (or why there is none) and exit
    0 SAT, 1 UNSAT, 2 input error, 3 unknown/timeout."""
    from catc.queries.solve import Status
    from catc.queries.solve import solve as run_solve
    from catc.semantics.validate import ValidationFailure

    inst = instance(paths, view, search_paths, problem_name, as_json)
    with progress(not as_json) as status:
        report = reporter(status)
        try:
            result = run_solve(
                inst,
                horizon=horizon,
                sequential=sequential,
                timeout=timeout,
                strategy=strategy,
                progress=report and (lambda t, k, elapsed: report(f"solving: horizon {t} of {k}")),
                prune=not no_prune,
            )
        except ValidationFailure as exc:
            echo(f"catc: internal error: {exc}", err=True)
            sys.exit(EXIT_INTERNAL)
    if as_json:
        import json

        from catc.present.report import solve_json

        echo(json.dumps(solve_json(inst, result), indent=2))
    else:
        from catc.present.report import print_solve

        print_solve(console(), inst, result)
    write_diagram(diagram, inst, result.plan if result.status is Status.SAT else None, result.states, as_json)
    sys.exit({Status.SAT: EXIT_OK, Status.UNSAT: EXIT_FAIL, Status.UNKNOWN: EXIT_UNKNOWN}[result.status])
