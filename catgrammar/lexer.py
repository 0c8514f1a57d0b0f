"""A Pygments lexer for ``.cat`` domain and problem files.

Every word list comes from :func:`catgrammar.symbols.all_keywords`, so a keyword added
there is highlighted here without touching this file (``tests/editors/test_keywords.py``
checks it).  The lexer is registered through the ``pygments.lexers`` entry point::

    [project.entry-points."pygments.lexers"]
    cat = "catgrammar.lexer:CatLexer"

after which ``pygmentize -l cat FILE`` and Sphinx ``.. code-block:: cat`` work.

Token mapping:

================================  =====================================================
``; comment``                     ``Comment.Single``
``define domain problem``         ``Keyword``
``(:morphism`` (a section head)   ``Keyword.Declaration``
``:precondition`` (an option)     ``Name.Attribute``
``:numeric`` (a requirement)      ``Keyword.Namespace``
``and member total-churn``        ``Keyword`` (word operators)
``= <= + - * /``                  ``Operator``
``real set enum``                 ``Keyword.Type``
``true false``                    ``Keyword.Constant``
``software minimize lex``         ``Name.Builtin`` (morphism kinds, metric words)
``12 0.5 1e-3``                   ``Number.Integer`` / ``Number.Float``
``"text"``                        ``String.Double`` (``String.Escape`` for ``\\x``)
``( ) { }``                       ``Punctuation``
any other name                    ``Name``
================================  =====================================================

``:view`` is both a section (``(:view software ...)``) and a hole option
(``(:hole mu :view software)``): directly after ``(`` it is a section, elsewhere an
option.  Names may contain hyphens (``lidar-driver``), so a keyword is only recognised
as a whole name: ``not-ready`` is a plain ``Name``.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from typing import TypeAlias

from pygments.lexer import RegexLexer, bygroups, default
from pygments.token import (
    Comment,
    Keyword,
    Name,
    Number,
    Operator,
    Punctuation,
    String,
    Whitespace,
    _TokenType,
)

from catgrammar.symbols import all_keywords

__all__ = ["TOKEN_FOR_CATEGORY", "CatLexer"]

TokenType: TypeAlias = _TokenType  # the class of Keyword, Name.Builtin, ...

#: The Pygments token of every ``all_keywords()`` category.
TOKEN_FOR_CATEGORY: dict[str, TokenType] = {
    "structure": Keyword,
    "section": Keyword.Declaration,
    "option": Name.Attribute,
    "requirement": Keyword.Namespace,
    "operator": Keyword,
    "symbol-operator": Operator,
    "type": Keyword.Type,
    "constant": Keyword.Constant,
    "kind": Name.Builtin,
    "metric": Name.Builtin,
}

_NAME = r"[a-zA-Z_][a-zA-Z0-9_-]*"
_COLON_WORD = r":[a-zA-Z_][a-zA-Z0-9_-]*"
#: Numbers as ``cat.lark`` reads them: ``3``, ``-2``, ``0.5``, ``.5``, ``1e-3``.
_FLOAT = r"[+-]?(?:[0-9]+\.[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|[+-]?[0-9]+[eE][+-]?[0-9]+"
_INTEGER = r"[+-]?[0-9]+"
#: What may not follow a keyword or number for it to be a whole token.
_END = r"(?![a-zA-Z0-9_-])"


def _keyword_table() -> dict[str, TokenType]:
    """Word → token for bare words and ``:words``, first category wins (see ``order``)."""
    keywords = all_keywords()
    # A word in two categories takes the first: ``:view`` outside a section head is the
    # hole option, not the section.  A category this module does not know yet is still
    # highlighted (as ``Keyword``); tests/editors/test_keywords.py fails until it is mapped.
    order = ["option", "requirement", "section", "structure", "operator", "type", "constant", "kind", "metric"]
    order += [c for c in keywords if c not in order and c != "symbol-operator"]
    table: dict[str, TokenType] = {}
    for category in order:
        for word in keywords.get(category, ()):
            table.setdefault(word, TOKEN_FOR_CATEGORY.get(category, Keyword))
    return table


_KEYWORDS = _keyword_table()


def _alternation(items: tuple[str, ...]) -> str:
    """A regex matching any of ``items``, longest first (``<=`` before ``<``)."""
    return "|".join(re.escape(item) for item in sorted(items, key=lambda w: (-len(w), w)))


def _classify(lexer: RegexLexer, match: re.Match[str]) -> Iterator[tuple[int, TokenType, str]]:
    """A bare name or ``:word``: its keyword token, or ``Name`` for anything else."""
    word = match.group()
    yield match.start(), _KEYWORDS.get(word, Name), word


class CatLexer(RegexLexer):
    """Lexer for ``.cat`` robot domain and problem files (the catc language)."""

    name = "Cat"
    aliases = ["cat", "catc"]
    filenames = ["*.cat"]
    mimetypes = ["text/x-cat"]

    flags = re.MULTILINE

    tokens = {
        "root": [
            (r"\s+", Whitespace),
            (r";[^\n]*", Comment.Single),
            (r'"', String.Double, "string"),
            # A section head: ``(`` then a section keyword (``(:view`` is a section).
            (
                rf"(\()(\s*)({_alternation(all_keywords()['section'])}){_END}",
                bygroups(Punctuation, Whitespace, Keyword.Declaration),
            ),
            (r"[(){}]", Punctuation),
            (_COLON_WORD, _classify),
            (f"(?:{_FLOAT}){_END}", Number.Float),
            (f"{_INTEGER}{_END}", Number.Integer),
            (_NAME, _classify),
            (_alternation(all_keywords()["symbol-operator"]), Operator),
        ],
        "string": [
            (r'[^"\\\n]+', String.Double),
            (r"\\.", String.Escape),
            (r'"', String.Double, "#pop"),
            # An unterminated string ends at the end of its line, as in cat.lark.
            default("#pop"),
        ],
    }

    @staticmethod
    def analyse_text(text: str) -> float:
        """Recognise ``(define (domain x)`` / ``(define (problem x)`` near the top."""
        if re.search(r"\(\s*define\s*\(\s*(?:domain|problem)\s+[a-zA-Z_]", text[:4096]):
            return 0.8
        return 0.0


def terminal_highlighter() -> Callable[[str], str]:
    """A function colouring one line of .cat source for a terminal, with this lexer (the
    same keyword lists as the grammar)."""
    from pygments import highlight
    from pygments.formatters import TerminalFormatter

    lexer, formatter = CatLexer(), TerminalFormatter()
    return lambda line: highlight(line, lexer, formatter).rstrip("\n")
