"""Diagnostics: stable codes, collected reports, and three output formats.

Every problem the toolchain reports has a code from :data:`CODES` (documented in
``docs/errors.md``, checked by a test).  Stages append to a :class:`Diagnostics` collection
and keep going; the CLI formats everything at the end as text (``file:line:col:
error[CODE]: message`` with the source line and a caret), JSON or GitHub annotations.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator

from catgrammar.codes import CODES, Code, Severity  # noqa: F401 - part of the diagnostics API
from catgrammar.record import Record, set_field
from catgrammar.span import Source, Span
from catgrammar.terminal import printable


def suggest(word: str, candidates: Iterable[str]) -> str | None:
    """The closest candidate to a misspelled ``word``, or None."""
    pool = list(candidates)
    import difflib  # only when a suggestion is wanted (start-up time)

    matches = difflib.get_close_matches(word, pool, n=1, cutoff=0.6)
    if matches:
        return matches[0]
    stem = word.lstrip(":")
    prefixed = [c for c in pool if len(stem) >= 3 and c.lstrip(":").startswith(stem)]
    return prefixed[0] if len(prefixed) == 1 else None


def did_you_mean(word: str, candidates: Iterable[str]) -> str:
    best = suggest(word, candidates)
    return f"; did you mean '{best}'?" if best else ""


class Fix(Record):
    """A change that applies a diagnostic's suggestion: replace ``span`` by ``text`` (an
    insertion when the span is empty).  Carried by the diagnostic, so that an editor applies
    it without reading the message (the language server's code actions)."""

    __slots__ = ("title", "span", "text")
    title: str
    span: Span
    text: str

    def __init__(self, title: str, span: Span, text: str) -> None:
        set_field(self, "title", title)
        set_field(self, "span", span)
        set_field(self, "text", text)


class Suggestion:
    """A did-you-mean for ``word`` written at ``span``: ``hint`` for the message ("; did you
    mean 'x'?" or "") and ``fixes``, the replacement of the word by the suggestion (none when
    there is no suggestion or no span)."""

    __slots__ = ("best", "hint", "fixes")

    def __init__(self, word: str, candidates: Iterable[str], span: Span | None, replacement: str | None = None) -> None:
        self.best = suggest(word, candidates)
        self.hint = f"; did you mean '{self.best}'?" if self.best else ""
        self.fixes: tuple[Fix, ...] = ()
        if self.best is not None and span is not None:
            text = self.best if replacement is None else replacement.format(self.best)
            self.fixes = (Fix(f"Replace with '{text}'", span, text),)


class Note(Record):
    __slots__ = ("message", "span")
    message: str
    span: Span | None

    def __init__(self, message: str, span: Span | None = None) -> None:
        set_field(self, "message", message)
        set_field(self, "span", span)


class Diagnostic(Record):
    __slots__ = ("code", "message", "span", "severity", "notes", "fixes")
    code: str
    message: str
    span: Span | None
    severity: Severity
    notes: tuple[Note, ...]
    fixes: tuple[Fix, ...]  # changes that apply the message's suggestion (did-you-mean, a missing flag)

    def __init__(
        self,
        code: str,
        message: str,
        span: Span | None,
        severity: Severity,
        notes: tuple[Note, ...] = (),
        fixes: tuple[Fix, ...] = (),
    ) -> None:
        set_field(self, "code", code)
        set_field(self, "message", message)
        set_field(self, "span", span)
        set_field(self, "severity", severity)
        set_field(self, "notes", notes)
        set_field(self, "fixes", fixes)

    @property
    def name(self) -> str:
        return CODES[self.code].name

    def to_json(self) -> dict:
        def loc(span: Span | None) -> dict | None:
            if span is None:
                return None
            return {
                "file": span.file,
                "line": span.line,
                "column": span.column,
                "end_line": span.end_line,
                "end_column": span.end_column,
            }

        return {
            "code": self.code,
            "name": self.name,
            "severity": self.severity.value,
            "message": self.message,
            "location": loc(self.span),
            "notes": [{"message": n.message, "location": loc(n.span)} for n in self.notes],
        }


class Diagnostics:
    """An ordered collection of diagnostics, plus the sources they point into."""

    def __init__(self) -> None:
        self._items: list[Diagnostic] = []
        self._keys: set[tuple] = set()
        self.sources: dict[str, Source] = {}

    def add_source(self, source: Source) -> None:
        self.sources[source.path] = source

    def report(
        self,
        code: str,
        message: str,
        span: Span | None,
        *notes: Note,
        severity: Severity | None = None,
        fixes: tuple[Fix, ...] = (),
    ) -> Diagnostic:
        diag = Diagnostic(code, message, span, severity or CODES[code].severity, tuple(notes), fixes)
        key = (code, message, span)
        if key not in self._keys:  # the same fact reached twice (e.g. a shared import)
            self._keys.add(key)
            self._items.append(diag)
        return diag

    def extend(self, other: Diagnostics) -> None:
        self.sources.update(other.sources)
        for d in other:
            self.report(d.code, d.message, d.span, *d.notes, severity=d.severity, fixes=d.fixes)

    def __iter__(self) -> Iterator[Diagnostic]:
        return iter(self._items)

    def __len__(self) -> int:
        return len(self._items)

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self._items if d.severity is Severity.ERROR]

    @property
    def warnings(self) -> list[Diagnostic]:
        return [d for d in self._items if d.severity is Severity.WARNING]

    @property
    def has_errors(self) -> bool:
        return any(d.severity is Severity.ERROR for d in self._items)

    def sorted(self) -> list[Diagnostic]:
        def key(d: Diagnostic):
            s = d.span
            return (s.file, s.line, s.column) if s else ("", 0, 0)

        return sorted(self._items, key=key)

    def promote_warnings(self) -> None:
        """``--strict``: every warning becomes an error."""
        self._items = [
            Diagnostic(d.code, d.message, d.span, Severity.ERROR, d.notes, d.fixes)
            if d.severity is Severity.WARNING
            else d
            for d in self._items
        ]


# ---------------------------------------------------------------- formatting


def excerpt_lines(source: Source | None, span: Span, label: str = "", highlight=None) -> list[str]:
    """The source line with a caret under the span; ``highlight`` (text → text, e.g. ANSI
    colours from the Pygments lexer) is applied to the source line only."""
    if source is None or span.line > source.line_count:
        return []
    raw = source.line_text(span.line).expandtabs(1)
    text = printable(raw)  # control characters shown as escapes: the caret follows them
    column = len(printable(raw[: span.column - 1])) + 1
    end_col = len(printable(raw[: span.end_column - 1])) + 1 if span.end_line == span.line else len(text) + 1
    shown = text if len(text) <= 200 else text[: max(200, column + 20)] + " …"
    width = len(str(span.line))
    caret_len = max(1, min(end_col, len(shown) + 1) - column)
    caret = " " * (column - 1) + "^" + "~" * (caret_len - 1)
    gutter = " " * width
    if highlight is not None:
        shown = highlight(shown)
    lines = [f" {gutter} |", f" {span.line} | {shown}", f" {gutter} | {caret}" + (f" {label}" if label else "")]
    return lines


def format_text(diags: Diagnostics, *, excerpts: bool = True, highlight=None) -> str:
    """Compiler-style text: ``file:line:col: error[CODE]: message`` plus excerpt and notes,
    with control characters shown as escapes (:func:`catgrammar.terminal.printable`).
    ``highlight`` colours the excerpts' source lines (see :func:`catgrammar.lexer.terminal_highlighter`)."""
    out: list[str] = []
    for d in diags.sorted():
        where = f"{d.span}: " if d.span else ""
        out.append(printable(f"{where}{d.severity.value}[{d.code}]: {d.message}"))
        if excerpts and d.span:
            out.extend(excerpt_lines(diags.sources.get(d.span.file), d.span, highlight=highlight))
        for n in d.notes:
            nwhere = f"{n.span}: " if n.span else ""
            out.append(printable(f"  = note: {nwhere}{n.message}"))
            if excerpts and n.span and n.span != d.span:
                out.extend(
                    "  " + line for line in excerpt_lines(diags.sources.get(n.span.file), n.span, highlight=highlight)
                )
    return "\n".join(out)


def summary_line(diags: Diagnostics, files: int) -> str:
    e, w = len(diags.errors), len(diags.warnings)
    plural = lambda n, word: f"{n} {word}{'' if n == 1 else 's'}"  # noqa: E731
    return f"{plural(e, 'error')}, {plural(w, 'warning')} in {plural(files, 'file')} checked"


def format_json(diags: Diagnostics, files: list[str]) -> str:
    import json

    return json.dumps(
        {
            "schema": "catc.check/1",
            "files": files,
            "errors": len(diags.errors),
            "warnings": len(diags.warnings),
            "diagnostics": [d.to_json() for d in diags.sorted()],
        },
        indent=2,
    )


def _gh_escape(text: str, prop: bool = False) -> str:
    text = printable(text).replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")
    if prop:
        text = text.replace(":", "%3A").replace(",", "%2C")
    return text


def format_github(diags: Diagnostics) -> str:
    """GitHub Actions workflow commands (``::error file=...,line=...::message``)."""
    out = []
    for d in diags.sorted():
        kind = "error" if d.severity is Severity.ERROR else "warning"
        props = [f"title={_gh_escape(d.code + ' ' + d.name, True)}"]
        if d.span:
            props = [
                f"file={_gh_escape(d.span.file, True)}",
                f"line={d.span.line}",
                f"col={d.span.column}",
                f"endLine={d.span.end_line}",
                f"endColumn={d.span.end_column}",
            ] + props
        out.append(f"::{kind} {','.join(props)}::{_gh_escape(d.message)}")
    return "\n".join(out)
