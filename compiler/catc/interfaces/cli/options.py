"""The click commands of the queries: one per query of :mod:`catc.queries.registry`, built
from its options (the targets' commands are built from the same option kinds:
:func:`click_params`), and ``--limit``/``--memory`` for the commands written out."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import click

from catc.interfaces import command
from catc.queries.base import Kind, Option, Query

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
    Kind.OUTPUT_FOLDER: click.Path(file_okay=False),
    Kind.INPUT_FILE: click.Path(dir_okay=False),
    Kind.FILE_PAIR: click.Path(),  # files, or (ground --diff) grounding folders
}


def click_params(option: Option) -> list[click.Parameter]:
    """The click parameters of one query option (``--minimize``/``--maximize``: two)."""
    kind, flags, name = option.kind, list(option.flags), option.name
    if kind in (Kind.PLAN_FILE, Kind.DOCUMENT_FILE):
        return [click.Argument([name], metavar=option.flags[0], type=click.Path(dir_okay=False))]
    if kind is Kind.OBJECTIVES:
        helps = option.help.split("\n")
        return [
            click.Option([flag, f"{flag[2:]}_terms"], multiple=True, metavar=option.metavar, help=text)
            for flag, text in zip(option.flags, helps)
        ]
    extra: dict[str, Any] = {"help": option.help or None}
    if option.required:
        extra["required"] = True
    if kind is Kind.FLAG:
        extra.update(is_flag=True, default=False)
    elif kind is Kind.NO_FLAG:
        extra.update(is_flag=True, flag_value=False, default=True)
    elif kind is Kind.CHOICE:
        extra.update(type=click.Choice(list(option.choices)), default=option.default, show_default=option.show_default)
    elif kind is Kind.FILE_PAIR:
        extra.update(nargs=2, type=_TYPES[kind], metavar=option.metavar)
    elif kind in (Kind.TEXTS, Kind.FOLDERS, Kind.WEIGHTS):
        extra.update(multiple=True, metavar=option.metavar)
        if kind in _TYPES:
            extra["type"] = _TYPES[kind]
    else:
        extra.update(metavar=option.metavar, type=_TYPES.get(kind))
        if option.default is not None:
            extra.update(default=option.default, show_default=option.show_default)
    return [click.Option([*flags, name], **extra)]


def option(option: Option) -> Callable[[Any], Any]:
    """A decorator adding the click parameters of ``option`` to a command written out."""

    def decorate(f: Any) -> Any:
        if not hasattr(f, "__click_params__"):
            f.__click_params__ = []
        f.__click_params__.extend(click_params(option))
        return f

    return decorate


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
