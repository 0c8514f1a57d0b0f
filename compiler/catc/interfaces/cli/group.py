"""The ``catc`` group: every query of :mod:`catc.queries.registry` and every target of
:mod:`catc.targets.registry` is a command built from its options (:mod:`.options`,
:mod:`.targets`); the other commands live in their own modules (:data:`LAZY_COMMANDS`).
Commands load on first use (start-up time)."""

from __future__ import annotations

import importlib
from typing import Any

import click

from catc import __version__
from catc.interfaces import command
from catc.queries import registry

#: Commands defined in their own modules, imported only when used (start-up time):
#: name → "module:attribute" of a click command.
LAZY_COMMANDS: dict[str, str] = {
    "check": "catc.interfaces.cli.check:check",
    "fmt": "catc.interfaces.fmt_command:fmt_command",
    "lsp": "catc.interfaces.lsp:lsp_command",
    "bench": "catc.bench.cli:bench_command",
    "init": "catc.interfaces.conveniences:init_command",
    "explain": "catc.interfaces.conveniences:explain_command",
    "import": "catc.interfaces.import_cli:import_command",
}


class _Group(click.Group):
    """Usage errors exit 2 (click's default); unexpected exceptions become a one-line
    internal-error report with exit 70 instead of a traceback (set CATC_DEBUG=1 to see it).
    Query and target commands and those in :data:`LAZY_COMMANDS` are made on first use."""

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
        from catc.interfaces.cli.targets import target_words

        lazy = {n for n in LAZY_COMMANDS if self._lazy(n) is not None}
        return sorted(set(super().list_commands(ctx)) | lazy | set(registry.names()) | target_words())

    def get_command(self, ctx: click.Context, name: str) -> click.Command | None:
        found = super().get_command(ctx, name)
        if found is not None:
            return found
        if name in registry.QUERIES:
            from catc.interfaces.cli.options import query_command

            return query_command(registry.get(name))
        lazy = self._lazy(name)
        if lazy is not None:
            return lazy
        from catc.interfaces.cli.targets import target_group_command

        return target_group_command(name)

    @staticmethod
    def _lazy(name: str) -> click.Command | None:
        target = LAZY_COMMANDS.get(name)
        if target is None:
            return None
        module, _, attr = target.partition(":")
        try:
            found: click.Command = getattr(importlib.import_module(module), attr)
        except ImportError:  # the command's module is not there (yet); optional extras report themselves
            return None
        return found

    def invoke(self, ctx: click.Context) -> Any:
        return command.guarded(
            self._invoke_limited, ctx, passthrough=(click.exceptions.Exit, click.exceptions.Abort, click.ClickException)
        )

    def _invoke_limited(self, ctx: click.Context) -> Any:
        """Every command runs under the limits of the environment (``CATC_LIMIT_*``); those
        with ``--limit``/``--memory`` refine them and cap the process's memory (:func:`limited`;
        ``bench``, ``fmt`` and ``lsp`` leave their process as it is)."""
        from catgrammar import limits

        with limits.using(command.command_limits((), None, False, cap_memory=False)):
            return super().invoke(ctx)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="catc")
def main() -> None:
    """catc — compile .cat robot-recomposition models and answer lifecycle queries."""
