"""catgrammar — the .cat language: grammar, parser, AST with source spans, diagnostics.

The names below are imported on first use (PEP 562), so that ``import catgrammar.span``
or ``from catgrammar import ast`` does not load the parser as well.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

__all__ = [
    "Diagnostic",
    "Diagnostics",
    "Severity",
    "Source",
    "Span",
    "parse_source",
    "parse_text",
    "read_source",
]

_HOME = {
    "Diagnostic": "diagnostics",
    "Diagnostics": "diagnostics",
    "Severity": "diagnostics",
    "Source": "span",
    "Span": "span",
    "parse_source": "parser",
    "parse_text": "parser",
    "read_source": "parser",
}

if TYPE_CHECKING:
    from catgrammar.diagnostics import Diagnostic, Diagnostics, Severity
    from catgrammar.parser import parse_source, parse_text, read_source
    from catgrammar.span import Source, Span


def __getattr__(name: str) -> Any:
    home = _HOME.get(name)
    if home is None:
        raise AttributeError(f"module 'catgrammar' has no attribute {name!r}")
    from importlib import import_module

    value = getattr(import_module(f"catgrammar.{home}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
