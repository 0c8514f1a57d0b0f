"""Labelled constraints for people and for JSON: what each one is and where it is written."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from catc.ir.labels import LabelInfo
from catgrammar.diagnostics import excerpt_lines
from catgrammar.span import Source, Span

_OWNED = ("precondition", "effect", "parameter bounds", "use limit")


def where(info: LabelInfo) -> str:
    """``FILE:LINE:COL`` of the construct; for a default initial value (written nowhere),
    ``default value of `r` (declared at FILE:LINE:COL)``."""
    span = info.span
    if span is not None:
        return f"{span.file}:{span.line}:{span.column}"
    if info.declared is not None:
        d = info.declared
        return f"default value of `{info.owner}` (declared at {d.file}:{d.line}:{d.column})"
    return "(no source location)"


def describe(info: LabelInfo) -> str:
    owner = f" of {info.owner}" if info.owner and info.kind in _OWNED else ""
    return f"{info.kind}{owner}  {info.text}"


def label_json(info: LabelInfo) -> dict:
    span = info.span
    return {
        "label": info.label,
        "kind": info.kind,
        "text": info.text,
        "owner": info.owner,
        "location": None
        if span is None
        else {
            "file": span.file,
            "line": span.line,
            "column": span.column,
            "end_line": span.end_line,
            "end_column": span.end_column,
        },
    }


def excerpts() -> Callable[[Span | None], list[str]]:
    """Source excerpts for spans, reading each file once, on demand."""
    cache: dict[str, Source | None] = {}

    def excerpt(span: Span | None) -> list[str]:
        if span is None:
            return []
        if span.file not in cache:
            try:
                cache[span.file] = Source(span.file, Path(span.file).read_text(encoding="utf-8"))
            except (OSError, UnicodeDecodeError):
                cache[span.file] = None
        return excerpt_lines(cache[span.file], span)

    return excerpt
