"""What a query command does, without click: load, convert the arguments, run, print, exit.

:mod:`catc.interfaces.cli` builds the click commands from the query registry;
:mod:`catc.interfaces.entry` reads plain command lines without importing click at all
(click's import is about a fifth of a small solve's whole run, docs/benchmarks.md).  Both
hand the same raw values to :func:`run_query`, so a command behaves the same whichever way
it was parsed: the same output, exit codes and error handling.  Nothing here may import click.

Exit codes (docs/cli.md): 0 success; 1 model errors (``check``) or infeasible (queries);
2 usage or unreadable input (and, for queries, any input error); 3 the solver gave up;
70 an internal error.
"""

from __future__ import annotations

import math
import os
import sys
from collections.abc import Callable, Mapping, Sequence
from fractions import Fraction
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

from catc.interfaces import guard
from catc.queries.base import ExitCode, InputError, Kind, Query
from catgrammar import codes

if TYPE_CHECKING:  # pragma: no cover
    from catc import ir
    from catgrammar.diagnostics import Diagnostics

EXIT_OK, EXIT_FAIL, EXIT_INPUT, EXIT_UNKNOWN, EXIT_INTERNAL = (
    ExitCode.OK,
    ExitCode.FAIL,
    ExitCode.INPUT,
    ExitCode.UNKNOWN,
    ExitCode.INTERNAL,
)


def echo(text: str = "", err: bool = False) -> None:
    """``click.echo`` for text: one line to standard output (or error), flushed, with
    control characters shown as escapes (a ``:unit`` or a path cannot drive the terminal)."""
    from catgrammar.terminal import printable

    stream = sys.stderr if err else sys.stdout
    stream.write(printable(text) + "\n")
    stream.flush()


def guarded(
    call: Callable[..., Any], *args: Any, passthrough: tuple[type[BaseException], ...] = (), **kwargs: Any
) -> Any:
    """Run a command so that no traceback reaches the user: a closed pipe (``catc solve |
    head``) stops quietly, input nesting too deeply is an input error, and anything else
    unexpected is a one-line internal-error report with exit 70 (``CATC_DEBUG=1`` shows
    the traceback).  ``passthrough`` exceptions (click's own) propagate unchanged."""
    from catgrammar import limits

    reraised: tuple[type[BaseException], ...] = (SystemExit, *passthrough)
    try:
        return call(*args, **kwargs)
    except reraised:
        raise
    except BrokenPipeError:  # stop quietly, as Unix tools do
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        sys.exit(EXIT_FAIL)
    except RecursionError:
        echo("catc: error: input nests too deeply to process", err=True)
        sys.exit(EXIT_INPUT)
    except KeyboardInterrupt:  # Ctrl-C (a query reports what it has: run_query)
        echo("catc: interrupted", err=True)
        sys.exit(ExitCode.INTERRUPTED)
    except MemoryError:
        out_of_memory(None, False)
    except limits.LimitExceeded as exc:
        limit_error(exc, False)
    except limits.Stopped as exc:  # the time limit, in a command with no partial answer
        if isinstance(exc, limits.Interrupted):
            echo("catc: interrupted", err=True)
            sys.exit(ExitCode.INTERRUPTED)
        from catc.interfaces.guard import time_limit_message

        echo(f"catc: error[{codes.TIME_LIMIT}]: {time_limit_message(exc.seconds, exc.phase)}", err=True)
        sys.exit(EXIT_UNKNOWN)
    except Exception as exc:  # a bug, reported without a traceback
        if guard.out_of_memory_error(exc):
            out_of_memory(None, False)
        if os.environ.get("CATC_DEBUG"):
            raise
        from catc.semantics.validate import ValidationFailure

        detail = (
            str(exc)
            if isinstance(exc, ValidationFailure)
            else f"{type(exc).__name__}: {exc} (set CATC_DEBUG=1 for details)"
        )
        echo(f"catc: internal error: {detail}", err=True)
        sys.exit(EXIT_INTERNAL)


# ====================================================================== errors


def input_errors(diags: Diagnostics, as_json: bool) -> NoReturn:
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


def argument_error(message: str, code: str, as_json: bool, location: str | None = None) -> NoReturn:
    """A bad command-line argument or input file found after parsing: ``catc: error[CODE]``
    (or ``FILE: error[CODE]``) and exit 2; with ``--json``, a catc.error/1 document."""
    from catgrammar.diagnostics import Diagnostics

    if as_json:
        diags = Diagnostics()
        diags.report(code, message, None)
        input_errors(diags, as_json)
    echo(f"{location or 'catc'}: error[{code}]: {message}", err=True)
    sys.exit(EXIT_INPUT)


# ====================================================================== loading


def search_path(extra: Sequence[str] = ()) -> tuple[str, ...]:
    """Where domains are looked for besides the problem's folder: ``--path`` folders, then
    the folders of the ``CATC_PATH`` environment variable (read here, at the edge)."""
    env = [p for p in os.environ.get("CATC_PATH", "").split(os.pathsep) if p]
    return (*extra, *env)


def stdlib_cache() -> Path | None:
    """Where the command line keeps checked standard-library domains between runs:
    ``$CATC_CACHE/stdlib``, else ``$XDG_CACHE_HOME/catc/stdlib``, else ``~/.cache/catc/stdlib``;
    ``CATC_CACHE=off`` keeps none (docs/cli.md)."""
    chosen = os.environ.get("CATC_CACHE", "")
    if chosen.lower() in ("off", "0", "no", "false"):
        return None
    if chosen:
        return Path(chosen) / "stdlib"
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "catc" / "stdlib"


def model_cache() -> Path | None:
    """Where the command line keeps checked models between runs: beside the standard
    library's (:func:`stdlib_cache`), in ``models``; none when that is off."""
    found = stdlib_cache()
    return None if found is None else found.parent / "models"


def instance(
    paths: Sequence[str], view: str | None, search_paths: Sequence[str], problem: str | None, as_json: bool
) -> ir.Instance:
    """PROBLEM or DOMAIN PROBLEM → the checked instance with its view applied, or exit 2
    with the diagnostics."""
    from catc.frontend.session import load_checked
    from catgrammar.diagnostics import Diagnostics

    if len(paths) not in (1, 2):
        argument_error("give PROBLEM or DOMAIN PROBLEM", codes.BAD_ARGUMENT, as_json)
    domain_path, problem_path = (None, paths[0]) if len(paths) == 1 else paths
    diags = Diagnostics()
    inst = load_checked(
        problem_path,
        domain_path,
        diags,
        view=view,
        problem_name=problem,
        search_paths=search_path(search_paths),
        stdlib_cache=stdlib_cache(),
        model_cache=model_cache(),
    )
    if inst is None:
        input_errors(diags, as_json)
    return inst


# ====================================================================== arguments


def convert(query: Query, inst: ir.Instance, raw: Mapping[str, Any]) -> dict[str, Any]:
    """The command line's values → the values the query takes (objective terms checked
    against the model, components looked up, weights read exactly, plan files read).
    Raises :class:`InputError`; objective terms with errors raise :class:`ObjectiveErrors`."""
    values = dict(raw)
    for option in query.options:
        value = raw.get(option.name)
        if value is None:
            continue
        if option.kind is Kind.SECONDS and not math.isfinite(value):
            raise InputError(f"{option.flags[0]} must be a finite number of seconds, got {value}", codes.BAD_ARGUMENT)
        if option.kind is Kind.OBJECTIVES:
            values[option.name] = objectives(inst, value) if value else None
            values["objective_source"] = list(value)  # their text, for a certificate (catc certify reads it)
        elif option.kind is Kind.COMPONENTS:
            values[option.name] = components(inst, value, option.none_word)
        elif option.kind is Kind.WEIGHTS:
            values[option.name] = weights(value) if value else None
        elif option.kind is Kind.PLAN_FILE:
            values[option.name] = read_plan_file(inst, value)
    stored = query.objective_texts(values) if query.objective_texts is not None else ()
    if stored:  # objective terms the query's input files carry: parsed here, as --minimize's
        values["objectives"] = objectives(inst, stored)
    return values


class ObjectiveErrors(Exception):
    def __init__(self, diags: Diagnostics) -> None:
        super().__init__("objective errors")
        self.diags = diags


def objectives(inst: ir.Instance, terms: Sequence[tuple[str, str]]) -> list[ir.Objective]:
    """``(sense, text)`` pairs in command-line order → checked objectives."""
    from catc import ir
    from catc.frontend.check import check_objective_text
    from catgrammar.diagnostics import Diagnostics

    diags = Diagnostics()
    out = []
    for sense, text in terms:
        term = check_objective_text(text, inst, diags, f"<--{sense}>")
        if term is not None:
            out.append(ir.Objective(ir.Sense(sense), term))
    if diags.has_errors:
        raise ObjectiveErrors(diags)
    return out


def components(inst: ir.Instance, text: str, none_word: str | None) -> list[str]:
    """``a,b c`` → morphism names, each one of the model's; ``none_word`` → no component."""
    if none_word is not None and text.strip().lower() == none_word:
        return []
    names = [c for c in text.replace(",", " ").split() if c]
    unknown = [n for n in names if n not in inst.morphisms]
    if unknown:
        from catgrammar.diagnostics import suggest

        said = [n + (f" (did you mean '{s}'?)" if (s := suggest(n, inst.morphisms)) else "") for n in unknown]
        raise InputError(f"unknown morphism(s) in the composition: {', '.join(said)}", codes.UNKNOWN_COMPONENT)
    return names


def weights(specs: Sequence[str]) -> dict[str, Fraction]:
    """``KEY=W`` specs → exact weights."""
    out: dict[str, Fraction] = {}
    for spec in specs:
        key, _, value = spec.partition("=")
        try:
            out[key] = Fraction(value)
        except (ValueError, ZeroDivisionError):
            raise InputError(f"--weights expects KEY=NUMBER, got {spec!r}", codes.BAD_WEIGHT) from None
    return out


class PlanFileError(Exception):
    def __init__(self, location: str, message: str, code: str) -> None:
        super().__init__(message)
        self.location, self.code = location, code


def read_plan_file(inst: ir.Instance, path: str) -> Any:
    """A ``catc.plan/1`` file → a Plan (unreadable: E0001; not JSON: E0801; not a plan: E0802)."""
    import json

    from catc.semantics.plan import PlanFormatError, read_plan

    try:
        with open(path, encoding="utf-8") as fh:
            doc = json.load(fh)
    except (OSError, UnicodeDecodeError) as exc:
        raise PlanFileError(path, f"cannot read the plan: {exc}", codes.UNREADABLE_FILE) from None
    except json.JSONDecodeError as exc:
        raise PlanFileError(f"{path}:{exc.lineno}:{exc.colno}", f"not JSON: {exc.msg}", codes.PLAN_NOT_JSON) from None
    except ValueError as exc:  # a JSON integer of more digits than Python reads
        raise PlanFileError(path, f"cannot read the plan: {exc}", codes.BAD_PLAN) from None
    try:
        return read_plan(inst, doc)
    except PlanFormatError as exc:
        raise PlanFileError(path, str(exc), codes.BAD_PLAN) from None


# ====================================================================== output


def console(as_json: bool = False) -> Any:
    """Rich on a terminal; plain aligned text when piped (no colour codes, faster start)."""
    from catc.present.console import PlainConsole, TerminalConsole

    if sys.stdout.isatty() and not os.environ.get("NO_COLOR"):
        from rich.console import Console

        return TerminalConsole(Console(highlight=False, emoji=False))
    return PlainConsole(echo)


class LineStatus:
    """The status line where standard error is not a terminal (``--progress``): each
    update is written as a line of its own (a log keeps every one)."""

    def update(self, renderable: Any) -> None:
        text = renderable.__rich__().plain if hasattr(renderable, "__rich__") else str(renderable)
        echo(f"catc: {text}", err=True)


class ThrottledStatus:
    """Where standard error is not a terminal and no ``--progress`` was asked (a pipe, a CI
    log): nothing for the first :attr:`QUIET` seconds, so a quick answer prints only itself;
    then what the query is doing, one line every :attr:`EVERY` seconds, so a long run is not
    silent for minutes."""

    QUIET = 10.0
    EVERY = 30.0

    def __init__(self) -> None:
        import threading
        import time

        self._message = "working"
        self._start = time.monotonic()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._tick, name="catc-progress", daemon=True)

    def update(self, renderable: Any) -> None:
        self._message = getattr(renderable, "message", None) or str(renderable)

    def _tick(self) -> None:
        import time

        wait = self.QUIET
        while not self._stop.wait(wait):
            echo(f"catc: {self._message} ({time.monotonic() - self._start:.0f} s)", err=True)
            wait = self.EVERY

    def __enter__(self) -> ThrottledStatus:
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join()


def progress(enabled: bool, forced: bool = False) -> Any:
    """A rich status line on a terminal (stderr), showing what the query is doing;
    ``forced`` (``--progress``): also when standard error is not a terminal (a line per
    update) and with ``--json``; otherwise, off a terminal, a line every half minute once
    the query has run ten seconds (:class:`ThrottledStatus`)."""
    import contextlib

    if not (enabled or forced):
        return contextlib.nullcontext(None)
    if not sys.stderr.isatty():
        return contextlib.nullcontext(LineStatus()) if forced else ThrottledStatus()
    from rich.console import Console

    return Console(stderr=True).status("solving…")


def reporter(status: Any) -> Callable[[str], None] | None:
    """A ``progress(message)`` callback for a query, showing ``message`` on the status line
    with the time since the query started, kept current while the solver works (rich
    redraws the line from its own thread); None without a status line."""
    if status is None:
        return None
    if isinstance(status, ThrottledStatus):  # plain text: off a terminal nothing needs rich
        return status.update
    import time

    from rich.text import Text

    start = time.perf_counter()

    class Live:
        def __init__(self, message: str) -> None:
            self.message = message

        def __rich__(self) -> Text:
            return Text(f"{self.message} ({time.perf_counter() - start:.1f} s)")

    return lambda message: status.update(Live(message))


# ====================================================================== a query command


def run_query(name: str, paths: Sequence[str], raw: Mapping[str, Any]) -> NoReturn:
    """``catc NAME PATHS [options]``: load, check the arguments, answer, print, exit with
    the answer's exit code (130 when interrupted).  ``raw`` holds every option's value as the
    command line gives it (see :func:`convert`).  The limits (``--limit``, ``--memory``,
    ``CATC_LIMIT_*``) and the time limit (``--timeout``) hold from loading to printing."""
    from catc.queries import registry
    from catgrammar import limits

    query = registry.get(name)
    values = {**query.defaults(), **raw}
    as_json = bool(values.get("as_json"))
    timeout = values.get("timeout")
    if timeout is not None and not math.isfinite(timeout):
        argument_error(f"--timeout must be a finite number of seconds, got {timeout}", codes.BAD_ARGUMENT, as_json)
    found = command_limits(values.get("limits") or (), values.get("memory"), as_json)
    with limits.using(found), limits.deadline(timeout) as clock, guard.stoppable(clock) as run:
        run.as_json = as_json
        try:
            code = _answer(query, paths, values, as_json, run)
        except KeyboardInterrupt:
            code = guard.stopped_exit(run, as_json, echo)
        except limits.TimeLimitReached as exc:  # reading the model, before the query could answer
            code = guard.time_limit_exit(guard.time_limit_message(exc.seconds, exc.phase), as_json, echo)
        except (MemoryError, SystemError) as exc:
            if not guard.out_of_memory_error(exc):
                raise
            out_of_memory(clock.root.phase, as_json)
        except limits.LimitExceeded as exc:
            limit_error(exc, as_json)
    sys.exit(code)


def command_limits(specs: Sequence[str], memory: int | None, as_json: bool, cap_memory: bool = True) -> Any:
    """The limits of this command (E1111 when malformed), with the process's memory capped
    (``cap_memory``: the commands that take ``--memory``)."""
    try:
        found = guard.command_limits(specs, memory)
    except guard.LimitArgumentError as exc:
        argument_error(str(exc), exc.code, as_json)
    if cap_memory:
        guard.limit_memory(found.memory, as_json)
    return found


def out_of_memory(phase: str | None, as_json: bool) -> NoReturn:
    """E1110, exit 3: the memory limit was reached."""
    try:
        guard.release_reserve()  # room to write the report
        message = guard.out_of_memory_message(phase)
        if as_json:  # with its "reason", as every unknown answer (issue 28)
            echo(guard.stopped_document(codes.OUT_OF_MEMORY, message))
        echo(f"catc: error[{codes.OUT_OF_MEMORY}]: {message}", err=True)
    except MemoryError:  # not even that: the report prepared beforehand, without Python's help
        guard.last_words()
    sys.exit(EXIT_UNKNOWN)


def limit_error(exc: Any, as_json: bool) -> NoReturn:
    """A limit crossed after loading (the horizon, a universe, an export): located, exit 2."""
    from catgrammar.diagnostics import Diagnostics

    if exc.span is None:  # a command-line argument (--horizon)
        argument_error(exc.message, exc.code, as_json)
    from catgrammar.parser import read_source

    diags = Diagnostics()
    read_source(exc.span.file, diags)  # for the excerpt
    diags.report(exc.code, exc.message, exc.span)
    input_errors(diags, as_json)


def _answer(query: Query, paths: Sequence[str], values: dict[str, Any], as_json: bool, run: Any) -> int:
    """Load, convert the arguments, answer and print; the exit code."""
    from catgrammar import limits

    limits.note_phase("reading the model")
    inst = instance(paths, values.get("view"), values.get("search_paths") or (), values.get("problem_name"), as_json)
    try:
        values = convert(query, inst, values)
        why = query.check(inst, values) if query.check is not None else None
        if why is not None:
            raise InputError(why, codes.NOT_APPLICABLE)
    except ObjectiveErrors as exc:
        input_errors(exc.diags, as_json)
    except PlanFileError as exc:
        argument_error(str(exc), exc.code, as_json, location=exc.location)
    except InputError as exc:
        argument_error(str(exc), exc.code, as_json)
    kwargs = query.run_options(values)
    with progress(query.progress and not as_json, bool(values.get("show_progress"))) as status:
        if query.progress:
            kwargs["progress"] = reporter(status)
        run.soft = True  # from here a first Ctrl-C asks the query to stop and say what it has
        result = query.run(inst, **kwargs)
    try:
        messages = query.artifacts(inst, result, values)
        if values.get("certificate"):  # the certificate module loads only when asked
            from catc.queries.registry import certificate_artifact

            messages = [*messages, certificate_artifact(inst, result, values)]
    except InputError as exc:
        argument_error(str(exc), exc.code, as_json)
    if as_json:
        import json

        echo(json.dumps(query.to_json(inst, result), indent=2))
    else:
        query.render(console(), inst, result, values)
        for message in messages:
            echo(message, err=True)
    return ExitCode.INTERRUPTED if limits.interrupted() else result.exit_code
