"""Model-edit line counts: the lines of a model file that count as model content (comments
and blank lines dropped, white space normalised; PDDL declarations one a line), and the
line-level difference of two models by difflib."""

from __future__ import annotations

import difflib
from collections.abc import Iterable
from dataclasses import dataclass

from catc.frontend.indent import code_part as strip_comment


def _split_declarations(line: str) -> list[str]:
    """``(:predicates (a) (b x))`` → ``["(:predicates", "(a)", "(b x)", ")"]``: one declaration
    a line, as a hand-written PDDL file would have them (what follows the section's closing
    parenthesis stays one line)."""
    head, _, rest = line.partition(" ")
    items: list[str] = [head]
    depth, cur = 1, []
    for i, ch in enumerate(rest):
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        if depth >= 2 or (ch == ")" and depth == 1):
            cur.append(ch)
            if depth == 1:
                items.append("".join(cur))
                cur = []
        elif depth == 0:
            items.append(")")
            tail = rest[i + 1 :].strip()
            if tail:
                items.append(tail)
            return items
    return [line]  # unbalanced: leave it as written


def model_lines(text: str, *, pddl: bool = False) -> list[str]:
    """The lines of a model file that count as model content: comments removed, whitespace
    normalised (runs of blanks → one space, stripped), blank lines dropped.  For PDDL,
    ``(:predicates ...)`` and ``(:functions ...)`` written on one line are split into one
    declaration per line first (as a hand-maintained file would list them)."""
    out: list[str] = []
    for raw in text.splitlines():
        line = " ".join(strip_comment(raw).split())
        if not line:
            continue
        if pddl and (line.startswith("(:predicates ") or line.startswith("(:functions ")):
            out.extend(_split_declarations(line))
        else:
            out.append(line)
    return out


@dataclass(frozen=True)
class LineDiff:
    added: int
    removed: int
    changed: int  # edited lines: a replaced block of a old and b new lines counts max(a, b)

    def __add__(self, other: LineDiff) -> LineDiff:
        return LineDiff(self.added + other.added, self.removed + other.removed, self.changed + other.changed)

    def text(self) -> str:
        return f"{self.changed} (+{self.added} −{self.removed})"


def line_diff(old: Iterable[str], new: Iterable[str]) -> LineDiff:
    """Line-level difference of two normalised line lists (:func:`model_lines`), by difflib."""
    a, b = list(old), list(new)
    added = removed = changed = 0
    for tag, i1, i2, j1, j2 in difflib.SequenceMatcher(None, a, b, autojunk=False).get_opcodes():
        if tag == "equal":
            continue
        removed += i2 - i1
        added += j2 - j1
        changed += max(i2 - i1, j2 - j1)
    return LineDiff(added, removed, changed)


def text_diff(old: str, new: str, *, pddl: bool = False) -> LineDiff:
    return line_diff(model_lines(old, pddl=pddl), model_lines(new, pddl=pddl))
