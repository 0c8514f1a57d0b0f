"""Where human output goes: a plain console for pipes and files, and tables that render as
aligned text or as rich tables on a terminal.

Everything a query prints goes through ``console.print`` with rich's markup
(``[bold]...[/]``); :class:`PlainConsole` strips the markup, so piped output has no colour
codes and does not import rich (start-up time).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any, Protocol

_MARKUP = re.compile(r"\[/?[a-z ]*\]")


class Console(Protocol):
    def print(self, obj: object = "") -> None: ...


class PlainConsole:
    """The subset of rich's Console used here, printing plain aligned text."""

    def __init__(self, write: Callable[[str], None]) -> None:
        self.write = write

    def print(self, obj: object = "") -> None:
        if isinstance(obj, Table):
            self.write(obj.render())
        else:
            self.write(_MARKUP.sub("", str(obj)))


class Table:
    """A minimal table that renders as aligned columns, or converts to a rich Table."""

    def __init__(self, *columns: str, right: tuple[int, ...] = ()) -> None:
        self.columns = columns
        self.right = right
        self.rows: list[tuple[str, ...]] = []

    def add_row(self, *cells: str) -> None:
        self.rows.append(cells)

    def render(self) -> str:
        widths = [max(len(r[i]) for r in [self.columns, *self.rows]) for i in range(len(self.columns))]
        out = []
        for row in [self.columns, *self.rows]:
            cells = [c.rjust(w) if i in self.right else c.ljust(w) for i, (c, w) in enumerate(zip(row, widths))]
            out.append("  ".join(cells).rstrip())
        return "\n".join(out)

    def __rich__(self) -> Any:
        from rich.table import Table as RichTable

        table = RichTable(show_header=True, header_style="bold", box=None, pad_edge=False)
        for i, c in enumerate(self.columns):
            table.add_column(c, justify="right" if i in self.right else "left")
        for r in self.rows:
            table.add_row(*r)
        return table
