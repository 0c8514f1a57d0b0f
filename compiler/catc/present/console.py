"""Where human output goes: a plain console for pipes and files, and tables that render as
aligned text or as rich tables on a terminal.

Everything a query prints goes through ``console.print`` with rich's markup
(``[bold]...[/]``); :class:`PlainConsole` renders the markup away, so piped output has no
colour codes and does not import rich (start-up time), and :class:`TerminalConsole` hands
it to rich.  Text from the user's files (a ``:unit``, a path, a source line) is put into
markup through :func:`escape`, so a ``[bold]`` or ``[/]`` in it is shown as written; table
cells are plain text.  Both consoles show control characters as escapes
(:func:`catgrammar.terminal.printable`): nothing printed can drive the terminal.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any, Protocol

from catgrammar.terminal import printable

# rich's markup tags (rich.markup.RE_TAGS): an opening or closing tag, after any backslashes
# (compiled by re when first used, and kept in its cache: a JSON answer never uses it)
_TAG = r"(\\*)(\[[a-z#/@][^[]*?])"


def counted(n: int, noun: str) -> str:
    """``1 step``, ``3 steps``, ``0 steps``: a count and its noun, agreeing."""
    return f"{n} {noun}{'' if n == 1 else 's'}"


class Console(Protocol):
    def print(self, obj: object = "") -> None: ...


def escape(text: str) -> str:
    """``text`` as markup that shows it as written (what ``rich.markup.escape`` does)."""
    text = re.sub(_TAG, lambda m: f"{m.group(1)}{m.group(1)}\\{m.group(2)}", text)
    return text + "\\" if text.endswith("\\") and not text.endswith("\\\\") else text


def plain(markup: str) -> str:
    """Markup rendered without styles: tags dropped, escaped tags and backslashes as rich
    shows them."""

    def tag(m: re.Match[str]) -> str:
        backslashes, escaped = divmod(len(m.group(1)), 2)
        return "\\" * backslashes + (m.group(2) if escaped else "")

    return re.sub(_TAG, tag, markup)


class PlainConsole:
    """The subset of rich's Console used here, printing plain aligned text."""

    def __init__(self, write: Callable[[str], None]) -> None:
        self.write = write

    def print(self, obj: object = "") -> None:
        if isinstance(obj, Table):
            self.write(obj.render())
        else:
            self.write(printable(plain(str(obj))))


class TerminalConsole:
    """rich's Console for a terminal, with control characters shown as escapes."""

    def __init__(self, console: Any) -> None:
        self.console = console

    def print(self, obj: object = "") -> None:
        self.console.print(obj if isinstance(obj, Table) else printable(str(obj)))


class Table:
    """A minimal table that renders as aligned columns, or converts to a rich Table."""

    def __init__(self, *columns: str, right: tuple[int, ...] = ()) -> None:
        self.columns = columns
        self.right = right
        self.rows: list[tuple[str, ...]] = []

    def add_row(self, *cells: str) -> None:
        """Cells are plain text (not markup), shown with control characters escaped."""
        self.rows.append(tuple(printable(c) for c in cells))

    def render(self) -> str:
        widths = [max(len(r[i]) for r in [self.columns, *self.rows]) for i in range(len(self.columns))]
        out = []
        for row in [self.columns, *self.rows]:
            cells = [c.rjust(w) if i in self.right else c.ljust(w) for i, (c, w) in enumerate(zip(row, widths))]
            out.append("  ".join(cells).rstrip())
        return "\n".join(out)

    def __rich__(self) -> Any:
        from rich.table import Table as RichTable
        from rich.text import Text

        table = RichTable(show_header=True, header_style="bold", box=None, pad_edge=False)
        for i, c in enumerate(self.columns):
            table.add_column(c, justify="right" if i in self.right else "left")
        for r in self.rows:
            table.add_row(*(Text(c) for c in r))
        return table
