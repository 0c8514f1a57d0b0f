"""The click commands of the targets (:mod:`catc.targets.registry`): ``catc export NAME``
for each target, or the words its ``command`` names (``catc compile`` for smt2, ``catc
ground``), built from its options, and the one route every target takes (:func:`run_target`):
read the options, load, run, then print the JSON document, write the files or print the text,
then the target's follow-up.  A target may name a command-line route of its own in
:data:`ROUTES` (``ground``: its ``--diff`` mode)."""

from __future__ import annotations

import importlib
import json
import math
from collections.abc import Mapping, Sequence
from typing import Any

import click

from catc.interfaces import command
from catc.interfaces.cli.options import click_params, limited
from catc.interfaces.layout import export
from catc.queries.base import InputError, Kind
from catc.targets import registry
from catc.targets.base import OptionError, Target
from catgrammar import codes

#: Targets whose command line does more than :func:`run_target`: name → "module:function"
#: taking (target, paths, values).
ROUTES: dict[str, str] = {"ground": "catc.interfaces.cli.ground:run_ground"}

#: The help of a group of targets (``catc export``).
GROUPS: dict[str, str] = {"export": "Export a model to other planners' formats (docs/export.md)."}


def _targets() -> list[Target]:
    return [registry.get(name) for name in registry.names()]


def target_words() -> set[str]:
    """The top-level command words of the targets (``export``, ``compile``, ``ground``)."""
    return {t.command[0] for t in _targets() if t.command}


def target_group_command(word: str) -> click.Command | None:
    """The command ``catc WORD``: a target's own command, or the group of the targets
    spelled ``WORD NAME``."""
    for target in _targets():
        if target.command == (word,):
            return target_command(target, word)
    if any(len(t.command) == 2 and t.command[0] == word for t in _targets()):
        return _TargetGroup(word, help=GROUPS.get(word, f"The {word} targets."))
    return None


class _TargetGroup(click.Group):
    """``catc export``: one subcommand per target spelled ``export NAME``."""

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        """Each command's first sentence whole (click cuts it at the terminal's width: "print...")."""
        rows = []
        for name in self.list_commands(ctx):
            cmd = self.get_command(ctx, name)
            if cmd is not None and not cmd.hidden:
                rows.append((name, cmd.get_short_help_str(limit=1000)))
        if rows:
            with formatter.section("Commands"):
                formatter.write_dl(rows)

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted(t.command[1] for t in _targets() if len(t.command) == 2 and t.command[0] == self.name)

    def get_command(self, ctx: click.Context, name: str) -> click.Command | None:
        target = registry.by_command((str(self.name), name))
        return None if target is None else target_command(target, name)


def target_command(target: Target, name: str) -> click.Command:
    """The click command of ``target``: ``PATHS`` (PROBLEM or DOMAIN PROBLEM), then its options."""
    # ground --diff of two groundings needs no model: its route checks the paths itself
    optional = target.name in ROUTES
    params: list[click.Parameter] = [click.Argument(["paths"], nargs=-1, required=not optional, type=click.Path())]
    for option in target.options:
        params.extend(click_params(option))

    def callback(paths: tuple[str, ...], **values: Any) -> None:
        route = ROUTES.get(target.name)
        if route is None:
            run_target(target, paths, values)
            return
        module, _, attr = route.partition(":")
        getattr(importlib.import_module(module), attr)(target, paths, values)

    return click.Command(name, params=params, callback=callback, help=f"{target.summary}\n\n{target.description}")


def prepared(target: Target, paths: Sequence[str], values: dict[str, Any]) -> bool:
    """Read the options before anything is loaded: the target's own reading (a bad value is
    a usage error), the number of paths, a finite timeout.  Returns ``--json``."""
    as_json = bool(values.get("as_json"))
    if target.prepare is not None:
        try:
            target.prepare(values)
        except OptionError as exc:
            raise click.BadParameter(str(exc), param_hint=exc.flag) from None
        except InputError as exc:  # e.g. a checker the options need is not installed
            command.argument_error(str(exc), exc.code, as_json)
    if len(paths) not in (1, 2):
        raise click.UsageError("give PROBLEM or DOMAIN PROBLEM")
    timeout = values.get("timeout")
    if timeout is not None and not math.isfinite(timeout):
        command.argument_error(
            f"--timeout must be a finite number of seconds, got {timeout}", codes.BAD_ARGUMENT, as_json
        )
    return as_json


def echo(text: str, err: bool = False) -> None:
    click.echo(text, err=err)


def run_target(target: Target, paths: Sequence[str], values: dict[str, Any]) -> None:
    """Load, run the target, and print its JSON (``--json``), write its files (an output
    option given) or print its text; then its follow-up decides the exit code."""
    from catgrammar import limits

    as_json = prepared(target, paths, values)
    output = next((o.name for o in target.options if o.kind in (Kind.OUTPUT_FILE, Kind.OUTPUT_FOLDER)), None)
    try:
        with limited(values.get("limits") or (), values.get("memory")), limits.deadline(values.get("timeout")):
            inst = loaded(paths, values, as_json)
            artifact = export(target, inst, target.run_options(values))
            if as_json:
                command.echo(json.dumps(target.to_json(inst, artifact), indent=2))
                return
            if output is not None and values.get(output):
                for line in target.write(inst, artifact, values):
                    echo(line)
            else:
                click.echo(target.render(inst, artifact), nl=False)
            code = target.follow(inst, artifact, values, echo) if target.follow is not None else 0
    except InputError as exc:
        command.argument_error(str(exc), exc.code, as_json)
    if code:
        raise SystemExit(code)


def loaded(paths: Sequence[str], values: Mapping[str, Any], as_json: bool) -> Any:
    """The checked instance of ``paths`` with the load options (``--view``, ``--path``,
    ``--problem``) applied, or exit 2 with the diagnostics."""
    return command.instance(
        paths, values.get("view"), values.get("search_paths") or (), values.get("problem_name"), as_json
    )


__all__ = ["ROUTES", "prepared", "run_target", "target_command", "target_group_command", "target_words"]
