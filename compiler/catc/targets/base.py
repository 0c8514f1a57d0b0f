"""What every target is made of: the :class:`Target` record that the command line, the Python
API, the language server and the generated docs read — as :mod:`catc.queries.base` is for
the queries.

A target module turns a checked instance into something another tool reads (PDDL files,
SMT-LIB2 text, the artifacts a robot runs) and defines one ``TARGET = Target(...)`` naming
its options, its ``run``, its JSON document, its text and the files it writes;
:mod:`catc.targets.registry` lists the modules.  Nothing else needs to change to add a
target: the command line builds its command from the options (``catc export NAME`` unless
``command`` says otherwise), the API answers ``model.export(NAME)``, the language server
``catc.export.NAME``.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

from catc import ir
from catc.queries.base import InputError, Kind, Operation, Option, limit_options, load_options
from catgrammar.record import Record, set_field

#: ``echo(text, err)``: how a target's follow-up (:attr:`Target.follow`) prints a line.
Echo = Callable[[str, bool], None]


class OptionError(ValueError):
    """An option's value is malformed (the command line reports it as a bad value of
    ``flag``, exit 2, before anything is loaded)."""

    def __init__(self, message: str, flag: str) -> None:
        super().__init__(message)
        self.flag = flag


def horizon_option(help: str) -> Option:
    return Option("horizon", ("--horizon", "-k"), Kind.COUNT, help)


def no_files(inst: ir.Instance, artifact: Any, options: Mapping[str, Any]) -> list[str]:
    return []


class Target(Operation, Record):
    """A target as every interface sees it.

    ``run(instance, **options)`` makes the artifact (``options``: those with ``use=Use.RUN``;
    :class:`InputError` when the model cannot be expressed); ``to_json(instance, artifact)``
    is its JSON document (the API's and the language server's answer); ``render(instance,
    artifact)`` its text (printed when no output file is named); ``write(instance, artifact,
    options)`` writes the files the output options name and returns the lines to print;
    ``follow(instance, artifact, options, echo)``, when given, runs after writing (check the
    files with other tools, run a planner on them) and returns the exit code.
    ``prepare(options)`` reads the options before loading (:class:`OptionError` for a bad
    value).  ``layout(artifact, lay_out)``, when given, is the artifact with its ``.cat``
    texts laid out by ``lay_out`` — the front end's formatter, which no target may import:
    every interface applies it right after ``run`` (``catc.interfaces.layout``).  ``command``: the command-line words (default ``("export", name)``); ``schema``:
    the JSON document's (default ``catc.export-NAME/1``)."""

    __slots__ = (
        "name",
        "command",
        "summary",
        "description",
        "options",
        "run",
        "to_json",
        "render",
        "write",
        "follow",
        "prepare",
        "layout",
        "schema",
    )
    name: str
    command: tuple[str, ...]
    summary: str
    description: str
    options: tuple[Option, ...]
    run: Callable[..., Any]
    to_json: Callable[[ir.Instance, Any], dict]
    render: Callable[[ir.Instance, Any], str]
    write: Callable[[ir.Instance, Any, Mapping[str, Any]], list[str]]
    follow: Callable[[ir.Instance, Any, Mapping[str, Any], Echo], int] | None
    prepare: Callable[[dict[str, Any]], None] | None
    layout: Callable[[Any, Callable[[str], str]], Any] | None
    schema: str

    def __init__(
        self,
        name: str,
        *,
        summary: str,
        description: str,
        options: tuple[Option, ...],
        run: Callable[..., Any],
        to_json: Callable[[ir.Instance, Any], dict],
        render: Callable[[ir.Instance, Any], str],
        write: Callable[[ir.Instance, Any, Mapping[str, Any]], list[str]] = no_files,
        follow: Callable[[ir.Instance, Any, Mapping[str, Any], Echo], int] | None = None,
        prepare: Callable[[dict[str, Any]], None] | None = None,
        layout: Callable[[Any, Callable[[str], str]], Any] | None = None,
        command: tuple[str, ...] | None = None,
        schema: str | None = None,
    ) -> None:
        set_field(self, "name", name)
        set_field(self, "command", ("export", name) if command is None else command)
        set_field(self, "summary", summary)
        set_field(self, "description", description)
        set_field(self, "options", options + limit_options())
        set_field(self, "run", run)
        set_field(self, "to_json", to_json)
        set_field(self, "render", render)
        set_field(self, "write", write)
        set_field(self, "follow", follow)
        set_field(self, "prepare", prepare)
        set_field(self, "layout", layout)
        set_field(self, "schema", schema or f"catc.export-{name}/1")


__all__ = ["Echo", "InputError", "OptionError", "Target", "horizon_option", "load_options", "no_files"]
