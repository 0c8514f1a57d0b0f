"""The tokenizer that feeds the LALR parser.

One compiled regular expression scans the text; words are classified against the keyword
lists of :mod:`catgrammar.symbols`, so the grammar (``cat.lark`` declares these terminals
with ``%declare``), this tokenizer and every highlighter share one vocabulary.  A keyword
ends at a word boundary: ``:morphisms`` is an unknown keyword, never ``:morphism s``.

It replaces Lark's own lexer for speed (a 2,000-morphism domain tokenizes about twice as
fast; see docs/benchmarks.md), and it never needs the parser's state: every word means the
same thing everywhere, which is why keywords of the language are reserved names.  Tokens
and errors are those of :mod:`catgrammar._lalr`: nothing here imports Lark.
"""

from __future__ import annotations

import re
from collections.abc import Iterator

from catgrammar._lalr import Token, UnexpectedCharacters
from catgrammar.symbols import MetricMode, MetricSense, Option, Section


def keyword_terminal(keyword: str) -> str:
    """``:max-effects`` → ``MAX_EFFECTS_KW`` (the terminal's name in cat.lark)."""
    return keyword.lstrip(":").upper().replace("-", "_") + "_KW"


#: ``:keyword`` → terminal (sections and options; other ``:words`` are requirement FLAGs).
COLON_KEYWORDS: dict[str, str] = {
    k: keyword_terminal(k) for k in dict.fromkeys([s.value for s in Section] + [o.value for o in Option])
}

#: Bare words with a fixed role in the grammar.  Terminals starting with ``_`` are dropped
#: from a rule's children by the parser (as Lark does).
WORDS: dict[str, str] = {
    "define": "_DEFINE_WORD",
    "domain": "_DOMAIN_WORD",
    "problem": "_PROBLEM_WORD",
    "enum": "_ENUM_WORD",
    "set": "_SET_WORD",
    MetricMode.LEX.value: "_LEX_WORD",
    MetricMode.PARETO.value: "_PARETO_WORD",
    MetricSense.MINIMIZE.value: "SENSE",
    MetricSense.MAXIMIZE.value: "SENSE",
    "true": "TRUE",
    "false": "FALSE",
}

PUNCTUATION = {"(": "LPAR", ")": "RPAR", "{": "LBRACE", "}": "RBRACE", "-": "MINUS", "*": "STAR"}

#: How a terminal is shown in "expected ..." messages.
TERMINAL_TEXT: dict[str, str] = {
    **{t: f"'{k}'" for k, t in COLON_KEYWORDS.items()},
    **{t: f"'{w}'" for w, t in WORDS.items() if t != "SENSE"},
    **{t: f"'{p}'" for p, t in PUNCTUATION.items()},
    "SENSE": "'minimize' or 'maximize'",
    "NAME": "a name",
    "OPSYM": "an operator",
    "NUMBER": "a number",
    "STRING": "a string",
    "FLAG": "a requirement flag",
    "$END": "the end of the file",
}

_TOKEN = re.compile(
    r"""
      (?P<WS>\s+)
    | (?P<COMMENT>;[^\n]*)
    | (?P<NUMBER>[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)(?![A-Za-z0-9_.])
    | (?P<PUNCT>[(){}*]|-(?![0-9.]))
    | (?P<COLON>:[A-Za-z][A-Za-z0-9_-]*)
    | (?P<WORD>[A-Za-z_][A-Za-z0-9_-]*)
    | (?P<STRING>"(?:[^"\\\n]|\\.)*")
    | (?P<OPSYM><=|>=|[=<>+/])
    """,
    re.VERBOSE,
)


class TooManyTokens(Exception):
    """More tokens than the ``limit`` given to :func:`tokenize`; ``token`` is the first past it."""

    def __init__(self, token: Token, limit: int) -> None:
        super().__init__(f"more than {limit} tokens")
        self.token, self.limit = token, limit


def tokenize(text: str, limit: int | None = None) -> Iterator[Token]:
    """Yield tokens with positions; raise ``UnexpectedCharacters`` on a stray character, and
    :class:`TooManyTokens` at token ``limit + 1``."""
    pos, line, line_start, n = 0, 1, 0, len(text)
    left = -1 if limit is None else limit
    match = _TOKEN.match
    colon_get, word_get, punct = COLON_KEYWORDS.get, WORDS.get, PUNCTUATION
    while pos < n:
        m = match(text, pos)
        if m is None:
            raise UnexpectedCharacters(text, pos, line, pos - line_start + 1)
        kind = m.lastgroup
        assert kind is not None  # every alternative of _TOKEN is a named group
        end = m.end()
        value = m.group()
        if kind == "WS" or kind == "COMMENT":
            newlines = value.count("\n")
            if newlines:
                line += newlines
                line_start = pos + value.rfind("\n") + 1
            pos = end
            continue
        if kind == "WORD":
            kind = word_get(value, "NAME")
        elif kind == "COLON":
            kind = colon_get(value, "FLAG")
        elif kind == "PUNCT":
            kind = punct[value]
        column = pos - line_start + 1
        token = Token(kind, value, pos, line, column, line, column + (end - pos), end)
        if left == 0:
            raise TooManyTokens(token, limit or 0)
        left -= 1
        yield token
        pos = end
