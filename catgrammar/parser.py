"""Text → AST.

``parse_source`` never raises on bad input: it reports located diagnostics and returns
``None`` when no tree could be built.  Three guards run before the parser sees the text, so
that every later stage can recurse safely and every message can point at the real culprit:

* reading only regular files (a FIFO or a device is never read: it could block or never
  end), the size of the input, and decoding (binary / non-UTF-8 files) in :func:`read_source`;
* a parenthesis scan that reports an unmatched ``)`` or an unclosed ``(`` precisely and
  rejects nesting deeper than the nesting limit;
* the number of tokens, and numeric literals longer than the literal-digits limit.

The limits are those in force (:mod:`catgrammar.limits`).

The parser is the LALR(1) automaton of ``cat.lark`` as computed by Lark, but run by
:mod:`catgrammar._lalr` from pre-generated tables: importing Lark costs ~40 ms per process,
which is most of a small ``catc solve``.  Regenerate the tables after editing the grammar
with ``python -m catgrammar.build_parser``.
"""

from __future__ import annotations

import errno
import os
import re
import stat
import unicodedata
from collections.abc import Callable, Iterator
from fractions import Fraction
from typing import Any

from catgrammar import ast, codes, limits
from catgrammar._lalr import Parser, Token, UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken
from catgrammar.diagnostics import Diagnostics, Fix, Note, Suggestion
from catgrammar.span import Source, Span
from catgrammar.symbols import Option, Section
from catgrammar.tokens import TERMINAL_TEXT, TooManyTokens, tokenize

# ---------------------------------------------------------------- reading


def decode_source(path: str, data: bytes, diags: Diagnostics) -> Source | None:
    """Bytes → :class:`Source`, or a located diagnostic for binary or non-UTF-8 input."""
    if b"\x00" in data:
        offset = data.index(b"\x00")
        src = Source(path, data[:offset].decode("utf-8", errors="replace"))
        diags.report(
            codes.BINARY_FILE, "binary file: found a NUL byte; .cat files are UTF-8 text", src.span(offset, offset)
        )
        return None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        src = Source(path, data[: exc.start].decode("utf-8", errors="replace"))
        diags.report(
            codes.INVALID_UTF8,
            f"invalid UTF-8: byte 0x{data[exc.start]:02x} cannot start or continue a character",
            src.span(len(src.text), len(src.text) + 1),
        )
        return None
    if text.startswith("\ufeff"):
        text = text[1:]
    return Source(path, text)


class NotRegularFile(OSError):
    """A path that names a FIFO, a device or a socket: reading it could block or never end,
    so it is never read."""


def read_regular(path: str, limit: int | None = None) -> bytes:
    """The bytes of the regular file ``path`` (at most ``limit + 1`` of them, so that a caller
    can tell a file past its limit).  Opened without blocking and checked on the open
    descriptor, so a FIFO, ``/dev/zero`` or a link to either raises :class:`NotRegularFile`
    instead of hanging."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0))
    with os.fdopen(fd, "rb") as fh:
        mode = os.fstat(fd).st_mode
        if stat.S_ISDIR(mode):
            raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR), path)
        if not stat.S_ISREG(mode):
            raise NotRegularFile(f"not a regular file: {path}")
        return fh.read() if limit is None else fh.read(limit + 1)


def read_source(path: str, diags: Diagnostics) -> Source | None:
    """The text of the file ``path`` (never more than the input-bytes limit is read)."""
    most = limits.current().input_bytes
    try:
        data = read_regular(path, most)
    except NotRegularFile:
        diags.report(codes.UNREADABLE_FILE, f"cannot read '{path}': not a regular file (a FIFO or a device)", None)
        return None
    except OSError as exc:
        diags.report(codes.UNREADABLE_FILE, f"cannot read '{path}': {exc.strerror or exc}", None)
        return None
    if len(data) > most:
        _too_large(path, data, most, diags)
        return None
    return decode_source(path, data, diags)


def _too_large(path: str, data: bytes, most: int, diags: Diagnostics) -> None:
    """E1101 at the first character past the input-bytes limit."""
    head = data[:most].decode("utf-8", errors="ignore")
    src = Source(path, head)
    diags.add_source(src)
    limit = limits.BY_NAME["input-bytes"]
    diags.report(
        limit.code,
        f"the file is larger than the input-bytes limit ({limits.count_text(most)} bytes; it is read no further); "
        f"{limit.how_to_raise}",
        src.span(len(head), len(head)),
    )


# ---------------------------------------------------------------- the parenthesis scan

_SCAN = re.compile(r'[()]|;[^\n]*|"(?:[^"\\\n]|\\.)*(?P<close>")?')


def scan_parentheses(src: Source, diags: Diagnostics) -> bool:
    """Report unmatched/unclosed parentheses and excessive depth.  True when clean."""
    stack: list[int] = []
    deepest = limits.current().nesting
    for m in _SCAN.finditer(src.text):
        tok = m.group()
        if tok[0] == '"' and m.group("close") is None:
            diags.report(
                codes.BAD_CHARACTER,
                "unterminated string: a string must close on the line it opens",
                src.span(m.start()),
            )
            return False
        if tok == "(":
            stack.append(m.start())
            if len(stack) > deepest:
                diags.report(
                    codes.TOO_DEEP,
                    f"parentheses nest more than {deepest} deep (the nesting limit); split the expression, or "
                    f"{limits.BY_NAME['nesting'].how_to_raise}",
                    src.span(m.start()),
                )
                return False
        elif tok == ")":
            if not stack:
                diags.report(codes.UNBALANCED_CLOSE, "unmatched ')': there is no '(' to close", src.span(m.start()))
                return False
            stack.pop()
    if stack:
        opener = stack[0]
        inner = stack[-1]
        open_text = f"{len(stack)} parenthes{'is' if len(stack) == 1 else 'es'} open"
        likely = likely_missing_close(src.text)
        if likely is not None:
            at, line_no, form = likely
            form_line, form_column = src.position(form)
            notes = [Note("this '(' is still open where the indentation says its form has ended", src.span(form))]
            if form != opener:
                notes.append(Note(f"the file ends with {open_text}; the outermost is here", src.span(opener)))
            diags.report(
                codes.UNCLOSED_PAREN,
                f"'(' is never closed: a ')' is probably missing here — line {line_no} is indented no deeper "
                f"than the '(' at {form_line}:{form_column}, which is still open there",
                src.span(at),
                *notes,
            )
            return False
        notes = []
        if inner != opener:
            notes.append(Note("the innermost '(' still open at the end of the file is here", src.span(inner)))
        diags.report(
            codes.UNCLOSED_PAREN,
            f"'(' is never closed: the file ends with {open_text}",
            src.span(opener),
            *notes,
        )
        return False
    return True


def likely_missing_close(text: str) -> tuple[int, int, int] | None:
    """Where a dropped ')' most likely belongs, read from the layout (as Python and rustc
    do for unclosed delimiters): the first line that does not start with ')' and is indented
    no deeper than the line of a '(' opened on an earlier line and still open.  Returns the
    offset just after the last code on the line before it (where the ')' goes), that line's
    number (1-based) and the offset of the innermost such '(' — or None when the layout
    says nothing (every line indented deeper than the forms open around it).  Only asked
    once the file is known to leave a '(' open; strings and comments end on their line."""
    stack: list[tuple[int, int]] = []  # (offset of the '(', its column)
    offset = 0
    previous_end: int | None = None  # just after the last code of the previous code line
    for line_no, line in enumerate(text.split("\n"), 1):
        start, offset = offset, offset + len(line) + 1
        code = line
        for m in _SCAN.finditer(line):
            if m.group().startswith(";"):
                code = line[: m.start()]
                break
        stripped = code.lstrip(" \t")
        if not stripped.strip():
            continue
        indent = len(code) - len(stripped)
        if not stripped.startswith(")") and previous_end is not None:
            deeper = [o for o, i in stack if i >= indent]
            if deeper:
                return previous_end, line_no, deeper[-1]
        for m in _SCAN.finditer(code):
            if m.group() == "(":
                stack.append((start + m.start(), m.start()))
            elif m.group() == ")" and stack:
                stack.pop()
        previous_end = start + len(code.rstrip())
    return None


# ---------------------------------------------------------------- syntax errors

_KEYWORDS = {s.value for s in Section} | {o.value for o in Option}


def _describe(parser: Parser, terminal: str) -> str:
    return TERMINAL_TEXT.get(terminal, terminal)


def _expected_text(parser: Parser, expected: set[str]) -> str:
    words = sorted({_describe(parser, t) for t in expected})
    if len(words) > 12:
        keywords = [w for w in words if w.startswith("':")]
        others = [w for w in words if not w.startswith("':")]
        words = others + ([f"a keyword ({', '.join(keywords[:10])}, ...)"] if keywords else [])
    return words[0] if len(words) == 1 else ", ".join(words[:-1]) + " or " + words[-1]


def _keywords_in(parser: Parser, expected: set[str]) -> list[str]:
    out = []
    for t in expected:
        d = _describe(parser, t)
        if d.startswith("':"):
            out.append(d.strip("'"))
    return out


_WORD = re.compile(r":?[A-Za-z_][A-Za-z0-9_-]*|[^\sA-Za-z0-9_]")


def _report_syntax(exc: UnexpectedInput, src: Source, parser: Parser, diags: Diagnostics) -> None:
    pos = getattr(exc, "pos_in_stream", None) or 0
    if isinstance(exc, UnexpectedToken):
        tok = exc.token
        if tok.type == "$END":
            diags.report(codes.UNCLOSED_PAREN, "unexpected end of file", src.span(len(src.text), len(src.text)))
            return
        pos = tok.start_pos if tok.start_pos is not None else pos
        text = str(tok)
        expected = set(exc.expected)
    elif isinstance(exc, UnexpectedCharacters):
        m = _WORD.match(src.text, pos)
        text = m.group() if m else src.text[pos : pos + 1]
        expected = set(exc.allowed or ())
    elif isinstance(exc, UnexpectedEOF):  # pragma: no cover - LALR reports the end as a $END token
        diags.report(codes.UNCLOSED_PAREN, "unexpected end of file", src.span(len(src.text), len(src.text)))
        return
    else:  # pragma: no cover - there are no other kinds
        diags.report(codes.SYNTAX, str(exc).splitlines()[0], src.span(pos))
        return

    span = src.span(pos, pos + max(1, len(text)))
    keywords = _keywords_in(parser, expected)
    fixes: tuple[Fix, ...] = ()
    if text.startswith(":") and len(text) > 1:
        if text in _KEYWORDS and keywords:
            msg = f"'{text}' is not allowed here; expected {_expected_text(parser, expected)}"
        elif keywords:
            suggestion = Suggestion(text, keywords, span)
            fixes = suggestion.fixes
            msg = f"unknown keyword '{text}'{suggestion.hint}"
            if not suggestion.hint:
                msg += f"; expected {_expected_text(parser, expected)}"
        else:
            msg = f"unexpected keyword '{text}'; expected {_expected_text(parser, expected)}"
        diags.report(codes.UNKNOWN_SECTION, msg, span, fixes=fixes)
        return
    if isinstance(exc, UnexpectedCharacters):
        if text.startswith('"'):
            diags.report(codes.BAD_CHARACTER, "unterminated string: a string must close on the line it opens", span)
        elif not text[:1].isascii() and (text[:1].isdigit() or text[:1].isnumeric()):  # issue 28
            ch = text[:1]
            name = unicodedata.name(ch, f"U+{ord(ch):04X}")
            message = f"{ch!r} ({name}) is not a digit of a number: numbers are written with the ASCII digits 0-9"
            diags.report(codes.BAD_CHARACTER, message, src.span(pos, pos + 1))
        elif text[:1] in "0123456789+-.":
            m = re.match(r"[+\-.\w]+", src.text[pos:])
            bad = m.group() if m else text
            diags.report(codes.BAD_CHARACTER, f"malformed number '{bad}'", src.span(pos, pos + len(bad)))
        else:
            diags.report(codes.BAD_CHARACTER, f"unexpected character {text!r}", span)
        return
    what = "')'" if text == ")" else "'('" if text == "(" else f"'{text}'"
    msg = f"unexpected {what}; expected {_expected_text(parser, expected)}"
    if keywords and text not in ("(", ")"):
        suggestion = Suggestion(":" + text, keywords, span)
        if suggestion.hint:
            msg += f" (keywords start with ':'{suggestion.hint})"
            fixes = suggestion.fixes
    diags.report(codes.SYNTAX, msg, span, fixes=fixes)


# ---------------------------------------------------------------- tree → AST


_PUNCT = frozenset({"LPAR", "RPAR", "LBRACE", "RBRACE"})


class _Builder:
    """Parse-tree callbacks → :mod:`catgrammar.ast`, run *inside* the LALR parser.

    No parse tree is ever built: each callback (named after its rule or alias in
    ``cat.lark``, Lark's ``Transformer`` convention) receives its children (tokens and AST
    nodes) and returns an AST node.  A node's span runs from its first to its last token;
    parentheses and option keywords are kept as tokens for exactly that reason and
    dropped here.  One builder (and one :class:`Parser`, about 0.2 ms to make) serves one
    parse: nothing is shared between parses, so threads may parse at once.
    """

    def __init__(self, src: Source | None = None, diags: Diagnostics | None = None) -> None:
        # None only in a builder that never parses (one made to check the callbacks)
        self.src: Source = src  # type: ignore[assignment]
        self.diags: Diagnostics = diags  # type: ignore[assignment]
        self.max_digits = limits.current().literal_digits

    # -- helpers
    def _tok_span(self, tok: Token) -> Span:
        # ignored: tokenize() gives every token its position (None only in Lark's signature)
        return Span(self.src.path, tok.line, tok.column, tok.end_line, tok.end_column, tok.start_pos, tok.end_pos)  # type: ignore[arg-type]

    def _span_of(self, item: Any) -> Span | None:
        if isinstance(item, Token):
            return self._tok_span(item)
        if isinstance(item, tuple):
            # ignored: the first and last item of a group are tokens or nodes, with spans
            return self._span_of(item[0]).cover(self._span_of(item[-1])) if item else None  # type: ignore[union-attr, arg-type]
        return getattr(item, "span", None)

    def _group_span(self, names: tuple[Any, ...]) -> Span:
        """The span of an untyped group of names (never empty: the grammar wants one)."""
        span = self._span_of(names)
        assert span is not None
        return span

    def _split(self, children: list) -> tuple[Span, list]:
        """(span of all children, children without punctuation and keyword tokens)."""
        spans = (
            [s for s in (self._span_of(c) for c in (children[0], children[-1])) if s is not None] if children else []
        )
        span = spans[0].cover(spans[-1]) if spans else self.src.span(0, 0)
        payload = [c for c in children if not (isinstance(c, Token) and (c.type in _PUNCT or c.type.endswith("_KW")))]
        return span, payload

    def _name(self, tok: Token) -> ast.Name:
        return ast.Name(str(tok), self._tok_span(tok))

    def _num(self, tok: Token) -> ast.Num:
        text = str(tok)
        span = self._tok_span(tok)
        digits = sum(c.isdigit() for c in text)
        exponent = _EXPONENT.search(text)
        most = self.max_digits
        if digits > most:
            problem = f"has {digits} digits"
        elif exponent and abs(int(exponent.group(1)[:8])) > most:
            problem = f"has an exponent of {exponent.group(1)}"
        else:
            return ast.Num(Fraction(text), text, span)
        self.diags.report(
            codes.LITERAL_TOO_LONG,
            f"numeric literal {problem}; at most {most} digits are supported (the literal-digits limit; "
            f"{limits.BY_NAME['literal-digits'].how_to_raise})",
            span,
        )
        return ast.Num(Fraction(0), "0", span)

    def _names(self, items: list) -> tuple[ast.Name, ...]:
        return tuple(self._name(c) for c in items if isinstance(c, Token) and c.type == "NAME")

    def _as_type(self, node) -> ast.TypeExpr:
        if isinstance(node, Token):
            name = self._name(node)
            return ast.TypeName(name, name.span)
        return node

    # -- file
    def start(self, children):
        return tuple(children)

    def domain(self, children):
        span, (name, *sections) = self._split(children)
        return ast.Domain(self._name(name), tuple(sections), span)

    def problem(self, children):
        span, (name, *sections) = self._split(children)
        return ast.Problem(self._name(name), tuple(sections), span)

    # -- domain sections
    def requirements(self, children):
        span, flags = self._split(children)
        return ast.Requirements(tuple(self._name(c) for c in flags), span)

    def imports(self, children):
        span, names = self._split(children)
        return ast.Imports(self._names(names), span)

    def name_list(self, children):
        return self._names(children)

    def enum_spec(self, children):
        span, names = self._split(children)
        return ast.EnumSpec(self._names(names), span)

    def sort_group(self, children):
        span, (names, _dash, parent) = self._split(children)
        if isinstance(parent, Token):
            parent = self._name(parent)
        return ast.SortGroup(names, parent, span)

    def sorts(self, children):
        span, items = self._split(children)
        groups = [
            ast.SortGroup(c, None, self._group_span(c)) if isinstance(c, tuple) else c  # untyped tail
            for c in items
        ]
        return ast.Sorts(tuple(groups), span)

    def typed_group(self, children):
        span, (names, _dash, sort) = self._split(children)
        return ast.TypedGroup(names, self._name(sort), span)

    def typed_names(self, children):
        return tuple(ast.TypedGroup(c, None, self._group_span(c)) if isinstance(c, tuple) else c for c in children)

    def constants(self, children):
        span, items = self._split(children)
        return ast.Constants(items[0] if items else (), span)

    def objects(self, children):
        span, items = self._split(children)
        return ast.Objects(items[0] if items else (), span)

    def resources(self, children):
        span, items = self._split(children)
        return ast.Resources(tuple(items), span)

    def set_type(self, children):
        span, (elem,) = self._split(children)
        return ast.SetType(self._name(elem), span)

    def resource(self, children):
        span, (name, type_, *options) = self._split(children)
        return ast.ResourceDecl(self._name(name), self._as_type(type_), tuple(options), span)

    def parameter(self, children):
        span, (name, type_, *options) = self._split(children)
        return ast.ParameterDecl(self._name(name), self._as_type(type_), tuple(options), span)

    def parameters(self, children):
        span, params = self._split(children)
        return ast.Opt(Option.PARAMETERS.value, tuple(params), span)

    def bound(self, children):
        (tok,) = children
        return None if tok.type == "STAR" else self._num(tok)

    def bounds(self, children):
        span, (lower, upper) = self._split(children)
        return ast.Bounds(lower, upper, span)

    @staticmethod
    def _opt(key: str, kind: str) -> Callable[[_Builder, list[Any]], ast.Opt]:
        def callback(self: _Builder, children: list[Any]) -> ast.Opt:
            span, payload = self._split(children)
            value: object
            if kind == "flag":
                value = True
            else:
                (item,) = payload  # a token, or a node for kind "node"
                if kind == "name":
                    value = self._name(item)
                elif kind == "number":
                    value = self._num(item)
                elif kind == "string":
                    value = self._name(item) if item.type == "NAME" else ast.Name(_unquote(item), self._tok_span(item))
                else:
                    value = item
            return ast.Opt(key, value, span)

        return callback

    group = _opt(Option.GROUP.value, "name")
    unit = _opt(Option.UNIT.value, "string")
    bounds_option = _opt(Option.BOUNDS.value, "node")
    doc = _opt(Option.DOC.value, "string")
    kind = _opt(Option.KIND.value, "name")
    churn = _opt(Option.CHURN.value, "number")
    uses = _opt(Option.USES.value, "number")
    cost = _opt(Option.COST.value, "node")
    precondition = _opt(Option.PRECONDITION.value, "node")
    effect = _opt(Option.EFFECT.value, "node")
    fixed = _opt(Option.FIXED.value, "flag")
    hole_view = _opt(Option.HOLE_VIEW.value, "name")
    max_effects = _opt(Option.MAX_EFFECTS.value, "number")
    max_preconditions = _opt(Option.MAX_PRECONDITIONS.value, "number")
    weight = _opt(Option.WEIGHT.value, "number")
    del _opt

    # -- grounding
    def datum_name(self, children: list[Any]) -> ast.Name:
        return self._name(children[0])

    def datum_number(self, children: list[Any]) -> ast.Num:
        return self._num(children[0])

    def datum_string(self, children: list[Any]) -> ast.Str:
        return ast.Str(_unquote(children[0]), self._tok_span(children[0]))

    def datum_list(self, children: list[Any]) -> ast.DatumList:
        span, items = self._split(children)
        return ast.DatumList(tuple(items), span)

    def ground_pair(self, children: list[Any]) -> ast.Opt:
        key, value = children
        return ast.Opt(str(key), value, self._tok_span(key).cover(value.span))

    def ground(self, children: list[Any]) -> ast.Ground:
        span, (kind, *pairs) = self._split(children)
        return ast.Ground(self._name(kind), tuple(pairs), span)

    def ground_option(self, children: list[Any]) -> ast.Opt:
        key, block = children
        return ast.Opt(Option.GROUND.value, block, self._tok_span(key).cover(block.span))

    def deployment(self, children: list[Any]) -> ast.DeploymentDecl:
        span, pairs = self._split(children)
        return ast.DeploymentDecl(tuple(pairs), span)

    def keep(self, children):
        span, names = self._split(children)
        return ast.Opt(Option.KEEP.value, self._names(names), span)

    def drop(self, children):
        span, names = self._split(children)
        return ast.Opt(Option.DROP.value, self._names(names), span)

    def morphism(self, children):
        span, (name, *options) = self._split(children)
        return ast.MorphismDecl(self._name(name), tuple(options), span)

    def hole(self, children):
        span, (name, *options) = self._split(children)
        return ast.HoleDecl(self._name(name), tuple(options), span)

    def view_decl(self, children):
        span, (name, *options) = self._split(children)
        return ast.ViewDecl(self._name(name), tuple(options), span)

    # -- problem sections
    def domain_ref(self, children):
        span, (name,) = self._split(children)
        return ast.DomainRef(self._name(name), span)

    def init(self, children):
        span, literals = self._split(children)
        return ast.Init(tuple(literals), span)

    def goal(self, children):
        span, (cond,) = self._split(children)
        return ast.Goal(cond, span)

    def horizon(self, children):
        span, (num,) = self._split(children)
        return ast.Horizon(self._num(num), span)

    def soft(self, children):
        span, (cond, *options) = self._split(children)
        return ast.Soft(cond, tuple(options), span)

    def objective_body(self, children):
        sense, term = children
        span = self._tok_span(sense).cover(term.span)
        return ast.Objective(self._name(sense), term, span)

    def objective(self, children):
        span, (body,) = self._split(children)
        return ast.Objective(body.sense, body.term, span)

    def single(self, children):
        return ("single", tuple(children))

    def lex(self, children):
        return ("lex", tuple(children))

    def pareto(self, children):
        return ("pareto", tuple(children))

    def metric(self, children):
        span, ((mode, objectives),) = self._split(children)
        return ast.Metric(mode, objectives, span)

    def deployed(self, children):
        span, names = self._split(children)
        return ast.Deployed(self._names(names), span)

    def view_use(self, children):
        span, (name,) = self._split(children)
        return ast.ViewUse(self._name(name), span)

    # -- expressions
    def ref(self, children):
        (tok,) = children
        return ast.Ref(str(tok), self._tok_span(tok))

    def number(self, children):
        (tok,) = children
        return self._num(tok)

    def true(self, children):
        return ast.BoolLit(True, self._tok_span(children[0]))

    def false(self, children):
        return ast.BoolLit(False, self._tok_span(children[0]))

    def set_literal(self, children):
        span, elements = self._split(children)
        return ast.SetLit(tuple(elements), span)

    def call(self, children):
        span, (head, *args) = self._split(children)
        return ast.Call(self._name(head), tuple(args), span)


_EXPONENT = re.compile(r"[eE]([+-]?[0-9]+)")


def _unquote(tok: Token) -> str:
    body = str(tok)[1:-1]
    return re.sub(r"\\(.)", r"\1", body)


class Cancelled(Exception):
    """A parse abandoned because its caller no longer wants it (``cancelled()`` said so)."""


def _watched(tokens: Iterator[Token], cancelled: Callable[[], bool], every: int = 4096) -> Iterator[Token]:
    for i, tok in enumerate(tokens):
        if i % every == 0 and cancelled():
            raise Cancelled
        yield tok


#: How many tokens the reader takes between two looks at the command's clock (a few
#: milliseconds' work: a 2 MB model is half a million tokens, issue 28 finding 4).
CLOCK_EVERY = 2048


def _timed(tokens: Iterator[Token], every: int = CLOCK_EVERY) -> Iterator[Token]:
    """``tokens``, stopping (:func:`catgrammar.limits.check_time`) every ``every`` tokens once
    the command's time is up, with the grace of a phase the answer needs (``FINISH_GRACE``:
    a query whose time is up still gives its UNKNOWN answer)."""
    for i, tok in enumerate(tokens):
        if i % every == 0:
            limits.check_time("reading the model", finishing=True)
        yield tok


def parse_source(src: Source, diags: Diagnostics, cancelled: Callable[[], bool] | None = None) -> ast.SourceFile | None:
    """Parse one file.  On failure, diagnostics are reported and None is returned.
    ``cancelled`` is asked every few thousand tokens; when it says so, :class:`Cancelled` is
    raised (the language server's check of a text the editor has replaced)."""
    diags.add_source(src)
    most = limits.current().input_bytes
    if len(src.text) > most // 4 and len(src.text.encode("utf-8", errors="replace")) > most:
        _too_large(src.path, src.text.encode("utf-8", errors="replace"), most, diags)
        return None
    stripped = re.sub(r";[^\n]*", "", src.text).strip()
    if not stripped:
        diags.report(
            codes.EMPTY_FILE,
            "empty file: expected (define (domain ...)) or (define (problem ...))",
            src.span(0, 0),
        )
        return None
    if not scan_parentheses(src, diags):
        return None
    parser = Parser(_Builder(src, diags))
    before = len(diags.errors)
    try:
        tokens = tokenize(src.text, limits.current().tokens)
        if limits.deadline_at() is not None:
            tokens = _timed(tokens)
        definitions = parser.parse(tokens if cancelled is None else _watched(tokens, cancelled))
    except UnexpectedInput as exc:
        _report_syntax(exc, src, parser, diags)
        return None
    except TooManyTokens as exc:
        tok, limit = exc.token, limits.BY_NAME["tokens"]
        diags.report(
            limit.code,
            f"more than {limits.count_text(exc.limit)} tokens (the tokens limit); split the file, or {limit.how_to_raise}",
            src.span(tok.start_pos or 0, tok.end_pos),
        )
        return None
    if len(diags.errors) > before:
        return None
    return ast.SourceFile(src.path, definitions)


def parse_text(text: str, path: str = "<string>", diags: Diagnostics | None = None) -> ast.SourceFile | None:
    diags = diags if diags is not None else Diagnostics()
    return parse_source(Source(path, text), diags)
