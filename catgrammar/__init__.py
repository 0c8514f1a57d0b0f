"""catgrammar — the .cat language: grammar, parser, AST with source spans, diagnostics."""

from catgrammar.diagnostics import Diagnostic, Diagnostics, Severity
from catgrammar.parser import parse_source, parse_text, read_source
from catgrammar.span import Source, Span

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
