"""``catc fmt``: one canonical layout for .cat files.

The formatter works on the token stream, not on the AST: it only ever changes the
whitespace between tokens, so the meaning cannot change (numbers, strings and names keep
their exact text).  Comments, which the tokenizer skips, are recovered from the gaps between
tokens: a comment on the same line as the token before it stays at the end of that line
(*trailing*); any other comment is printed on its own line before the next token (*leading*).
Single blank lines between the items of a broken list are kept.

Layout:

* 2-space indentation; ``(define ...)`` lists one section per line, ``(:resources ...)``
  one resource per line and ``(:morphism ...)`` one option per line, except that its short
  options share a line (``:kind hardware :churn 1 :uses 1 :cost 150``);
* other lists stay on one line when they fit in :data:`WIDTH` columns, closing brackets
  included, and hold no comment; otherwise they break, PDDL style: ``(and (a ...)`` with the
  other arguments aligned under the first, ``:key value`` pairs kept together;
* lists of like items are *filled* (as many per line as fit), continued under their first
  item: ``(:init ...)``, ``(:requirements ...)``, ``(:import ...)``, ``(:deployed ...)``, the
  names of ``:keep``/``:drop``, ``{set}`` literals and ``(enum ...)``;
* typed lists (``(:sorts ...)``, ``(:constants ...)``, ``(:objects ...)``) put one
  ``names - sort`` group per line; a group too long for a line is filled, its continuation
  lines two columns further in, and ``- sort`` stays with the last name.

Formatting is idempotent, and :func:`format_text` checks its own output: the tokens and the
comments must come back identical, or it raises :class:`FormatError`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from catgrammar.symbols import Section
from catgrammar.tokens import tokenize

if TYPE_CHECKING:
    from catgrammar._lalr import Token
    from catgrammar.diagnostics import Diagnostics

WIDTH = 100

_SECTIONS = frozenset(s.value for s in Section)
_TYPED = frozenset({":sorts", ":constants", ":objects"})
_FILL = frozenset({":init", ":requirements", ":import", ":deployed"})
_ALWAYS_BROKEN = frozenset({":morphism", ":resources"})
_SCALAR_OPTIONS = frozenset({":kind", ":churn", ":uses", ":cost"})  # share a line when atoms
_NAME_LIST_KEYS = frozenset({":keep", ":drop"})
_COMMENT = re.compile(r";[^\n]*")


class FormatError(Exception):
    """The formatter would have changed the tokens or lost a comment (a bug in catc fmt)."""


@dataclass
class Comment:
    text: str
    blank_before: bool = False


@dataclass
class Tok:
    kind: str
    text: str
    leading: list[Comment] = field(default_factory=list)
    trailing: str | None = None
    blank_before: bool = False  # a blank line right before the token (or its first comment)


@dataclass
class Atom:
    tok: Tok


@dataclass
class Group:
    open: Tok
    children: list[Node]
    close: Tok
    names: bool = False  # a list of names or values, filled: {a b}, :keep (a b), (enum a b)


Node = Atom | Group
Unit = list[Node]  # nodes printed together: a ":key value" pair, a "names - sort" group


# ---------------------------------------------------------------- tokens + comments


def _blank(gap: str) -> bool:
    return gap.count("\n") >= 2


def scan(text: str) -> tuple[list[Tok], Tok]:
    """Tokens with their comments attached, and an end-of-file token holding the comments
    after the last token."""
    toks: list[Tok] = []
    pos = 0
    raw: list[Token | None] = [*tokenize(text), None]
    for t in raw:
        start = t.start_pos if t is not None and t.start_pos is not None else len(text)
        gap = text[pos:start]
        tok = Tok(t.type, t.value) if t is not None else Tok("$END", "")
        leading: list[Comment] = []
        last = 0
        for m in _COMMENT.finditer(gap):
            before = gap[last : m.start()]
            if toks and not leading and "\n" not in before and toks[-1].trailing is None and last == 0:
                toks[-1].trailing = m.group().rstrip()
            else:
                leading.append(Comment(m.group().rstrip(), _blank(before)))
            last = m.end()
        tok.leading = leading
        if leading:
            tok.blank_before = leading[0].blank_before
            tail_blank = _blank(gap[last:])
            # a blank line between the last comment and the token: keep it as a separator
            tok.leading.append(Comment("", True)) if tail_blank else None
        else:
            tok.blank_before = _blank(gap)
        toks.append(tok)
        if t is not None and t.end_pos is not None:
            pos = t.end_pos
    # "x ; a ) ; b )": a comment before closing parentheses ends up after them when printed;
    # attach the comments of a token and the closing parentheses after it to the last ones
    # of that run, so that the layout does not depend on where they were
    body = toks[:-1]
    i = 0
    while i < len(body):
        j = i + 1
        while j < len(body) and body[j].kind in ("RPAR", "RBRACE") and not body[j].leading:
            j += 1
        run = body[i:j]
        comments = [r.trailing for r in run if r.trailing is not None]
        if len(run) > 1 and comments:
            for r in run:
                r.trailing = None
            for r, c in zip(run[len(run) - len(comments) :], comments):
                r.trailing = c
        i = j
    return toks[:-1], toks[-1]


def tree(toks: list[Tok]) -> list[Node]:
    stack: list[list[Node]] = [[]]
    opens: list[tuple[Tok, bool]] = []  # an open bracket, and whether a :keep/:drop is before it
    prev: Tok | None = None
    for tok in toks:
        if tok.kind in ("LPAR", "LBRACE"):
            stack.append([])
            opens.append((tok, prev is not None and prev.text in _NAME_LIST_KEYS))
        elif tok.kind in ("RPAR", "RBRACE"):
            children = stack.pop()
            open_tok, after_key = opens.pop()
            enum = bool(children) and isinstance(children[0], Atom) and children[0].tok.kind == "_ENUM_WORD"
            names = open_tok.kind == "LBRACE" or after_key or enum
            stack[-1].append(Group(open_tok, children, tok, names))
        else:
            stack[-1].append(Atom(tok))
        prev = tok
    if len(stack) != 1:  # pragma: no cover - the parser rejects unbalanced input first
        raise FormatError("unbalanced parentheses")
    return stack[0]


# ---------------------------------------------------------------- helpers on nodes


def first_tok(node: Node) -> Tok:
    return node.tok if isinstance(node, Atom) else node.open


def last_tok(node: Node) -> Tok:
    return node.tok if isinstance(node, Atom) else node.close


def _internal_comments(node: Node, tail_free: bool = True) -> bool:
    """Any comment inside ``node`` that forces it to break.  Leading comments of its first
    token and a trailing comment after its last token are placed by the parent; a trailing
    comment on the last token of its last child moves out after the closing parentheses
    (when ``tail_free`` and no closing parenthesis on the way has a comment of its own)."""
    if isinstance(node, Atom):
        return False
    if node.open.trailing is not None or node.close.leading:
        return True
    n = len(node.children)
    for i, c in enumerate(node.children):
        if first_tok(c).leading:
            return True
        free = i == n - 1 and tail_free and node.close.trailing is None
        if last_tok(c).trailing is not None and not free:
            return True
        if _internal_comments(c, free):
            return True
    return False


def _tail_comment(node: Node) -> str | None:
    """The trailing comment at the end of ``node`` (the innermost one, when it moves out)."""
    while True:
        tok = last_tok(node)
        if tok.trailing is not None or isinstance(node, Atom) or not node.children:
            return tok.trailing
        node = node.children[-1]


def flat(node: Node) -> str:
    if isinstance(node, Atom):
        return node.tok.text
    if _head(node) in _TYPED:  # (:constants a b - sort  c - other): two spaces between groups
        head, *rest = node.children
        inner = "  ".join(_unit_flat(u) for u in _typed_units(rest))
        return node.open.text + flat(head) + (" " + inner if inner else "") + node.close.text
    return node.open.text + " ".join(flat(c) for c in node.children) + node.close.text


def _is_key(node: Node) -> bool:
    return isinstance(node, Atom) and node.tok.text.startswith(":")


def _head(node: Node) -> str | None:
    if isinstance(node, Group) and node.children and isinstance(node.children[0], Atom):
        return node.children[0].tok.text
    return None


def _units(children: list[Node]) -> list[Unit]:
    """``:key value`` pairs stay together, and so does a number with the name after it (a
    quantity, ``512 MB``: a broken list never splits it); everything else is a unit of its own."""
    units: list[Unit] = []
    i = 0
    while i < len(children):
        c = children[i]
        if (_is_key(c) or _is_number(c)) and i + 1 < len(children) and not _is_key(children[i + 1]):
            after = children[i + 1]
            if _is_number(c) and not (isinstance(after, Atom) and after.tok.kind == "NAME"):
                units.append([c])
                i += 1
                continue
            units.append([c, children[i + 1]])
            i += 2
        else:
            units.append([c])
            i += 1
    return units


def _is_number(node: Node) -> bool:
    return isinstance(node, Atom) and node.tok.kind == "NUMBER"


def _typed_units(children: list[Node]) -> list[Unit]:
    """``a b - sort c - (enum x y)`` → ``[a b - sort] [c - (enum x y)]``."""
    units: list[Unit] = []
    cur: Unit = []
    i = 0
    while i < len(children):
        c = children[i]
        cur.append(c)
        if isinstance(c, Atom) and c.tok.kind == "MINUS" and i + 1 < len(children):
            cur.append(children[i + 1])
            units.append(cur)
            cur = []
            i += 2
            continue
        i += 1
    if cur:
        units.append(cur)
    return units


def _unit_flat(unit: Unit) -> str:
    return " ".join(flat(n) for n in unit)


def _unit_has_comments(unit: Unit) -> bool:
    for i, n in enumerate(unit):
        if i > 0 and first_tok(n).leading:
            return True
        last = i == len(unit) - 1
        if not last and _tail_comment(n) is not None:
            return True
        if _internal_comments(n, last):
            return True
    return False


# ---------------------------------------------------------------- output


class Out:
    def __init__(self) -> None:
        self.lines: list[str] = [""]
        self.pending: str | None = None

    @property
    def col(self) -> int:
        return len(self.lines[-1])

    @property
    def at_line_start(self) -> bool:
        return not self.lines[-1].strip()

    def write(self, s: str) -> None:
        self.lines[-1] += s

    def flush(self) -> None:
        if self.pending is not None:
            self.write((" " if self.lines[-1].strip() else "") + self.pending)
            self.pending = None

    def nl(self, col: int, blank: bool = False) -> None:
        self.flush()
        self.lines[-1] = self.lines[-1].rstrip()
        if blank and self.lines[-1]:
            self.lines.append("")
        self.lines.append(" " * col)

    def sep(self) -> None:
        """A space before the next item on this line (a new line after a trailing comment)."""
        if self.pending is not None:
            col = self.col + 1
            self.nl(col)
        else:
            self.write(" ")

    def comments(self, tok: Tok, col: int) -> None:
        """Leading comments of ``tok``: each on its own line at ``col``."""
        if not tok.leading:
            return
        if not self.at_line_start or self.pending is not None:
            self.nl(col)
        elif self.col != col:
            self.lines[-1] = " " * col
        for c in tok.leading:
            if c.text:
                if c.blank_before and len(self.lines) > 1 and self.lines[-2] != "":
                    self.lines[-1] = ""
                    self.lines.append(" " * col)
                self.write(c.text)
            self.nl(col, blank=not c.text)

    def trailing(self, tok: Tok) -> None:
        if tok.trailing is not None:
            if self.pending is not None:
                self.flush()
            self.pending = tok.trailing

    def text(self) -> str:
        self.flush()
        out = "\n".join(line.rstrip() for line in self.lines).strip("\n")
        out = re.sub(r"\n{3,}", "\n\n", out)
        return out + "\n" if out else ""


# ---------------------------------------------------------------- layout
#
# ``tail`` is the number of columns that must follow a node on its last line: the closing
# brackets of the lists it ends.  A list stays on one line only when it fits with them.


def emit(node: Node, out: Out, tail: int = 0) -> None:
    """Print ``node`` starting at the current column (its leading comments already done)."""
    if isinstance(node, Atom):
        out.write(node.tok.text)
        out.trailing(node.tok)
        return
    head = _head(node)
    forced = head == "define" or head in _ALWAYS_BROKEN
    if not forced and not _internal_comments(node):
        text = flat(node)
        if out.col + len(text) + tail <= WIDTH:
            out.write(text)
            tail_comment = _tail_comment(node)
            if tail_comment is not None:
                out.trailing(Tok("", "", trailing=tail_comment))
            return
    _broken(node, out, head, tail)


def emit_unit(unit: Unit, out: Out, tail: int = 0) -> None:
    for i, n in enumerate(unit):
        if i:
            tok = first_tok(n)
            if tok.leading:
                out.comments(tok, out.col + 1 if out.pending is None else out.col)
            else:
                out.sep()
        emit(n, out, tail if i == len(unit) - 1 else 0)


def place(unit: Unit, out: Out, col: int, blank: bool = True, tail: int = 0) -> None:
    """Start ``unit`` on a new line at ``col`` (with its leading comments)."""
    tok = first_tok(unit[0])
    out.nl(col, blank=blank and tok.blank_before)
    out.comments(tok, col)
    emit_unit(unit, out, tail)


def inline(unit: Unit, out: Out, tail: int = 0) -> None:
    """Continue the current line with ``unit`` (a new line if a comment is in the way)."""
    tok = first_tok(unit[0])
    if tok.leading:
        out.comments(tok, out.col + 1 if out.pending is None else out.col)
    else:
        out.sep()
    emit_unit(unit, out, tail)


def start(unit: Unit, out: Out, col: int, tail: int = 0) -> None:
    """Print the first unit of a list right after the opening bracket (or at ``col`` on the
    next line when it has leading comments)."""
    if first_tok(unit[0]).leading:
        place(unit, out, col, blank=False, tail=tail)
    else:
        emit_unit(unit, out, tail)


def _flat_at(unit: Unit, col: int, tail: int) -> bool:
    """Whether ``unit`` prints on one line starting at ``col``."""
    return not _unit_has_comments(unit) and col + len(_unit_flat(unit)) + tail <= WIDTH


def _flow(units: list[Unit], out: Out, col: int, tail: int, after_broken: bool = False) -> None:
    """Fill: each unit on the current line when it fits there (with ``tail`` after the last
    one), otherwise on a new line at ``col``.  A comment or a blank line before a unit, a
    comment inside it, or a unit before it that took several lines also starts a new line."""
    for i, u in enumerate(units):
        t = tail if i == len(units) - 1 else 0
        tok = first_tok(u[0])
        if (
            after_broken
            or tok.leading
            or tok.blank_before
            or out.pending is not None
            or not _flat_at(u, out.col + 1, t)
        ):
            place(u, out, col, tail=t)
            after_broken = not _flat_at(u, col, t)
        else:
            inline(u, out, t)


def _lines(units: list[Unit], out: Out, col: int, tail: int) -> None:
    """One unit per line at ``col``."""
    for i, u in enumerate(units):
        place(u, out, col, tail=tail if i == len(units) - 1 else 0)


def _close(node: Group, out: Out, col: int) -> None:
    if node.close.leading:
        out.comments(node.close, col)
    elif out.pending is not None and node.close.trailing is not None:
        out.nl(col)
    out.write(node.close.text)
    out.trailing(node.close)


def _broken(node: Group, out: Out, head: str | None, tail: int) -> None:
    """Print ``node`` over several lines: the layout depends on what kind of list it is."""
    open_col = out.col
    out.write(node.open.text)
    out.trailing(node.open)
    if out.pending is not None:  # "( ; comment": the contents start on the next line
        out.nl(open_col + 1)
    inner = 0 if node.close.leading else tail + 1  # what follows the last child on its line
    if not node.children:
        _close(node, out, open_col + 1)
    elif head == "define" or head in _SECTIONS:
        _close(node, out, _section(node, out, head, open_col, inner))
    elif node.names:
        _close(node, out, _names(node, out, open_col, inner))
    elif isinstance(node.children[0], Atom) and not _is_key(node.children[0]):
        _close(node, out, _call(node, out, open_col, inner))
    else:
        # ((a b) (c d)) or (:key v :key v): everything aligned after the parenthesis
        units = _units(node.children)
        start(units[0], out, open_col + 1, inner if len(units) == 1 else 0)
        _lines(units[1:], out, open_col + 1, inner)
        _close(node, out, open_col + 1)


def _call(node: Group, out: Out, open_col: int, inner: int) -> int:
    """``(op first-arg`` with the other arguments aligned under the first; returns the
    column of the closing parenthesis's comments."""
    first, *rest = node.children
    start([first], out, open_col + 1)
    units = _units(rest)
    if not units:
        return open_col + 1
    if first_tok(units[0][0]).leading:
        align = open_col + 2
        place(units[0], out, align, blank=False, tail=inner if len(units) == 1 else 0)
    else:
        out.sep()
        align = out.col
        emit_unit(units[0], out, inner if len(units) == 1 else 0)
    _lines(units[1:], out, align, inner)
    return align


def _names(node: Group, out: Out, open_col: int, inner: int) -> int:
    """A list of names or values -- ``{a b c}``, ``:keep (a b c)``, ``(enum a b c)`` -- filled
    line by line, continued under its first element."""
    units: list[Unit] = [[c] for c in node.children]
    first = units[0][0]
    if isinstance(first, Atom) and first.tok.kind == "_ENUM_WORD":
        start(units[0], out, open_col + 1, inner if len(units) == 1 else 0)
        return _fill(units[1:], out, open_col + 2, inner)
    t = inner if len(units) == 1 else 0
    start(units[0], out, open_col + 1, t)
    _flow(units[1:], out, open_col + 1, inner, after_broken=not _flat_at(units[0], open_col + 1, t))
    return open_col + 1


def _section_head(node: Group, head: str | None) -> int:
    """How many children stay on the first line: ``(define (domain d)``, ``(:morphism m``,
    ``(:metric lex``; one for the sections whose arguments are all alike."""
    children = node.children
    if head == "define":
        return 2
    second = children[1] if len(children) > 1 else None
    if (
        isinstance(second, Atom)
        and not _is_key(second)
        and second.tok.kind != "MINUS"
        and head not in _TYPED
        and head not in _FILL
    ):
        return 2
    return 1


def _section(node: Group, out: Out, head: str | None, open_col: int, inner: int) -> int:
    """``(define ...)`` and ``(:section ...)``: a head on the first line, the rest in a block
    two columns in; returns the column of the closing parenthesis's comments."""
    block = open_col + 2
    n_head = _section_head(node, head)
    rest = node.children[n_head:]
    start(node.children[:n_head], out, open_col + 1, 0 if rest else inner)
    if not rest:
        return block
    if head in _FILL:
        return _fill(_units(rest), out, block, inner)
    if head in _TYPED:
        _typed(_typed_units(rest), out, block, inner)
    elif head == "define":
        _lines([[c] for c in rest], out, block, inner)
    elif head == ":morphism":
        _options(_units(rest), out, block, inner)
    else:
        units = _units(rest)
        if len(units) == 1 and head not in _ALWAYS_BROKEN:
            inline(units[0], out, inner)
        else:
            _lines(units, out, block, inner)
    return block


def _fill(units: list[Unit], out: Out, block: int, inner: int) -> int:
    """``(:init a b`` filled line by line, continued under the first unit (at ``block`` when
    a comment is in the way); returns the continuation column."""
    if not units:
        return block
    t = inner if len(units) == 1 else 0
    if first_tok(units[0][0]).leading or out.pending is not None:
        col = block
        place(units[0], out, col, blank=False, tail=t)
    else:
        col = out.col + 1
        inline(units[0], out, t)
    _flow(units[1:], out, col, inner, after_broken=not _flat_at(units[0], col, t))
    return col


def _typed(units: list[Unit], out: Out, block: int, inner: int) -> None:
    """``names - sort`` groups one per line; a group too long for one line is filled, its
    continuation lines two columns further in (the ``- sort`` stays with the last name)."""
    for i, u in enumerate(units):
        t = inner if i == len(units) - 1 else 0
        words: list[Unit] = [[n] for n in u]
        if len(u) >= 3 and isinstance(u[-2], Atom) and u[-2].tok.kind == "MINUS":
            words = [[n] for n in u[:-3]] + [u[-3:]]
        t0 = t if len(words) == 1 else 0
        place(words[0], out, block, tail=t0)
        _flow(words[1:], out, block + 2, t, after_broken=not _flat_at(words[0], block, t0))


def _is_scalar_option(unit: Unit) -> bool:
    """``:kind k``, ``:churn n``, ``:uses n``, ``:cost n``: a morphism's short options."""
    return (
        len(unit) == 2
        and isinstance(unit[0], Atom)
        and unit[0].tok.text in _SCALAR_OPTIONS
        and isinstance(unit[1], Atom)
    )


def _options(units: list[Unit], out: Out, block: int, inner: int) -> None:
    """A morphism's options one per line, except that consecutive short options share a line
    (filled): ``:kind hardware :churn 1 :uses 1 :cost 150``."""
    i = 0
    while i < len(units):
        j = i + 1
        if _is_scalar_option(units[i]):
            while j < len(units) and _is_scalar_option(units[j]):
                j += 1
        t = inner if j == len(units) else 0
        t0 = t if j == i + 1 else 0
        place(units[i], out, block, tail=t0)
        _flow(units[i + 1 : j], out, block, t, after_broken=not _flat_at(units[i], block, t0))
        i = j


def format_text(text: str) -> str:
    """The canonical layout of ``text`` (which must tokenize; parse it first for diagnostics)."""
    toks, end = scan(text)
    nodes = tree(toks)
    out = Out()
    for i, node in enumerate(nodes):
        tok = first_tok(node)
        if i == 0:
            out.comments(tok, 0)
        else:
            out.nl(0, blank=True)
            if tok.leading:
                tok.leading[0].blank_before = True
            out.comments(tok, 0)
        emit(node, out)
    if end.leading:
        comments = [c for c in end.leading if c.text]
        if comments:
            if nodes:
                out.nl(0, blank=end.blank_before)
            end.leading = comments
            out.comments(end, 0)
    result = out.text()
    _verify(text, result)
    return result


def _signature(text: str) -> tuple[list[tuple[str, str]], list[str]]:
    toks, end = scan(text)
    pairs = [(t.kind, t.text) for t in toks]
    comments: list[str] = []
    for t in [*toks, end]:
        comments.extend(c.text for c in t.leading if c.text)
        if t.trailing is not None:
            comments.append(t.trailing)
    return pairs, comments


def _verify(before: str, after: str) -> None:
    b_toks, b_comments = _signature(before)
    a_toks, a_comments = _signature(after)
    if b_toks != a_toks:
        raise FormatError("catc fmt changed the tokens of the file (a bug: please report it)")
    if b_comments != a_comments:
        raise FormatError("catc fmt lost or changed a comment (a bug: please report it)")


# ---------------------------------------------------------------- the command


def format_file(path: str, diags: Diagnostics) -> tuple[str, str] | None:
    """(original text, formatted text), or None (diagnostics reported) for bad input."""
    from catgrammar.parser import parse_source, read_source

    src = read_source(path, diags)
    if src is None:
        return None
    if parse_source(src, diags) is None:
        return None
    with open(path, "rb") as fh:
        raw = fh.read().decode("utf-8")
    return raw, format_text(src.text)
