"""The indentation rule of ``catc fmt``, line by line, as an editor computes it.

An editor indents one line at a time from the lines above it; ``catc fmt`` lays out a whole
file.  This module states, for one line, the column ``catc fmt`` would give it, from what an
editor can see: the innermost bracket still open before the line, the text after that
bracket on its line, and (for typed lists) the line before.  The Vim and Emacs indenters
(``editors/vim/indent/cat.vim``, ``editors/emacs/cat-mode.el``) implement the same rules; the
tests hold all three against ``catc fmt`` on every ``.cat`` file of the repository.

The rules, for the innermost open bracket at column ``c`` (0-based) of line ``L``:

* ``{`` (a set), ``:keep (``/``:drop (`` (a list of names), a list whose first element is a
  list, or a ``:key`` that is not a section: under the first element, column ``c + 1``;
* ``(define`` and a ``(:section``: the body two columns in (``c + 2``), except the filled
  sections (``:init``, ``:requirements``, ``:import``, ``:deployed``), continued under their
  first item when it is on the head's line, and the typed lists (``:sorts``, ``:constants``,
  ``:objects``): each ``names - sort`` group at ``c + 2``, a group's continuation at ``c + 4``;
* ``(enum a b``: filled, under ``a`` (or ``c + 2`` when ``enum`` ends its line);
* any other list, a call ``(op first``: under ``first`` (``c + 2`` when the head ends the
  line; as if ``first`` followed on the head's line when only a comment does);
* after an open bracket followed only by a comment: ``c + 1``.

Brackets inside strings and comments do not count.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from catgrammar.symbols import Section

SECTIONS = frozenset({"define", *(s.value for s in Section)})
FILLED = frozenset({":init", ":requirements", ":import", ":deployed"})
TYPED = frozenset({":sorts", ":constants", ":objects"})
NAME_LIST_KEYS = frozenset({":keep", ":drop"})
STEP = 2
_ATOM = re.compile(r'[^\s(){}";]+')
_GROUP_END = re.compile(r'(^|\s)-\s+([^\s(){}";]+|\(.*\))\s*$')


def code_part(line: str) -> str:
    """``line`` without its comment (a ``;`` outside a string)."""
    in_string = escaped = False
    for i, ch in enumerate(line):
        if in_string:
            if escaped:
                escaped = False
            elif ch == "\\":
                escaped = True
            elif ch == '"':
                in_string = False
        elif ch == '"':
            in_string = True
        elif ch == ";":
            return line[:i]
    return line


def _open_bracket(lines: Sequence[str], n: int) -> tuple[int, int] | None:
    """(line, column) of the innermost bracket still open at the start of line ``n``."""
    stack: list[tuple[int, int]] = []
    for ln in range(n):
        in_string = escaped = False
        for col, ch in enumerate(lines[ln]):
            if in_string:
                if escaped:
                    escaped = False
                elif ch == "\\":
                    escaped = True
                elif ch == '"':
                    in_string = False
            elif ch == '"':
                in_string = True
            elif ch == ";":
                break
            elif ch in "({":
                stack.append((ln, col))
            elif ch in ")}" and stack:
                stack.pop()
    return stack[-1] if stack else None


def indent_of(lines: Sequence[str], n: int) -> int:
    """The column ``catc fmt`` gives line ``n`` (0-based) of ``lines`` (the lines above it as
    they stand; line ``n`` itself is not read)."""
    found = _open_bracket(lines, n)
    if found is None:
        return 0
    ln, c = found
    line = lines[ln]
    rest = line[c + 1 :]
    code = code_part(rest)
    first = len(code) - len(code.lstrip())
    if not code.strip():  # "(" alone, or followed by a comment only
        return c + 1
    first_col = c + 1 + first
    head_match = _ATOM.match(code, first)
    if line[c] == "{" or head_match is None or code_part(line[:c]).rstrip().split()[-1:] in ([":keep"], [":drop"]):
        return first_col
    head = head_match.group()
    after = code[head_match.end() :]
    nxt = len(after) - len(after.lstrip())
    has_next = bool(after.strip())
    next_col = c + 1 + head_match.end() + nxt
    if head in SECTIONS:
        if head in FILLED:
            return next_col if has_next else c + STEP
        if head in TYPED:
            return c + STEP + (0 if _group_ended(lines, ln, n) else STEP)
        return c + STEP
    if head.startswith(":"):
        return first_col
    if has_next:
        return next_col
    if code.rstrip() != rest.rstrip():  # the head, then a comment: as if the first argument followed it
        return c + 1 + head_match.end() + 1
    return c + STEP


def _group_ended(lines: Sequence[str], ln: int, n: int) -> bool:
    """In a typed list opened on line ``ln``: does line ``n`` start a new ``names - sort``
    group (the code line before it ends one, or is the head's)?"""
    for prev in range(n - 1, ln, -1):
        code = code_part(lines[prev]).strip()
        if code:
            return bool(_GROUP_END.search(code))
    return True


def reindent(text: str) -> str:
    """Every line of ``text`` at the column :func:`indent_of` gives it (comment lines and
    all); blank lines stay blank."""
    lines = text.split("\n")
    out: list[str] = []
    for i, line in enumerate(lines):
        body = line.strip()
        out.append(" " * indent_of(out + lines[i:], i) + body if body else "")
    return "\n".join(out)
