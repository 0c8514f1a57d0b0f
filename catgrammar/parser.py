"""Text → AST.

``parse_source`` never raises on bad input: it reports located diagnostics and returns
``None`` when no tree could be built.  Three guards run before Lark sees the text, so that
every later stage can recurse safely and every message can point at the real culprit:

* decoding (binary / non-UTF-8 files) in :func:`read_source`;
* a parenthesis scan that reports an unmatched ``)`` or an unclosed ``(`` precisely and
  rejects nesting deeper than :data:`MAX_DEPTH`;
* numeric literals longer than :data:`MAX_LITERAL_DIGITS` digits.
"""

from __future__ import annotations

import functools
import os
import re
from fractions import Fraction
from importlib import resources
from typing import Any

from lark import Lark, Token, Transformer_NonRecursive, v_args
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from catgrammar import ast
from catgrammar.diagnostics import Diagnostics, Note, did_you_mean
from catgrammar.span import Source, Span
from catgrammar.symbols import Option, Section

MAX_DEPTH = 128
MAX_LITERAL_DIGITS = 4000


@functools.lru_cache(maxsize=1)
def lark_parser() -> Lark:
    """The LALR parser, built once per process and cached on disk by Lark."""
    grammar = resources.files("catgrammar").joinpath("cat.lark").read_text(encoding="utf-8")
    return Lark(
        grammar,
        parser="lalr",
        lexer="contextual",
        propagate_positions=True,
        maybe_placeholders=False,
        cache=_cache_path(grammar),
    )


def _cache_path(grammar: str) -> str | bool:
    """A per-user cache file next to Lark's default, or no cache when none is writable."""
    import hashlib
    import tempfile

    digest = hashlib.sha256(grammar.encode()).hexdigest()[:16]
    directory = os.environ.get("CATC_CACHE_DIR") or os.path.join(tempfile.gettempdir(), "catc-cache")
    try:
        os.makedirs(directory, exist_ok=True)
    except OSError:
        return False
    return os.path.join(directory, f"cat-grammar-{digest}.lark.cache")


# ---------------------------------------------------------------- reading


def decode_source(path: str, data: bytes, diags: Diagnostics) -> Source | None:
    """Bytes → :class:`Source`, or a located diagnostic for binary or non-UTF-8 input."""
    if b"\x00" in data:
        offset = data.index(b"\x00")
        src = Source(path, data[:offset].decode("utf-8", errors="replace"))
        diags.report("E0002", "binary file: found a NUL byte; .cat files are UTF-8 text", src.span(offset, offset))
        return None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        src = Source(path, data[: exc.start].decode("utf-8", errors="replace"))
        diags.report(
            "E0003",
            f"invalid UTF-8: byte 0x{data[exc.start]:02x} cannot start or continue a character",
            src.span(len(src.text), len(src.text) + 1),
        )
        return None
    if text.startswith("\ufeff"):
        text = text[1:]
    return Source(path, text)


def read_source(path: str, diags: Diagnostics) -> Source | None:
    try:
        with open(path, "rb") as fh:
            data = fh.read()
    except OSError as exc:
        diags.report("E0001", f"cannot read '{path}': {exc.strerror or exc}", None)
        return None
    return decode_source(path, data, diags)


# ---------------------------------------------------------------- the parenthesis scan

_SCAN = re.compile(r'[()]|;[^\n]*|"(?:[^"\\\n]|\\.)*"?')


def scan_parentheses(src: Source, diags: Diagnostics) -> bool:
    """Report unmatched/unclosed parentheses and excessive depth.  True when clean."""
    stack: list[int] = []
    for m in _SCAN.finditer(src.text):
        tok = m.group()
        if tok == "(":
            stack.append(m.start())
            if len(stack) > MAX_DEPTH:
                diags.report(
                    "E0104",
                    f"parentheses nest more than {MAX_DEPTH} deep; split the expression",
                    src.span(m.start()),
                )
                return False
        elif tok == ")":
            if not stack:
                diags.report("E0102", "unmatched ')': there is no '(' to close", src.span(m.start()))
                return False
            stack.pop()
    if stack:
        opener = stack[0]
        inner = stack[-1]
        notes = []
        if inner != opener:
            notes.append(Note("the innermost '(' still open at the end of the file is here", src.span(inner)))
        diags.report(
            "E0103",
            f"'(' is never closed: the file ends with {len(stack)} parenthes{'is' if len(stack) == 1 else 'es'} open",
            src.span(opener),
            *notes,
        )
        return False
    return True


# ---------------------------------------------------------------- syntax errors

_HUMAN = {
    "LPAR": "'('",
    "RPAR": "')'",
    "NAME": "a name",
    "HEAD": "an operator",
    "NUMBER": "a number",
    "STRING": "a string",
    "FLAG": "a requirement flag",
    "SENSE": "'minimize' or 'maximize'",
    "$END": "the end of the file",
    "STAR": "'*'",
    "FIXED": "':fixed'",
    "TRUE": "'true'",
    "FALSE": "'false'",
    "LBRACE": "'{'",
    "RBRACE": "'}'",
}

_KEYWORDS = {s.value for s in Section} | {o.value for o in Option}


def _describe(parser: Lark, terminal: str) -> str:
    if terminal in _HUMAN:
        return _HUMAN[terminal]
    try:
        pattern = parser.get_terminal(terminal).pattern
    except KeyError:
        return terminal
    if pattern.type == "str":
        return f"'{pattern.value}'"
    keyword = _KEYWORD_PATTERN.fullmatch(pattern.value)
    return f"'{keyword.group(1)}'" if keyword else terminal


#: How the grammar spells a keyword terminal: the word, then a word-boundary lookahead.
_KEYWORD_PATTERN = re.compile(r"(:?[a-z][a-z-]*)\(\?!\[A-Za-z0-9_-\]\)")


def _expected_text(parser: Lark, expected: set[str]) -> str:
    words = sorted({_describe(parser, t) for t in expected})
    if len(words) > 12:
        keywords = [w for w in words if w.startswith("':")]
        others = [w for w in words if not w.startswith("':")]
        words = others + ([f"a keyword ({', '.join(keywords[:10])}, ...)"] if keywords else [])
    return words[0] if len(words) == 1 else ", ".join(words[:-1]) + " or " + words[-1]


def _keywords_in(parser: Lark, expected: set[str]) -> list[str]:
    out = []
    for t in expected:
        d = _describe(parser, t)
        if d.startswith("':"):
            out.append(d.strip("'"))
    return out


_WORD = re.compile(r":?[A-Za-z_][A-Za-z0-9_-]*|[^\sA-Za-z0-9_]")


def _report_syntax(exc: UnexpectedInput, src: Source, parser: Lark, diags: Diagnostics) -> None:
    pos = getattr(exc, "pos_in_stream", None) or 0
    if isinstance(exc, UnexpectedToken):
        tok = exc.token
        if tok.type == "$END":
            diags.report("E0103", "unexpected end of file", src.span(len(src.text), len(src.text)))
            return
        pos = tok.start_pos if tok.start_pos is not None else pos
        text = str(tok)
        expected = set(exc.expected)
    elif isinstance(exc, UnexpectedCharacters):
        m = _WORD.match(src.text, pos)
        text = m.group() if m else src.text[pos : pos + 1]
        expected = set(exc.allowed or ())
    elif isinstance(exc, UnexpectedEOF):
        diags.report("E0103", "unexpected end of file", src.span(len(src.text), len(src.text)))
        return
    else:  # pragma: no cover - Lark has no other kinds
        diags.report("E0101", str(exc).splitlines()[0], src.span(pos))
        return

    span = src.span(pos, pos + max(1, len(text)))
    keywords = _keywords_in(parser, expected)
    if text.startswith(":") and len(text) > 1:
        if text in _KEYWORDS and keywords:
            msg = f"'{text}' is not allowed here; expected {_expected_text(parser, expected)}"
        elif keywords:
            msg = f"unknown keyword '{text}'{did_you_mean(text, keywords)}" or ""
            if not did_you_mean(text, keywords):
                msg += f"; expected {_expected_text(parser, expected)}"
        else:
            msg = f"unexpected keyword '{text}'; expected {_expected_text(parser, expected)}"
        diags.report("E0106", msg, span)
        return
    if isinstance(exc, UnexpectedCharacters) and not re.match(r"[\w(){}*+<>=/-]", text):
        diags.report("E0107", f"unexpected character {text!r}", span)
        return
    what = "')'" if text == ")" else "'('" if text == "(" else f"'{text}'"
    msg = f"unexpected {what}; expected {_expected_text(parser, expected)}"
    if keywords and text not in ("(", ")"):
        hint = did_you_mean(":" + text, keywords)
        if hint:
            msg += f" (keywords start with ':'{hint})"
    diags.report("E0101", msg, span)


# ---------------------------------------------------------------- tree → AST


class _Builder(Transformer_NonRecursive):
    """Lark tree → :mod:`catgrammar.ast`.  Never indexes children by position except
    where the grammar fixes the shape (the leading NAME of a declaration)."""

    def __init__(self, src: Source, diags: Diagnostics):
        super().__init__()
        self.src = src
        self.diags = diags

    # -- helpers
    def _span(self, meta: Any) -> Span:
        if getattr(meta, "empty", True):
            return self.src.span(0, 0)
        return Span(
            self.src.path, meta.line, meta.column, meta.end_line, meta.end_column, meta.start_pos, meta.end_pos
        )

    def _tok_span(self, tok: Token) -> Span:
        return Span(
            self.src.path, tok.line, tok.column, tok.end_line, tok.end_column, tok.start_pos, tok.end_pos
        )

    def _name(self, tok: Token) -> ast.Name:
        return ast.Name(str(tok), self._tok_span(tok))

    def _num(self, tok: Token) -> ast.Num:
        text = str(tok)
        digits = sum(c.isdigit() for c in text)
        span = self._tok_span(tok)
        exponent = re.search(r"[eE]([+-]?\d+)", text)
        if digits > MAX_LITERAL_DIGITS:
            problem = f"has {digits} digits"
        elif exponent and abs(int(exponent.group(1)[:8])) > MAX_LITERAL_DIGITS:
            problem = f"has an exponent of {exponent.group(1)}"
        else:
            return ast.Num(Fraction(text), text, span)
        self.diags.report(
            "E0105",
            f"numeric literal {problem}; at most {MAX_LITERAL_DIGITS} digits are supported",
            span,
        )
        return ast.Num(Fraction(0), "0", span)

    def _names(self, children: list) -> tuple[ast.Name, ...]:
        return tuple(self._name(c) for c in children if isinstance(c, Token) and c.type == "NAME")

    # -- file
    def start(self, children):
        return tuple(children)

    @v_args(meta=True)
    def domain(self, meta, children):
        name, *sections = children
        return ast.Domain(self._name(name), tuple(sections), self._span(meta))

    @v_args(meta=True)
    def problem(self, meta, children):
        name, *sections = children
        return ast.Problem(self._name(name), tuple(sections), self._span(meta))

    # -- domain sections
    @v_args(meta=True)
    def requirements(self, meta, children):
        return ast.Requirements(tuple(self._name(c) for c in children), self._span(meta))

    @v_args(meta=True)
    def imports(self, meta, children):
        return ast.Imports(self._names(children), self._span(meta))

    @v_args(meta=True)
    def name_list(self, meta, children):
        return self._names(children)

    @v_args(meta=True)
    def enum_spec(self, meta, children):
        return ast.EnumSpec(self._names(children), self._span(meta))

    @v_args(meta=True)
    def sort_group(self, meta, children):
        names, parent = children
        if isinstance(parent, Token):
            parent = self._name(parent)
        return ast.SortGroup(names, parent, self._span(meta))

    @v_args(meta=True)
    def sorts(self, meta, children):
        groups = []
        for c in children:
            if isinstance(c, tuple):  # untyped tail: plain symbolic sorts
                span = c[0].span.cover(c[-1].span)
                groups.append(ast.SortGroup(c, None, span))
            else:
                groups.append(c)
        return ast.Sorts(tuple(groups), self._span(meta))

    @v_args(meta=True)
    def typed_group(self, meta, children):
        names, sort = children
        return ast.TypedGroup(names, self._name(sort), self._span(meta))

    @v_args(meta=True)
    def typed_names(self, meta, children):
        groups = []
        for c in children:
            if isinstance(c, tuple):
                groups.append(ast.TypedGroup(c, None, c[0].span.cover(c[-1].span)))
            else:
                groups.append(c)
        return tuple(groups)

    @v_args(meta=True)
    def constants(self, meta, children):
        (groups,) = children
        return ast.Constants(groups, self._span(meta))

    @v_args(meta=True)
    def objects(self, meta, children):
        (groups,) = children
        return ast.Objects(groups, self._span(meta))

    @v_args(meta=True)
    def resources(self, meta, children):
        return ast.Resources(tuple(children), self._span(meta))

    def _type(self, node) -> ast.TypeExpr:
        if isinstance(node, Token):
            name = self._name(node)
            return ast.TypeName(name, name.span)
        return node

    @v_args(meta=True)
    def set_type(self, meta, children):
        (elem,) = children
        return ast.SetType(self._name(elem), self._span(meta))

    @v_args(meta=True)
    def resource(self, meta, children):
        name, type_, *options = children
        return ast.ResourceDecl(self._name(name), self._type(type_), tuple(options), self._span(meta))

    @v_args(meta=True)
    def parameter(self, meta, children):
        name, type_, *options = children
        return ast.ParameterDecl(self._name(name), self._type(type_), tuple(options), self._span(meta))

    @v_args(meta=True)
    def parameters(self, meta, children):
        return ast.Opt(Option.PARAMETERS.value, tuple(children), self._span(meta))

    @v_args(meta=True)
    def bound(self, meta, children):
        (tok,) = children
        return None if tok.type == "STAR" else self._num(tok)

    @v_args(meta=True)
    def bounds(self, meta, children):
        lower, upper = children
        return ast.Bounds(lower, upper, self._span(meta))

    def _opt(key: str, kind: str):  # noqa: N805 - a factory for option handlers
        @v_args(meta=True)
        def handler(self, meta, children):
            if kind == "flag":
                value = True
            else:
                (value,) = children
                if kind == "name" and isinstance(value, Token):
                    value = self._name(value)
                elif kind == "number":
                    value = self._num(value)
                elif kind == "string":
                    value = self._name(value) if value.type == "NAME" else ast.Name(_unquote(value), self._tok_span(value))
            return ast.Opt(key, value, self._span(meta))

        return handler

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

    @v_args(meta=True)
    def keep(self, meta, children):
        return ast.Opt(Option.KEEP.value, self._names(children), self._span(meta))

    @v_args(meta=True)
    def drop(self, meta, children):
        return ast.Opt(Option.DROP.value, self._names(children), self._span(meta))

    @v_args(meta=True)
    def morphism(self, meta, children):
        name, *options = children
        return ast.MorphismDecl(self._name(name), tuple(options), self._span(meta))

    @v_args(meta=True)
    def hole(self, meta, children):
        name, *options = children
        return ast.HoleDecl(self._name(name), tuple(options), self._span(meta))

    @v_args(meta=True)
    def view_decl(self, meta, children):
        name, *options = children
        return ast.ViewDecl(self._name(name), tuple(options), self._span(meta))

    # -- problem sections
    @v_args(meta=True)
    def domain_ref(self, meta, children):
        (name,) = children
        return ast.DomainRef(self._name(name), self._span(meta))

    @v_args(meta=True)
    def init(self, meta, children):
        return ast.Init(tuple(children), self._span(meta))

    @v_args(meta=True)
    def goal(self, meta, children):
        (cond,) = children
        return ast.Goal(cond, self._span(meta))

    @v_args(meta=True)
    def horizon(self, meta, children):
        (num,) = children
        return ast.Horizon(self._num(num), self._span(meta))

    @v_args(meta=True)
    def soft(self, meta, children):
        cond, *options = children
        return ast.Soft(cond, tuple(options), self._span(meta))

    @v_args(meta=True)
    def objective_body(self, meta, children):
        sense, term = children
        return ast.Objective(self._name(sense), term, self._span(meta))

    @v_args(meta=True)
    def objective(self, meta, children):
        (body,) = children
        return ast.Objective(body.sense, body.term, self._span(meta))

    @v_args(meta=True)
    def single(self, meta, children):
        return ("single", tuple(children))

    @v_args(meta=True)
    def lex(self, meta, children):
        return ("lex", tuple(children))

    @v_args(meta=True)
    def pareto(self, meta, children):
        return ("pareto", tuple(children))

    @v_args(meta=True)
    def metric(self, meta, children):
        ((mode, objectives),) = children
        return ast.Metric(mode, objectives, self._span(meta))

    @v_args(meta=True)
    def deployed(self, meta, children):
        return ast.Deployed(self._names(children), self._span(meta))

    @v_args(meta=True)
    def view_use(self, meta, children):
        (name,) = children
        return ast.ViewUse(self._name(name), self._span(meta))

    # -- expressions
    @v_args(meta=True)
    def ref(self, meta, children):
        (tok,) = children
        return ast.Ref(str(tok), self._tok_span(tok))

    @v_args(meta=True)
    def number(self, meta, children):
        (tok,) = children
        return self._num(tok)

    @v_args(meta=True)
    def true(self, meta, children):
        return ast.BoolLit(True, self._tok_span(children[0]))

    @v_args(meta=True)
    def false(self, meta, children):
        return ast.BoolLit(False, self._tok_span(children[0]))

    @v_args(meta=True)
    def set_literal(self, meta, children):
        elements = tuple(c for c in children if not isinstance(c, Token))
        return ast.SetLit(elements, self._span(meta))

    @v_args(meta=True)
    def call(self, meta, children):
        head, *args = children
        return ast.Call(self._name(head), tuple(args), self._span(meta))


def _unquote(tok: Token) -> str:
    body = str(tok)[1:-1]
    return re.sub(r"\\(.)", r"\1", body)


def parse_source(src: Source, diags: Diagnostics) -> ast.SourceFile | None:
    """Parse one file.  On failure, diagnostics are reported and None is returned."""
    diags.add_source(src)
    stripped = re.sub(r";[^\n]*", "", src.text).strip()
    if not stripped:
        diags.report(
            "E0004",
            "empty file: expected (define (domain ...)) or (define (problem ...))",
            src.span(0, 0),
        )
        return None
    if not scan_parentheses(src, diags):
        return None
    parser = lark_parser()
    try:
        tree = parser.parse(src.text)
    except UnexpectedInput as exc:
        _report_syntax(exc, src, parser, diags)
        return None
    before = len(diags.errors)
    definitions = _Builder(src, diags).transform(tree)
    if len(diags.errors) > before:
        return None
    return ast.SourceFile(src.path, definitions)


def parse_text(text: str, path: str = "<string>", diags: Diagnostics | None = None) -> ast.SourceFile | None:
    diags = diags if diags is not None else Diagnostics()
    return parse_source(Source(path, text), diags)
