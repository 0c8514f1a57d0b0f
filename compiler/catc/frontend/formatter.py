"""``catc fmt``: one canonical layout for .cat files.

The formatter works on the token stream, not on the AST: it only ever changes the
whitespace between tokens, so the meaning cannot change (numbers, strings and names keep
their exact text).  Comments, which the tokenizer skips, are recovered from the gaps between
tokens: a comment on the same line as the token before it stays at the end of that line
(*trailing*); any other comment is printed on its own line before the next token (*leading*).
Single blank lines between the items of a broken list are kept.

Layout:

* 2-space indentation; ``(define ...)`` lists one section per line and ``(:morphism ...)``
  one option per line; ``(:resources ...)`` one resource per line;
* other lists stay on one line when they fit in :data:`WIDTH` columns and hold no comment;
  otherwise they break, PDDL style: ``(and (a ...)`` with the other arguments aligned under
  the first, ``:key value`` pairs kept together, ``(:init ...)`` filled line by line and
  typed lists (``a b - sort``) one group per line.

Formatting is idempotent, and :func:`format_text` checks its own output: the tokens and the
comments must come back identical, or it raises :class:`FormatError`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from catgrammar.symbols import Section
from catgrammar.tokens import tokenize

WIDTH = 100

_SECTIONS = frozenset(s.value for s in Section)
_TYPED = frozenset({":sorts", ":constants", ":objects"})
_FILL = frozenset({":init", ":requirements", ":import", ":deployed"})
_ALWAYS_BROKEN = frozenset({":morphism", ":resources"})
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
    children: list
    close: Tok


# ---------------------------------------------------------------- tokens + comments


def _blank(gap: str) -> bool:
    return gap.count("\n") >= 2


def scan(text: str) -> tuple[list[Tok], Tok]:
    """Tokens with their comments attached, and an end-of-file token holding the comments
    after the last token."""
    toks: list[Tok] = []
    pos = 0
    raw = list(tokenize(text)) + [None]
    for t in raw:
        start = t.start_pos if t is not None else len(text)
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
        if t is not None:
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
        comments = [t.trailing for t in run if t.trailing is not None]
        if len(run) > 1 and comments:
            for t in run:
                t.trailing = None
            for t, c in zip(run[len(run) - len(comments) :], comments):
                t.trailing = c
        i = j
    return toks[:-1], toks[-1]


def tree(toks: list[Tok]) -> list:
    stack: list[list] = [[]]
    opens: list[Tok] = []
    for tok in toks:
        if tok.kind in ("LPAR", "LBRACE"):
            stack.append([])
            opens.append(tok)
        elif tok.kind in ("RPAR", "RBRACE"):
            children = stack.pop()
            stack[-1].append(Group(opens.pop(), children, tok))
        else:
            stack[-1].append(Atom(tok))
    if len(stack) != 1:  # pragma: no cover - the parser rejects unbalanced input first
        raise FormatError("unbalanced parentheses")
    return stack[0]


# ---------------------------------------------------------------- helpers on nodes


def first_tok(node) -> Tok:
    return node.tok if isinstance(node, Atom) else node.open


def last_tok(node) -> Tok:
    return node.tok if isinstance(node, Atom) else node.close


def _internal_comments(node, tail_free: bool = True) -> bool:
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


def _tail_comment(node) -> str | None:
    """The trailing comment at the end of ``node`` (the innermost one, when it moves out)."""
    while True:
        tok = last_tok(node)
        if tok.trailing is not None or isinstance(node, Atom) or not node.children:
            return tok.trailing
        node = node.children[-1]


def flat(node) -> str:
    if isinstance(node, Atom):
        return node.tok.text
    if _head(node) in _TYPED:  # (:constants a b - sort  c - other): two spaces between groups
        head, *rest = node.children
        inner = "  ".join(_unit_flat(u) for u in _typed_units(rest))
        return node.open.text + flat(head) + (" " + inner if inner else "") + node.close.text
    return node.open.text + " ".join(flat(c) for c in node.children) + node.close.text


def _is_key(node) -> bool:
    return isinstance(node, Atom) and node.tok.text.startswith(":")


def _head(node) -> str | None:
    if isinstance(node, Group) and node.children and isinstance(node.children[0], Atom):
        return node.children[0].tok.text
    return None


def _units(children: list) -> list[list]:
    """``:key value`` pairs stay together; everything else is a unit of its own."""
    units: list[list] = []
    i = 0
    while i < len(children):
        c = children[i]
        if _is_key(c) and i + 1 < len(children) and not _is_key(children[i + 1]):
            units.append([c, children[i + 1]])
            i += 2
        else:
            units.append([c])
            i += 1
    return units


def _typed_units(children: list) -> list[list]:
    """``a b - sort c - (enum x y)`` → ``[a b - sort] [c - (enum x y)]``."""
    units: list[list] = []
    cur: list = []
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


def _unit_flat(unit: list) -> str:
    return " ".join(flat(n) for n in unit)


def _unit_has_comments(unit: list) -> bool:
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


def emit(node, out: Out) -> None:
    """Print ``node`` starting at the current column (its leading comments already done)."""
    if isinstance(node, Atom):
        out.write(node.tok.text)
        out.trailing(node.tok)
        return
    head = _head(node)
    forced = head == "define" or head in _ALWAYS_BROKEN
    if not forced and not _internal_comments(node):
        text = flat(node)
        if out.col + len(text) <= WIDTH:
            out.write(text)
            tail = _tail_comment(node)
            if tail is not None:
                out.trailing(Tok("", "", trailing=tail))
            return
    _broken(node, out, head)


def emit_unit(unit: list, out: Out) -> None:
    for i, n in enumerate(unit):
        if i:
            tok = first_tok(n)
            if tok.leading:
                out.comments(tok, out.col + 1 if out.pending is None else out.col)
            else:
                out.sep()
        emit(n, out)


def place(unit: list, out: Out, col: int, blank: bool = True) -> None:
    """Start ``unit`` on a new line at ``col`` (with its leading comments)."""
    tok = first_tok(unit[0])
    out.nl(col, blank=blank and tok.blank_before)
    out.comments(tok, col)
    emit_unit(unit, out)


def inline(unit: list, out: Out) -> None:
    """Continue the current line with ``unit`` (a new line if a comment is in the way)."""
    tok = first_tok(unit[0])
    if tok.leading:
        out.comments(tok, out.col + 1 if out.pending is None else out.col)
    else:
        out.sep()
    emit_unit(unit, out)


def _close(node: Group, out: Out, col: int) -> None:
    if node.close.leading:
        out.comments(node.close, col)
    elif out.pending is not None and node.close.trailing is not None:
        out.nl(col)
    out.write(node.close.text)
    out.trailing(node.close)


def _broken(node: Group, out: Out, head: str | None) -> None:
    open_col = out.col
    out.write(node.open.text)
    out.trailing(node.open)
    if out.pending is not None:  # "( ; comment": the contents start on the next line
        out.nl(open_col + 1)
    children = node.children
    if not children:
        _close(node, out, open_col + 1)
        return
    block = open_col + 2
    if head == "define" or head in _SECTIONS:
        # (define (domain x) ...) / (:section [name] ...): the rest in a block, one per line
        n_head = 1
        if head == "define" or (
            len(children) > 1
            and isinstance(children[1], Atom)
            and not _is_key(children[1])
            and children[1].tok.kind != "MINUS"
            and head not in _TYPED
            and head not in _FILL
        ):
            n_head = 2
        emit_unit(children[:n_head], out) if not first_tok(children[0]).leading else place(
            children[:n_head], out, open_col + 1, blank=False
        )
        rest = children[n_head:]
        if head in _TYPED:
            units = _typed_units(rest)
        elif head == "define":
            units = [[c] for c in rest]
        else:
            units = _units(rest)
        if head in _FILL:
            _fill(units, out, block)
        elif len(units) == 1 and head != "define" and head not in _ALWAYS_BROKEN:
            inline(units[0], out)
        else:
            for u in units:
                place(u, out, block)
        _close(node, out, block)
        return
    first = children[0]
    if isinstance(first, Atom) and not _is_key(first):
        # (op first-arg
        #     other-args...)
        if first.tok.leading:
            place([first], out, open_col + 1, blank=False)
        else:
            emit(first, out)
        units = _units(children[1:])
        if not units:
            _close(node, out, open_col + 1)
            return
        out.sep() if not first_tok(units[0][0]).leading else None
        align = out.col
        if first_tok(units[0][0]).leading:
            align = open_col + 2
            place(units[0], out, align, blank=False)
        else:
            emit_unit(units[0], out)
        for u in units[1:]:
            place(u, out, align)
        _close(node, out, align)
        return
    # ((a b) (c d)) or (:key v :key v): everything aligned after the parenthesis
    units = _units(children)
    align = open_col + 1
    if first_tok(units[0][0]).leading:
        place(units[0], out, align, blank=False)
    else:
        emit_unit(units[0], out)
    for u in units[1:]:
        place(u, out, align)
    _close(node, out, align)


def _fill(units: list[list], out: Out, block: int) -> None:
    """As many units per line as fit (a unit that cannot fit starts its own line)."""
    if not units:
        return
    fits_inline = all(not _unit_has_comments(u) for u in units) and not first_tok(units[0][0]).leading
    text = " ".join(_unit_flat(u) for u in units)
    if fits_inline and out.col + 1 + len(text) <= WIDTH and out.pending is None:
        for u in units:
            inline(u, out)
        return
    place(units[0], out, block)
    for u in units[1:]:
        tok = first_tok(u[0])
        if (
            tok.leading
            or tok.blank_before
            or out.pending is not None
            or _unit_has_comments(u)
            or out.col + 1 + len(_unit_flat(u)) > WIDTH
        ):
            place(u, out, block)
        else:
            inline(u, out)


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


def format_file(path: str, diags) -> tuple[str, str] | None:
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
