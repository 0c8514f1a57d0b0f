"""Source files and positions."""

from __future__ import annotations

import bisect
from typing import NamedTuple


class Span(NamedTuple):
    """A range of source text.  Lines and columns are 1-based; ``end_column`` is exclusive;
    ``start``/``end`` are character offsets into the file's text.

    A named tuple rather than a frozen dataclass: the parser makes one per token, and tuple
    construction is several times cheaper."""

    file: str
    line: int
    column: int
    end_line: int
    end_column: int
    start: int = 0
    end: int = 0

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"

    def cover(self, other: Span) -> Span:
        """The smallest span containing both (same file)."""
        first, last = (self, other) if self.start <= other.start else (other, self)
        tail = last if last.end >= first.end else first
        return Span(self.file, first.line, first.column, tail.end_line, tail.end_column, first.start, tail.end)


class Source:
    """The text of one file, with a line index for excerpts and offset→position lookups.

    Mutable like the ``@dataclass(slots=True)`` it was (equal when path and text are; not
    hashable), written out to keep ``@dataclass``'s start-up cost off every ``catc`` run."""

    __slots__ = ("path", "text", "_line_starts")
    __hash__ = None  # type: ignore[assignment]  # unhashable (mutable), as the dataclass was

    def __init__(self, path: str, text: str) -> None:
        self.path = path
        self.text = text
        starts = [0]
        find = text.find
        pos = find("\n")
        while pos != -1:
            starts.append(pos + 1)
            pos = find("\n", pos + 1)
        self._line_starts = starts

    def __eq__(self, other: object) -> bool:
        if other.__class__ is self.__class__:
            return (self.path, self.text) == (other.path, other.text)
        return NotImplemented

    def __repr__(self) -> str:
        return f"Source(path={self.path!r}, text={self.text!r})"

    def line_text(self, line: int) -> str:
        if line < 1 or line > len(self._line_starts):
            return ""
        start = self._line_starts[line - 1]
        end = self.text.find("\n", start)
        return self.text[start : end if end != -1 else len(self.text)].rstrip("\r")

    @property
    def line_count(self) -> int:
        return len(self._line_starts)

    def position(self, offset: int) -> tuple[int, int]:
        """1-based (line, column) of a character offset."""
        offset = max(0, min(offset, len(self.text)))
        index = bisect.bisect_right(self._line_starts, offset) - 1
        return index + 1, offset - self._line_starts[index] + 1

    def span(self, start: int, end: int | None = None) -> Span:
        end = start + 1 if end is None else end
        line, column = self.position(start)
        end_line, end_column = self.position(end)
        return Span(self.path, line, column, end_line, end_column, start, end)

    def whole(self) -> Span:
        return self.span(0, len(self.text))
