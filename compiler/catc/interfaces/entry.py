"""The ``catc`` executable (and ``python -m catc``).

A plain query command line (``catc solve ...``, ``catc optimize ...``, ...) runs without
importing click.  Importing click costs about 20 ms, as much as everything else catc imports
and a fifth of a small solve's whole run; the start-up target (within 1.2× of a hand-written
Z3 script, docs/benchmarks.md) cannot be met with it.  So :func:`parse_query` reads the
common forms of a query's options itself, from the same option table the click command is
built from, and hands anything else — help, an unknown or malformed option, a value click
would reject or might read differently, options whose values click checks against the
file system (``--path``, ``--diagram``, ``--plot``), objective terms, ``--`` —
to the click command line in :mod:`catc.interfaces.cli`, which then parses it as always.
Whatever it accepts, it reads exactly as click does (a property test compares the two on
generated command lines), and both routes run the same :func:`catc.interfaces.command.run_query`.
A plain ``catc check`` is run by :mod:`catc.interfaces.check_command`, also without click.
"""

from __future__ import annotations

import gc
import os
import sys
from typing import Any

from catc.queries.base import Kind, Option, Query

#: Kinds read here; an option of any other kind leaves the command line to click.
_READ = {
    Kind.FLAG,
    Kind.NO_FLAG,
    Kind.COUNT,
    Kind.POSITIVE,
    Kind.SECONDS,
    Kind.NAME,
    Kind.CHOICE,
    Kind.TEXTS,
    Kind.COMPONENTS,
    Kind.WEIGHTS,
}
_REPEATED = {Kind.TEXTS, Kind.WEIGHTS}


def _digits(text: str) -> bool:
    return text.isascii() and text.isdigit()


def _convert(option: Option, value: str) -> object | None:
    """The parameter value of ``value``, or None to leave it to click."""
    kind = option.kind
    if kind in (Kind.COUNT, Kind.POSITIVE):
        if not _digits(value):
            return None
        n = int(value)
        return n if kind is Kind.COUNT or n >= 1 else None
    if kind is Kind.SECONDS:
        whole, dot, fraction = value.partition(".")
        if not _digits(whole) or (dot and not _digits(fraction)):
            return None
        seconds = float(value)  # as click's FloatRange converts it
        return seconds if seconds > 0 else None
    if kind is Kind.CHOICE:
        return value if value in option.choices else None
    return value if value and not value.startswith("-") else None  # a word


def parse_query(query: Query, args: list[str]) -> dict[str, Any] | None:
    """The parameters of ``catc QUERY ARGS`` as click would pass them to the command, or
    None when the arguments are not of the plain forms read here (click then reads them)."""
    table = {flag: option for option in query.options for flag in option.flags if flag.startswith("-")}
    params: dict[str, Any] = {o.name: o.default for o in query.options}
    paths: list[str] = []
    rest = iter(args)
    for arg in rest:
        if not arg.startswith("-"):
            paths.append(arg)
            continue
        if arg.startswith("--"):
            name, equals, attached = arg.partition("=")
        else:  # a short option, its value possibly attached: -k3
            name, equals, attached = arg[:2], "", arg[2:]
        option = table.get(name)
        if option is None or option.kind not in _READ:
            return None
        if option.kind in (Kind.FLAG, Kind.NO_FLAG):
            if equals or attached:
                return None
            params[option.name] = option.kind is Kind.FLAG
            continue
        value = attached if equals or attached else next(rest, None)
        converted = None if value is None else _convert(option, value)
        if converted is None:
            return None
        if option.kind in _REPEATED:
            params[option.name] = (*(params[option.name] or ()), converted)
        else:
            params[option.name] = converted
    for option in query.options:
        if option.kind in (
            Kind.PLAN_FILE,
            Kind.DOCUMENT_FILE,
        ):  # the last word, as click gives it (a file, not a folder)
            if len(paths) not in (2, 3) or not paths[-1] or os.path.isdir(paths[-1]):
                return None
            params[option.name] = paths.pop()
    if len(paths) not in (1, 2):
        return None
    params["paths"] = tuple(paths)
    return params


#: The cyclic collector's first threshold for a catc process.  The front end allocates many
#: small objects and keeps them (the AST, then the IR), so with the default (700) the
#: collector rescans the growing, cycle-free structure again and again: parse + check of a
#: 20,000-morphism domain took 10.7 s with it and 7.0 s with this (measured by hand).  It is
#: a setting of the whole process, so only the executable makes it — never the library,
#: which the language server, the runtime and programs share with their own threads.
GC_THRESHOLD = 100_000


def configure_process() -> None:
    """What the ``catc`` executable sets for its own process (see :data:`GC_THRESHOLD`); it
    also makes the process-wide settings of the limits (:class:`catc.interfaces.guard.Process`)."""
    _, second, third = gc.get_threshold()
    gc.set_threshold(GC_THRESHOLD, second, third)
    from catc.interfaces.guard import Process

    Process.executable = True


def main(argv: list[str] | None = None) -> None:
    """Run ``catc`` with ``argv`` (default: the process's arguments); exits."""
    if argv is None:
        configure_process()
        from catc.interfaces import guard

        try:
            _main(argv)
        except MemoryError:  # at the memory limit, even the E1110 report ran out (exit 3)
            guard.last_words()
        except SystemExit as exc:
            leave(exc.code)
            raise
    else:
        _main(argv)


def leave(code: object) -> None:
    """End the ``catc`` process now with exit status ``code`` (an ``int`` or None, as
    ``sys.exit`` takes), skipping the interpreter's teardown of its modules and objects: the
    answer is printed, and that teardown cost a plain ``catc solve`` ~25 ms of CPU, about
    twice what it costs a hand-written Z3 script (docs/benchmarks.md, issue 23).  What an
    exit must still do is done first: the ``atexit`` functions run and standard output and
    error are flushed.  Returns (and the process ends as usual) when it cannot be sure:
    another thread still runs, the status is a message, or a stream cannot be flushed
    (a closed pipe: Python then reports it as it always does)."""
    import atexit

    status = 0 if code is None else code
    if not isinstance(status, int) or not 0 <= status <= 255:
        return
    threading = sys.modules.get("threading")
    if threading is not None and threading.active_count() > 1:
        return
    run_exit_functions = getattr(atexit, "_run_exitfuncs", None)
    if run_exit_functions is None:  # not CPython
        return
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except BaseException:  # left to the interpreter's own exit
        return
    run_exit_functions()
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except BaseException:
        return
    os._exit(status)


def _main(argv: list[str] | None) -> None:
    args = sys.argv[1:] if argv is None else list(argv)
    from catc.queries import registry

    if args[:1] == ["check"]:
        from catc.interfaces import check_command

        found = check_command.parse_check(args[1:])
        if found is not None:
            from catc.interfaces import command

            try:
                command.guarded(check_command.run_check, **found)
            except KeyboardInterrupt:  # Ctrl-C before the command could take it (exit 130)
                command.echo("catc: interrupted", err=True)
                sys.exit(command.ExitCode.INTERRUPTED)
    if args and args[0] in registry.QUERIES:
        params = parse_query(registry.get(args[0]), args[1:])
        if params is not None:
            from catc.interfaces import command

            paths = params.pop("paths")
            try:
                command.guarded(command.run_query, args[0], paths, params)
            except KeyboardInterrupt:  # Ctrl-C before the command could take it (exit 130)
                command.echo("catc: interrupted", err=True)
                sys.exit(command.ExitCode.INTERRUPTED)
    from catc.interfaces.cli import main as cli

    try:  # the name and variable of shell completion (docs/cli.md) whether run as catc or python -m catc
        if argv is None:
            cli(prog_name="catc", complete_var="_CATC_COMPLETE")
        else:
            cli(args, prog_name="catc", complete_var="_CATC_COMPLETE")
    except KeyboardInterrupt:  # pragma: no cover - click turns it into Abort; guarded() exits 130 first
        sys.stderr.write("catc: interrupted\n")
        sys.exit(130)
