"""The ``catc`` executable (and ``python -m catc``).

A plain ``catc solve`` command line runs without importing click.  Importing click costs
about 20 ms, as much as everything else catc imports and a fifth of a small solve's whole
run; the issue's start-up target (within 1.3× of a hand-written Z3 script, docs/benchmarks.md)
cannot be met with it.  So :func:`parse_solve` reads the common forms of ``catc solve``
arguments itself and hands anything else — help, an unknown or malformed option, a value
click would reject or might read differently, ``--path``, ``--diagram``, ``--`` — to the
click command line in :mod:`catc.interfaces.cli`, which then parses it as always.  Whatever it
accepts, it reads exactly as click does (a property test compares the two on generated
command lines), and both routes run the same :func:`catc.interfaces.command.solve`.
"""

from __future__ import annotations

import sys

#: The ``catc solve`` options read here: option → (parameter, kind).  A kind is ``flag``,
#: ``count`` (a whole number ≥ 0), ``seconds`` (a decimal number > 0), ``name`` (text
#: not starting with ``-``) or a tuple of choices.
SOLVE_OPTIONS: dict[str, tuple[str, object]] = {
    "--horizon": ("horizon", "count"),
    "-k": ("horizon", "count"),
    "--view": ("view", "name"),
    "--sequential": ("sequential", "flag"),
    "--problem": ("problem_name", "name"),
    "--timeout": ("timeout", "seconds"),
    "--strategy": ("strategy", ("incremental", "single")),
    "--json": ("as_json", "flag"),
    "--no-prune": ("no_prune", "flag"),
}

#: Every parameter of ``catc solve`` with click's default.
SOLVE_DEFAULTS: dict[str, object] = {
    "horizon": None,
    "view": None,
    "sequential": False,
    "search_paths": (),
    "problem_name": None,
    "timeout": None,
    "strategy": "incremental",
    "as_json": False,
    "diagram": None,
    "no_prune": False,
}


def _digits(text: str) -> bool:
    return text.isascii() and text.isdigit()


def _convert(kind: object, value: str) -> object | None:
    """The parameter value of ``value``, or None to leave it to click."""
    if kind == "count":
        return int(value) if _digits(value) else None
    if kind == "seconds":
        whole, dot, fraction = value.partition(".")
        if not _digits(whole) or (dot and not _digits(fraction)):
            return None
        seconds = float(value)  # as click's FloatRange converts it
        return seconds if seconds > 0 else None
    if kind == "name":
        return value if value and not value.startswith("-") else None
    return value if value in kind else None  # type: ignore[operator] - a tuple of choices


def parse_solve(args: list[str]) -> dict[str, object] | None:
    """The parameters of ``catc solve ARGS`` as click would pass them to the command, or
    None when the arguments are not of the plain forms read here (click then reads them)."""
    params = dict(SOLVE_DEFAULTS)
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
        spec = SOLVE_OPTIONS.get(name)
        if spec is None:
            return None
        dest, kind = spec
        if kind == "flag":
            if equals or attached:
                return None
            params[dest] = True
            continue
        value = attached if equals or attached else next(rest, None)
        converted = None if value is None else _convert(kind, value)
        if converted is None:
            return None
        params[dest] = converted
    if len(paths) not in (1, 2):
        return None
    params["paths"] = tuple(paths)
    return params


def main(argv: list[str] | None = None) -> None:
    """Run ``catc`` with ``argv`` (default: the process's arguments); exits."""
    args = sys.argv[1:] if argv is None else list(argv)
    params = parse_solve(args[1:]) if args[:1] == ["solve"] else None
    if params is not None:
        from catc.interfaces import command

        try:
            command.guarded(command.solve, **params)
        except KeyboardInterrupt:  # as click reports it
            command.echo(err=True)
            command.echo("Aborted!", err=True)
            sys.exit(command.EXIT_FAIL)
    from catc.interfaces.cli import main as cli

    if argv is None:
        cli()
    else:
        cli(args)
