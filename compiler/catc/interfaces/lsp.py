"""``catc lsp``: a language server for .cat files (pygls 2.x, over stdio).

Features: the diagnostics of ``catc check`` on open/change (computed from the editor's
in-memory text), Markdown hover (resources, morphisms, θ parameters, sorts, constants,
views, holes, options; from the last version that checked while the text does not),
go to definition, completion (keywords and names in scope), document symbols, references
and rename across a domain and its problems, formatting (``catc fmt``), quick fixes (the
diagnostics' structured fixes: did-you-mean, a missing requirement flag), semantic tokens,
unit inlay hints and signature help for a form's options (docs/editors.md has the table;
the parts that need no pygls are in :mod:`catc.interfaces.lsp_tools`).

Documents are checked in the background (one worker thread), so the server answers other
requests while a large document is checked; a newer text of a document makes the check of
the older one stale (dropped before it starts, abandoned while it parses or between phases,
never published).  Positions are in the encoding negotiated with the client (LSP 3.17
``general.positionEncodings``; UTF-16 unless the client offers UTF-8 or UTF-32 first), while
catc's spans count code points; every position crossing the wire is converted.  A request
whose parameters cannot be read (a position of -1 or 2³¹) is answered with an error.

The analysis (:func:`analyse`) does not depend on pygls; the server part imports pygls only
when the command runs, so the rest of catc works without the ``lsp`` extra.
"""

from __future__ import annotations

import os
import re
import sys
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any
from urllib.parse import unquote, urlparse

import click

from catgrammar import ast
from catgrammar.span import Source, Span

MISSING = "catc lsp needs the 'lsp' extra: pip install 'catc-lang[lsp]'"

_WORD = re.compile(r"[:A-Za-z_][A-Za-z0-9_-]*")


# ---------------------------------------------------------------- analysis (no pygls)


@dataclass
class Definition:
    kind: (
        str  # domain | problem | sort | enum value | constant | object | resource | morphism | hole | view | parameter
    )
    name: str
    span: Span  # of the name
    whole: Span  # of the declaration
    owner: str | None = None  # the domain/problem (or morphism for parameters)


@dataclass
class Analysis:
    path: str
    text: str
    diagnostics: list = field(default_factory=list)  # catgrammar Diagnostic objects of this file
    tree: ast.SourceFile | None = None
    definitions: list[Definition] = field(default_factory=list)  # this file and the domains it sees
    domains: list = field(default_factory=list)  # checked ir.Domain objects
    problems: list = field(default_factory=list)  # checked ir.Problem objects
    sources: dict = field(default_factory=dict)  # path → text of every file read (for positions)
    stale: set = field(default_factory=set)  # ids of domains/problems kept from an older analysis


def _same(a: str, b: str) -> bool:
    return os.path.normcase(os.path.abspath(a)) == os.path.normcase(os.path.abspath(b))


def _opt_names(value) -> list[ast.Name]:
    if isinstance(value, ast.Name):
        return [value]
    if isinstance(value, (tuple, list)):
        return [v for v in value if isinstance(v, ast.Name)]
    return []


def definitions_of(tree: ast.SourceFile) -> list[Definition]:
    out: list[Definition] = []
    for d in tree.definitions:
        owner = d.name.text
        if isinstance(d, ast.Domain):
            out.append(Definition("domain", owner, d.name.span, d.span))
            for s in d.sections:
                if isinstance(s, ast.Sorts):
                    for g in s.groups:
                        for n in g.names:
                            out.append(Definition("sort", n.text, n.span, g.span, owner))
                        if isinstance(g.parent, ast.EnumSpec):
                            for v in g.parent.values:
                                out.append(Definition("enum value", v.text, v.span, g.parent.span, owner))
                elif isinstance(s, ast.Constants):
                    for typed in s.groups:
                        for n in typed.names:
                            out.append(Definition("constant", n.text, n.span, typed.span, owner))
                elif isinstance(s, ast.Resources):
                    for r in s.resources:
                        out.append(Definition("resource", r.name.text, r.name.span, r.span, owner))
                elif isinstance(s, ast.MorphismDecl):
                    out.append(Definition("morphism", s.name.text, s.name.span, s.span, owner))
                    for o in s.options:
                        if isinstance(o.value, (tuple, list)):
                            for p in o.value:
                                if isinstance(p, ast.ParameterDecl):
                                    out.append(Definition("parameter", p.name.text, p.name.span, p.span, s.name.text))
                elif isinstance(s, ast.HoleDecl):
                    out.append(Definition("hole", s.name.text, s.name.span, s.span, owner))
                elif isinstance(s, ast.ViewDecl):
                    out.append(Definition("view", s.name.text, s.name.span, s.span, owner))
        elif isinstance(d, ast.Problem):
            out.append(Definition("problem", owner, d.name.span, d.span))
            for sec in d.sections:
                if isinstance(sec, ast.Objects):
                    for typed in sec.groups:
                        for n in typed.names:
                            out.append(Definition("object", n.text, n.span, typed.span, owner))
    return out


def analyse(
    path: str, text: str, search_paths: tuple[str, ...] = (), cancelled: Callable[[], bool] | None = None
) -> Analysis:
    """``catc check`` on one document's in-memory text (its imports come from disk).
    ``cancelled`` is asked while parsing and between the phases; when it says so,
    :class:`catgrammar.parser.Cancelled` is raised."""
    from catc.frontend.session import check_parsed
    from catc.frontend.workspace import Workspace, normalise_path
    from catgrammar.diagnostics import Diagnostics
    from catgrammar.parser import Cancelled, parse_source

    result = Analysis(path, text)
    diags = Diagnostics()
    tree = parse_source(Source(path, text), diags, cancelled)
    result.tree = tree
    ws = Workspace(diags, search_paths)
    ws.files[normalise_path(path)] = tree
    instances: dict = {}
    if tree is not None:
        for d in tree.definitions:
            ws.index(d, path)
        if cancelled is not None and cancelled():
            raise Cancelled
        _, instances = check_parsed(ws, [(path, tree)], diags)
    result.sources = {p: src.text for p, src in diags.sources.items()}
    result.diagnostics = [d for d in diags if d.span is None or _same(d.span.file, path)]
    result.domains = ws.checked_domains()
    result.problems = [i.problem for i in instances.values()]
    if tree is not None:
        result.definitions = definitions_of(tree)
    seen = {id(tree)}
    for key, other in ws.files.items():
        if other is not None and id(other) not in seen and not _same(key, path):
            seen.add(id(other))
            result.definitions += definitions_of(other)
    return result


def word_at(text: str, line: int, character: int) -> str | None:
    """The name (or :keyword) under a 0-based position (``character`` in code points)."""
    lines = text.split("\n")
    if not 0 <= line < len(lines):
        return None
    s = lines[line]
    for m in _WORD.finditer(s):
        if m.start() <= character <= m.end():
            return m.group()
    return None


def code_units(text: str, encoding: str) -> int:
    """The length of ``text`` in a position encoding's units ("utf-8", "utf-16", "utf-32")."""
    if encoding == "utf-32":
        return len(text)
    if encoding == "utf-8":
        return len(text.encode("utf-8", "surrogatepass"))
    return len(text.encode("utf-16-le", "surrogatepass")) // 2


def client_column(line: str, column: int, encoding: str) -> int:
    """A 0-based code-point column of ``line`` as the client counts it."""
    return code_units(line[:column], encoding)


def server_column(line: str, character: int, encoding: str) -> int:
    """A 0-based column as the client counts it → code points (inside a character: that
    character; past the end of the line: its end)."""
    if encoding == "utf-32":
        return min(character, len(line))
    units = 0
    for i, c in enumerate(line):
        units += code_units(c, encoding)
        if units > character:
            return i
    return len(line)


def lookup(a: Analysis, name: str) -> list[Definition]:
    """Definitions named ``name``: this file's first, then those of the domains it uses."""
    found = [d for d in a.definitions if d.name == name]
    found.sort(key=lambda d: (not _same(d.span.file, a.path),))
    return found


def _grounding_text(g: object) -> str:
    """One line: what the morphism becomes on the robot (its ``:ground`` block)."""
    from catc.ir import grounding as gr

    if isinstance(g, gr.HardwareGrounding):
        text = "".join(p if isinstance(p, str) else "{" + str(p.name) + "}" for p in g.instruction.parts)
        return f"grounded as a hardware step: “{text}”"
    if isinstance(g, gr.SoftwareGrounding):
        return f"grounded as ROS 2 node `{g.node}` in image `{g.image}` ({g.profile.value})"
    if isinstance(g, gr.BehaviorGrounding):
        skill = f", skill image `{g.image}`" if g.image else ""
        return f"grounded as behaviour-tree node `{g.node_id}`{skill}"
    return "no grounding: `catc ground` writes nothing for it (W0106)"


def _unit_text(text: str) -> str:
    """``GB (information)``: the unit with its dimension (docs/language.md §Units)."""
    from catc.frontend import units

    try:
        return f"{text} ({units.parse(text).dimension})"
    except units.UnitError:
        return text


def _declaration(a: Analysis, d: Definition, max_lines: int = 8) -> str | None:
    """The declaration of ``d`` as written (its first line and an ellipsis when long)."""
    text = a.text if _same(d.whole.file, a.path) else a.sources.get(d.whole.file)
    if text is None:
        text = next((t for p, t in a.sources.items() if _same(p, d.whole.file)), None)
    if text is None:
        return None
    code = text[d.whole.start : d.whole.end]
    lines = code.split("\n")
    if len(lines) > max_lines or d.kind in ("domain", "problem", "morphism"):
        return lines[0].rstrip() + (" …" if len(lines) > 1 else "")
    indent = min((len(x) - len(x.lstrip()) for x in lines[1:] if x.strip()), default=0)
    return "\n".join([lines[0], *(x[indent:] for x in lines[1:])])


def _fenced(code: str) -> str:
    fence = "```"
    while fence in code:
        fence += "`"
    return f"{fence}cat\n{code}\n{fence}"


def hover_text(a: Analysis, name: str, at: Span | None = None) -> str | None:
    """The hover of ``name`` (written at ``at``) as Markdown: the declaration as written (a
    fenced ``cat`` block), what it is, then its details; paragraphs are separated by blank
    lines, so that every Markdown renderer keeps them apart.  Names of a domain that does
    not check (yet) still show their declaration; details of the last version that checked
    are marked as such."""
    if name.startswith(":"):
        from catc.interfaces.lsp_tools import OPTION_DOCS

        option = OPTION_DOCS.get(name)
        return f"{_fenced(option[0])}\n\n**option** `{name}`: {option[1]}" if option else None
    defs = lookup(a, name)
    d = defs[0] if defs else None
    if at is not None:
        from catc.interfaces.lsp_tools import target

        found = target(a, name, at)
        if found is not None:
            d = found[0]
    blocks: list[str] = []
    if d is not None:
        code = _declaration(a, d)
        if code:
            blocks.append(_fenced(code))
    details = _details(a, name, d)
    if details is None:
        if d is None:
            return None
        owner = f"{'morphism' if d.kind == 'parameter' else 'in'} `{d.owner}`" if d.owner else ""
        blocks.append(f"**{d.kind}** `{d.name}`" + (f" ({owner})" if owner else ""))
        if d.kind not in ("domain", "problem", "parameter"):
            blocks.append("*Only the declaration is shown: its definition does not check yet.*")
        return "\n\n".join(blocks)
    blocks += details
    return "\n\n".join(blocks)


def _bounds(lower: Any, upper: Any) -> str:
    from catc.ir.numbers import number_text

    lo = number_text(lower) if lower is not None else "*"
    hi = number_text(upper) if upper is not None else "*"
    return f"({lo} {hi})"


def _morphism_details(m: Any) -> list[str]:
    """A morphism's hover blocks: kind, doc, weights, θ parameters, preconditions, effects
    and grounding (each list after its own paragraph)."""
    from catc.ir.numbers import number_text
    from catc.ir.text import effect_text, to_text

    blocks = [f"**morphism** `{m.name}` ({m.kind.value})"]
    if m.doc:
        blocks.append(m.doc)
    extra = [f"churn {number_text(m.churn)}"]
    if m.uses == 0:
        extra.append("switched off (:uses 0)")
    elif m.uses is not None:
        extra.append(f"uses ≤ {m.uses}")
    if m.cost is not None:
        extra.append(f"cost {to_text(m.cost)}")
    blocks.append(", ".join(extra))
    if m.params:
        rows = []
        for p in m.params:
            b = f" in {_bounds(p.lower, p.upper)}" if p.lower is not None or p.upper is not None else ""
            u = f" [{p.unit}]" if p.unit else ""
            rows.append(f"- `{p.name}` : {_sort_text(p.sort)}{u}{b}{' (fixed)' if p.fixed else ''}")
        blocks += ["parameters:", "\n".join(rows)]
    if m.pre:
        blocks += ["preconditions:", "\n".join(f"- `{to_text(lit.expr)}`" for lit in m.pre)]
    if m.effects:
        blocks += ["effects:", "\n".join(f"- `{effect_text(e)}`" for e in m.effects)]
    blocks.append(_grounding_text(m.grounding))
    return blocks


def _details(a: Analysis, name: str, d: Definition | None) -> list[str] | None:
    """The Markdown blocks that describe ``name`` from the checked model, or None."""
    bounds = _bounds

    def where(kind: str, owner: object) -> str:
        stale = " — *as it last checked*" if id(owner) in a.stale else ""
        return f"*{kind} `{owner.name}`*{stale}"  # type: ignore[attr-defined]

    if d is not None and d.kind == "parameter":
        for dom in a.domains:
            m = dom.morphisms.get(d.owner or "")
            p = next((p for p in m.params if p.name == name), None) if m is not None else None
            if m is not None and p is not None:
                b = f" in {bounds(p.lower, p.upper)}" if p.lower is not None or p.upper is not None else ""
                fixed = " (fixed: one value for the composition)" if p.fixed else ""
                u = f" [{_unit_text(p.unit)}]" if p.unit else ""
                return [f"**parameter** `{name}` : {_sort_text(p.sort)}{u}{b}{fixed}", where("morphism", m)]
        return None
    for dom in a.domains:
        r = dom.resources.get(name)
        if r is not None:
            facts = []
            if r.unit:
                facts.append(f"unit: {_unit_text(r.unit)}")
            if r.group:
                facts.append(f"group: {r.group}")
            if r.lower is not None or r.upper is not None:
                facts.append(f"bounds: {bounds(r.lower, r.upper)}")
            blocks = [f"**resource** `{r.name}` : {_sort_text(r.sort)}"]
            if facts:
                blocks.append("\n".join(f"- {f}" for f in facts))
            if r.doc:
                blocks.append(r.doc)
            return [*blocks, where("domain", dom)]
    for dom in a.domains:
        m = dom.morphisms.get(name)
        if m is not None:
            return [*_morphism_details(m), where("domain", dom)]
    for dom in a.domains:
        s = dom.sorts.get(name)
        if s is not None:
            return [f"**sort** `{name}`: {_sort_text(s, expand=True)}", where("domain", dom)]
        c = dom.constants.get(name)
        if c is not None:
            return [f"**constant** `{name}` : {_sort_text(c.sort)}", where("domain", dom)]
        v = dom.views.get(name)
        if v is not None:
            return [f"**view** `{name}`: keeps {', '.join(sorted(v.kept)) or 'nothing'}", where("domain", dom)]
        h = dom.holes.get(name)
        if h is not None:
            bits = [f"view {h.view}" if h.view else "no view"]
            if h.max_effects is not None:
                bits.append(f"at most {h.max_effects} effects")
            if h.max_preconditions is not None:
                bits.append(f"at most {h.max_preconditions} preconditions")
            return [f"**hole** `{name}`: {', '.join(bits)}", where("domain", dom)]
    for p in a.problems:
        o = p.objects.get(name)
        if o is not None:
            return [f"**object** `{name}` : {_sort_text(o.sort)}", where("problem", p)]
    return None


def _sort_text(sort, expand: bool = False) -> str:
    kind = getattr(sort.kind, "value", str(sort.kind))
    if getattr(sort, "element", None) is not None:
        return f"(set {sort.element.name})"
    if expand and sort.values:
        return f"(enum {' '.join(sort.values)})"
    if expand and sort.parent:
        return f"{kind} (a kind of {sort.parent})"
    if expand:
        return f"{kind} sort"
    return sort.name or kind


def names_in_scope(a: Analysis) -> dict[str, str]:
    """name → what it is, for completion."""
    out: dict[str, str] = {}
    for d in a.definitions:
        out.setdefault(d.name, d.kind)
    for dom in a.domains:
        for n in dom.resources:
            out.setdefault(n, "resource")
        for n in dom.morphisms:
            out.setdefault(n, "morphism")
        for n in dom.constants:
            out.setdefault(n, "constant")
        for n in dom.sorts:
            out.setdefault(n, "sort")
        for n in dom.views:
            out.setdefault(n, "view")
        for n in dom.holes:
            out.setdefault(n, "hole")
    for p in a.problems:
        for n in p.objects:
            out.setdefault(n, "object")
    return out


def uri_to_path(uri: str) -> str:
    parsed = urlparse(uri)
    if parsed.scheme == "file":
        path = unquote(parsed.path)
        return parsed.path if "\0" in path else path  # %00 stays quoted: no path has a NUL
    return uri


def path_to_uri(path: str) -> str:
    from pathlib import Path

    try:
        return Path(os.path.abspath(path)).as_uri()
    except ValueError:  # pragma: no cover
        return path


# ---------------------------------------------------------------- the server


class Lines:
    """Positions for the client: catc's spans (1-based, code points) in the negotiated
    encoding, reading each file's lines once (the document's text as analysed, the other
    files as read by the analysis)."""

    def __init__(self, encoding: str, texts: Mapping[str, str]) -> None:
        self.encoding = encoding
        self.texts = {os.path.normcase(os.path.abspath(k)): v for k, v in texts.items()}
        self._lines: dict[str, list[str] | None] = {}

    def line(self, path: str, line: int) -> str | None:
        """Line ``line`` (0-based) of ``path``, or None when it is not known."""
        key = os.path.normcase(os.path.abspath(path))
        if key not in self._lines:
            text = self.texts.get(key)
            self._lines[key] = text.split("\n") if text is not None else None
        lines = self._lines[key]
        return lines[line] if lines is not None and 0 <= line < len(lines) else None

    def position(self, types: Any, path: str, line: int, column: int) -> Any:
        """A 1-based line and code-point column → an LSP Position."""
        text = self.line(path, line - 1)
        character = column - 1 if text is None else client_column(text, column - 1, self.encoding)
        return types.Position(max(line - 1, 0), max(character, 0))

    def range(self, types: Any, span: Span | None) -> Any:
        if span is None:
            return types.Range(types.Position(0, 0), types.Position(0, 0))
        return types.Range(
            self.position(types, span.file, span.line, span.column),
            self.position(types, span.file, span.end_line, span.end_column),
        )


def _encoding(ls: Any) -> str:
    """The position encoding pygls negotiated with the client ("utf-16" by default)."""
    value = getattr(ls.workspace, "position_encoding", None)
    return str(getattr(value, "value", value) or "utf-16")


def _lines(ls: Any, a: Analysis) -> Lines:
    return Lines(_encoding(ls), {**a.sources, a.path: a.text})


class Checks:
    """The background checks of open documents: one worker thread, so that the server
    answers other requests meanwhile.  Each new text of a document starts a new generation;
    a check of an older generation is stale: dropped before it starts, abandoned while it
    parses or between its phases, and its result is never published."""

    def __init__(self) -> None:
        import threading
        from concurrent.futures import ThreadPoolExecutor

        self._lock = threading.Lock()
        self._generation: dict[str, int] = {}
        self.executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="catc-check")
        self.tasks: dict[str, Any] = {}  # uri → the asyncio task that checks its latest text

    def next(self, uri: str) -> int:
        with self._lock:
            self._generation[uri] = self._generation.get(uri, 0) + 1
            return self._generation[uri]

    def stale(self, uri: str, generation: int) -> bool:
        with self._lock:
            return self._generation.get(uri) != generation

    def run(self, uri: str, generation: int, path: str, text: str, search: tuple[str, ...]) -> Analysis | None:
        """In the worker: the analysis, or None when it became stale."""
        from catgrammar.parser import Cancelled

        if self.stale(uri, generation):
            return None
        try:
            a = analyse(path, text, search, cancelled=lambda: self.stale(uri, generation))
        except Cancelled:
            return None
        return None if self.stale(uri, generation) else a


def build_server() -> Any:
    """The language server: document sync with diagnostics, navigation, symbols, and one
    ``workspace/executeCommand`` command per query (``catc.solve``, ``catc.diagnose``, ...)."""
    from lsprotocol import types
    from pygls.lsp.server import LanguageServer

    from catc import __version__

    server = LanguageServer(
        "catc", __version__, text_document_sync_kind=types.TextDocumentSyncKind.Full, protocol_cls=_protocol_class()
    )
    server.analyses = {}  # type: ignore[attr-defined]  # catc's own: uri → Analysis (the last one)
    server.checks = Checks()  # type: ignore[attr-defined]
    _register_documents(server, types)
    _register_navigation(server, types)
    _register_symbols(server, types)
    _register_queries(server, types)
    _register_editing(server, types)
    _register_fixes(server, types)
    _register_display(server, types)
    _register_signature_help(server, types)
    return server


def _protocol_class() -> Any:
    """pygls's protocol, answering a request whose parameters cannot be read (a position of
    -1 or 2³¹: LSP's uinteger ends at 2³¹−1) with its error; pygls only logs it, and the
    client would wait for ever."""
    from pygls.exceptions import JsonRpcException
    from pygls.exceptions import JsonRpcInvalidRequest as InvalidRequest
    from pygls.protocol import LanguageServerProtocol

    class Protocol(LanguageServerProtocol):
        def structure_message(self, data: dict[str, Any]) -> Any:
            try:
                return super().structure_message(data)
            except JsonRpcException as exc:
                if "method" in data and isinstance(data.get("id"), (int, str)):
                    self._send_response(data["id"], error=exc.to_response_error())
                    return _ANSWERED
                if "method" not in data and "id" not in data:
                    return object()  # neither request, notification nor response: no message
                raise

        def handle_message(self, message: Any) -> None:
            if message is _ANSWERED:
                return
            if not hasattr(message, "jsonrpc"):  # a body of [], null, 1, "x" or {}: no message
                self._send_response(None, error=InvalidRequest("not a JSON-RPC message").to_response_error())  # type: ignore[arg-type]  # id null
                return
            super().handle_message(message)

    return Protocol


_ANSWERED = object()  # a request already answered with an error while it was read


async def _refresh(ls: Any, types: Any, uri: str, generation: int, text: str) -> None:
    """Check ``text``, the document's text of ``generation``, in the background and publish
    its diagnostics (unless a newer text came meanwhile)."""
    import asyncio

    from catc.interfaces.command import search_path

    loop = asyncio.get_running_loop()
    try:
        a = await loop.run_in_executor(
            ls.checks.executor, ls.checks.run, uri, generation, uri_to_path(uri), text, search_path()
        )
    except Exception as exc:  # never take the editor down with an internal error
        ls.window_log_message(types.LogMessageParams(types.MessageType.Error, f"catc: {exc!r}"))
        return
    if a is None or ls.checks.stale(uri, generation):
        return
    previous = ls.analyses.get(uri)
    if a.tree is None and previous is not None:  # keep symbols/definitions of the last good parse
        a.definitions = previous.definitions or a.definitions
        if not a.domains:
            a.domains = list(previous.domains)
            a.stale |= {id(d) for d in a.domains}
        a.tree = previous.tree
        a.sources = {**previous.sources, **a.sources}
    if previous is not None:
        _keep_last_good(a, previous)
    ls.analyses[uri] = a
    _publish(ls, types, uri, a)


def _keep_last_good(a: Analysis, previous: Analysis) -> None:
    """A domain (or problem) of this document that does not check now keeps the checked
    model of its last version that did, marked stale: hover, semantic tokens and unit hints
    go on working while the text is being edited."""
    defined = {(d.kind, d.name) for d in a.definitions if _same(d.span.file, a.path)}
    have = {x.name for x in a.domains}
    for dom in previous.domains:
        if dom.name not in have and ("domain", dom.name) in defined:
            a.domains.append(dom)
            a.stale.add(id(dom))
    have = {x.name for x in a.problems}
    for prob in previous.problems:
        if prob.name not in have and ("problem", prob.name) in defined:
            a.problems.append(prob)
            a.stale.add(id(prob))


def _lsp_diagnostic(types: Any, lines: Lines, d: Any) -> Any:
    from catgrammar.diagnostics import Severity

    severity = {Severity.ERROR: types.DiagnosticSeverity.Error, Severity.WARNING: types.DiagnosticSeverity.Warning}
    related = [
        types.DiagnosticRelatedInformation(
            types.Location(path_to_uri(note.span.file), lines.range(types, note.span)), note.message
        )
        for note in getattr(d, "notes", ()) or ()
        if getattr(note, "span", None) is not None
    ]
    return types.Diagnostic(
        range=lines.range(types, d.span),
        message=d.message,
        severity=severity.get(d.severity, types.DiagnosticSeverity.Information),
        code=d.code,
        source="catc",
        related_information=related or None,
    )


def _publish(ls: Any, types: Any, uri: str, a: Analysis) -> None:
    lines = _lines(ls, a)
    out = [_lsp_diagnostic(types, lines, d) for d in a.diagnostics]
    ls.text_document_publish_diagnostics(types.PublishDiagnosticsParams(uri=uri, diagnostics=out))


def _schedule(ls: Any, types: Any, uri: str) -> None:
    """Start checking the document's current text: a new generation, so that every check
    of an older text is stale from now on."""
    import asyncio

    text = ls.workspace.get_text_document(uri).source
    generation = ls.checks.next(uri)
    ls.checks.tasks[uri] = asyncio.ensure_future(_refresh(ls, types, uri, generation, text))


async def _current(ls: Any, types: Any, uri: str) -> Analysis:
    """The document's latest analysis; until it has one, its check under way is waited for
    (a request that comes right after the document was opened)."""
    import asyncio

    while uri not in ls.analyses:
        task = ls.checks.tasks.get(uri)
        if task is None:
            _schedule(ls, types, uri)
            continue
        if task.done():
            break
        await asyncio.shield(task)
    return ls.analyses.get(uri) or Analysis(uri_to_path(uri), "")


async def _fresh(ls: Any, types: Any, uri: str) -> Analysis:
    """The analysis of the document's current text (its check under way is waited for):
    what an edit of the text (rename, code actions) must start from."""
    import asyncio

    task = ls.checks.tasks.get(uri)
    if task is not None and not task.done():
        await asyncio.shield(task)
    return await _current(ls, types, uri)


def _log(ls: Any, types: Any, message: str) -> None:
    ls.window_log_message(types.LogMessageParams(types.MessageType.Error, f"catc: {message}"))


def _word(ls: Any, a: Analysis, position: Any) -> tuple[str, Span] | None:
    """The name under an LSP position of the document's text, and its span (catc's)."""
    text = _doc_text(ls, a)
    lines = text.split("\n")
    if not 0 <= position.line < len(lines):
        return None
    line = lines[position.line]
    column = server_column(line, position.character, _encoding(ls))
    for m in _WORD.finditer(line):
        if m.start() <= column <= m.end():
            offset = sum(len(x) + 1 for x in lines[: position.line]) + m.start()
            return m.group(), Source(a.path, text).span(offset, offset + len(m.group()))
    return None


def _offset(text: str, position: Any, encoding: str) -> int:
    """An LSP position → a character offset of ``text`` (clamped to the text)."""
    lines = text.split("\n")
    if position.line >= len(lines):
        return len(text)
    return sum(len(x) + 1 for x in lines[: position.line]) + server_column(
        lines[position.line], position.character, encoding
    )


def _end(types: Any, text: str, encoding: str) -> Any:
    lines = text.split("\n")
    return types.Position(len(lines) - 1, code_units(lines[-1], encoding))


def _open_texts(ls: Any) -> dict[str, str]:
    out = {}
    for uri, doc in list(ls.workspace.text_documents.items()):
        if uri.startswith("file:"):
            out[uri_to_path(uri)] = doc.source
    return out


def _request_failed(message: str) -> Exception:
    from pygls.exceptions import JsonRpcException

    class Failed(JsonRpcException):
        CODE = -32803  # LSP RequestFailed
        MESSAGE = "Request failed"

    return Failed(message=message)


def _register_documents(server: Any, types: Any) -> None:
    @server.feature(types.TEXT_DOCUMENT_DID_OPEN)
    async def did_open(ls: Any, params: Any) -> None:
        _schedule(ls, types, params.text_document.uri)

    @server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
    async def did_change(ls: Any, params: Any) -> None:
        _schedule(ls, types, params.text_document.uri)

    @server.feature(types.TEXT_DOCUMENT_DID_SAVE)
    async def did_save(ls: Any, params: Any) -> None:
        _schedule(ls, types, params.text_document.uri)

    @server.feature(types.TEXT_DOCUMENT_DID_CLOSE)
    async def did_close(ls: Any, params: Any) -> None:
        uri = params.text_document.uri
        ls.checks.next(uri)  # a check under way is stale
        ls.checks.tasks.pop(uri, None)
        ls.analyses.pop(uri, None)
        ls.text_document_publish_diagnostics(types.PublishDiagnosticsParams(uri=uri, diagnostics=[]))


_COMPLETION_KINDS = {
    "resource": "Variable",
    "morphism": "Function",
    "sort": "Class",
    "constant": "Constant",
    "object": "Constant",
    "enum value": "EnumMember",
    "view": "Interface",
    "hole": "Struct",
    "domain": "Module",
    "problem": "Module",
    "parameter": "TypeParameter",
}


def _register_navigation(server: Any, types: Any) -> None:
    from catgrammar.symbols import all_keywords

    async def name_at(ls: Any, params: Any) -> tuple[Analysis, str | None]:
        a = await _current(ls, types, params.text_document.uri)
        text = ls.workspace.get_text_document(params.text_document.uri).source
        line, character = params.position.line, params.position.character
        lines = text.split("\n")
        if not 0 <= line < len(lines):
            return a, None
        return a, word_at(text, line, server_column(lines[line], character, _encoding(ls)))

    @server.feature(types.TEXT_DOCUMENT_HOVER)
    async def hover(ls: Any, params: Any) -> Any:
        a = await _current(ls, types, params.text_document.uri)
        found = _word(ls, a, params.position)
        if found is None:
            return None
        name, at = found
        try:
            text = hover_text(a, name, at)
        except Exception as exc:  # never a traceback for a half-written model
            _log(ls, types, f"hover: {exc!r}")
            return None
        if text is None:
            return None
        return types.Hover(contents=types.MarkupContent(kind=types.MarkupKind.Markdown, value=text))

    @server.feature(types.TEXT_DOCUMENT_DEFINITION)
    async def definition(ls: Any, params: Any) -> Any:
        a, name = await name_at(ls, params)
        defs = lookup(a, name) if name else []
        if not defs:
            return None
        lines = _lines(ls, a)
        return [types.Location(path_to_uri(d.span.file), lines.range(types, d.span)) for d in defs]

    @server.feature(types.TEXT_DOCUMENT_COMPLETION, types.CompletionOptions(trigger_characters=[":", "("]))
    async def completion(ls: Any, params: Any) -> Any:
        a = await _current(ls, types, params.text_document.uri)
        kinds = {k: getattr(types.CompletionItemKind, v) for k, v in _COMPLETION_KINDS.items()}
        items = [
            types.CompletionItem(label=k, kind=types.CompletionItemKind.Keyword, detail="keyword")
            for k in sorted({w for words in all_keywords().values() for w in words})
        ]
        items += [
            types.CompletionItem(label=n, kind=kinds.get(kind, types.CompletionItemKind.Text), detail=kind)
            for n, kind in sorted(names_in_scope(a).items())
        ]
        return types.CompletionList(is_incomplete=False, items=items)


_SYMBOL_KINDS = {
    "resource": "Variable",
    "morphism": "Function",
    "view": "Interface",
    "hole": "Struct",
    "sort": "Class",
    "constant": "Constant",
    "object": "Constant",
}


def _register_symbols(server: Any, types: Any) -> None:
    @server.feature(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    async def document_symbol(ls: Any, params: Any) -> Any:
        a = await _current(ls, types, params.text_document.uri)
        lines = _lines(ls, a)
        sk = types.SymbolKind
        top: list = []
        by_owner: dict[str, list] = {}
        for d in a.definitions:
            if not _same(d.span.file, a.path):
                continue
            if d.kind in ("domain", "problem"):
                children: list = []
                by_owner[d.name] = children
                kind = sk.Module if d.kind == "domain" else sk.Namespace
                top.append(
                    types.DocumentSymbol(
                        name=d.name,
                        detail=d.kind,
                        kind=kind,
                        range=lines.range(types, d.whole),
                        selection_range=lines.range(types, d.span),
                        children=children,
                    )
                )
            elif d.kind in _SYMBOL_KINDS and d.owner in by_owner:
                by_owner[d.owner].append(
                    types.DocumentSymbol(
                        name=d.name,
                        detail=d.kind,
                        kind=getattr(sk, _SYMBOL_KINDS[d.kind]),
                        range=lines.range(types, d.whole),
                        selection_range=lines.range(types, d.span),
                    )
                )
        return top


def _register_editing(server: Any, types: Any) -> None:
    """References and rename (with prepareRename)."""
    import asyncio

    from catc.interfaces import lsp_tools as tools

    @server.feature(types.TEXT_DOCUMENT_REFERENCES)
    async def references(ls: Any, params: Any) -> Any:
        a = await _fresh(ls, types, params.text_document.uri)
        found = _word(ls, a, params.position)
        if found is None:
            return []
        try:
            files = await asyncio.to_thread(tools.workspace_files, a, _open_texts(ls))
            spans = await asyncio.to_thread(tools.references, a, *found, files, params.context.include_declaration)
        except Exception as exc:  # never a traceback for a half-written model
            _log(ls, types, f"references: {exc!r}")
            return []
        lines = Lines(_encoding(ls), files)
        return [types.Location(path_to_uri(s.file), lines.range(types, s)) for s in spans]

    @server.feature(types.TEXT_DOCUMENT_PREPARE_RENAME)
    async def prepare_rename(ls: Any, params: Any) -> Any:
        a = await _fresh(ls, types, params.text_document.uri)
        found = _word(ls, a, params.position)
        if found is None:
            raise _request_failed("there is no name here to rename")
        try:
            tools.check_rename(a, *found)
        except tools.RenameError as exc:
            raise _request_failed(str(exc)) from None
        lines = Lines(_encoding(ls), {a.path: _doc_text(ls, a)})
        return types.PrepareRenamePlaceholder(range=lines.range(types, found[1]), placeholder=found[0])

    @server.feature(types.TEXT_DOCUMENT_RENAME, types.RenameOptions(prepare_provider=True))
    async def rename(ls: Any, params: Any) -> Any:
        a = await _fresh(ls, types, params.text_document.uri)
        found = _word(ls, a, params.position)
        if found is None:
            raise _request_failed("there is no name here to rename")
        try:
            files = await asyncio.to_thread(tools.workspace_files, a, _open_texts(ls))
            edits = await asyncio.to_thread(tools.rename_edits, a, *found, params.new_name, files)
        except tools.RenameError as exc:
            raise _request_failed(str(exc)) from None
        lines = Lines(_encoding(ls), files)
        return types.WorkspaceEdit(
            changes={
                path_to_uri(path): [types.TextEdit(lines.range(types, s), params.new_name) for s in spans]
                for path, spans in edits.items()
            }
        )


def _register_fixes(server: Any, types: Any) -> None:
    """Formatting and code actions."""
    import asyncio

    from catc.interfaces import lsp_tools as tools

    @server.feature(types.TEXT_DOCUMENT_FORMATTING)
    async def formatting(ls: Any, params: Any) -> Any:
        text = ls.workspace.get_text_document(params.text_document.uri).source
        try:
            new = await asyncio.to_thread(tools.formatted, text)  # seconds for a huge file: off the loop
        except Exception as exc:  # never a traceback for a half-written model
            _log(ls, types, f"formatting: {exc!r}")
            return []
        if new is None or new == text:
            return []  # a file that does not parse is left alone
        return [types.TextEdit(types.Range(types.Position(0, 0), _end(types, text, _encoding(ls))), new)]

    @server.feature(
        types.TEXT_DOCUMENT_CODE_ACTION, types.CodeActionOptions(code_action_kinds=[types.CodeActionKind.QuickFix])
    )
    async def code_action(ls: Any, params: Any) -> Any:
        a = await _fresh(ls, types, params.text_document.uri)
        lines = _lines(ls, a)
        want = params.range
        out = []
        for d in a.diagnostics:
            fixes = getattr(d, "fixes", ())
            if not fixes or d.span is None:
                continue
            diag = _lsp_diagnostic(types, lines, d)
            r = diag.range
            if (r.end.line, r.end.character) < (want.start.line, want.start.character) or (
                (want.end.line, want.end.character) < (r.start.line, r.start.character)
            ):
                continue
            for fix in fixes:
                edit = types.TextEdit(lines.range(types, fix.span), fix.text)
                out.append(
                    types.CodeAction(
                        title=fix.title,
                        kind=types.CodeActionKind.QuickFix,
                        diagnostics=[diag],
                        is_preferred=len(fixes) == 1,
                        edit=types.WorkspaceEdit(changes={path_to_uri(fix.span.file): [edit]}),
                    )
                )
        return out


def _doc_text(ls: Any, a: Analysis) -> str:
    try:
        return ls.workspace.get_text_document(path_to_uri(a.path)).source
    except Exception:  # pragma: no cover
        return a.text


def _register_display(server: Any, types: Any) -> None:
    """Semantic tokens and unit inlay hints (in a thread: a large document takes a second)."""
    import asyncio

    from catc.interfaces import lsp_tools as tools

    legend = types.SemanticTokensLegend(
        token_types=list(tools.TOKEN_TYPES), token_modifiers=list(tools.TOKEN_MODIFIERS)
    )

    @server.feature(
        types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL, types.SemanticTokensRegistrationOptions(legend=legend, full=True)
    )
    async def semantic_tokens(ls: Any, params: Any) -> Any:
        a = await _fresh(ls, types, params.text_document.uri)
        encoding = _encoding(ls)
        lines = a.text.split("\n")
        data: list[int] = []
        last_line = last_start = 0
        try:
            found = await asyncio.to_thread(tools.semantic_tokens, a)
        except Exception as exc:  # never a traceback for a half-written model
            _log(ls, types, f"semantic tokens: {exc!r}")
            found = []
        for span, kind, mods in found:
            line = span.line - 1
            text = lines[line] if line < len(lines) else ""
            start = client_column(text, span.column - 1, encoding)
            length = code_units(text[span.column - 1 : span.end_column - 1], encoding)
            bits = sum(1 << tools.TOKEN_MODIFIERS.index(m) for m in mods)
            delta_start = start - last_start if line == last_line else start
            data += [line - last_line, delta_start, length, tools.TOKEN_TYPES.index(kind), bits]
            last_line, last_start = line, start
        return types.SemanticTokens(data=data)

    @server.feature(types.TEXT_DOCUMENT_INLAY_HINT)
    async def inlay_hints(ls: Any, params: Any) -> Any:
        a = await _fresh(ls, types, params.text_document.uri)
        lines = _lines(ls, a)
        r = params.range
        out = []
        try:
            hints = await asyncio.to_thread(tools.unit_hints, a)
        except Exception as exc:  # never a traceback for a half-written model
            _log(ls, types, f"inlay hints: {exc!r}")
            hints = []
        for span, unit, resource in hints:
            end = lines.position(types, span.file, span.end_line, span.end_column)
            if not ((r.start.line, r.start.character) <= (end.line, end.character) <= (r.end.line, r.end.character)):
                continue
            out.append(
                types.InlayHint(
                    position=end,
                    label=unit,
                    kind=types.InlayHintKind.Type,
                    tooltip=f"unit of resource {resource}",
                    padding_left=True,
                )
            )
        return out


def _register_signature_help(server: Any, types: Any) -> None:
    """The options of the form under the cursor."""
    from catc.interfaces import lsp_tools as tools

    @server.feature(
        types.TEXT_DOCUMENT_SIGNATURE_HELP,
        types.SignatureHelpOptions(trigger_characters=[":", " ", "("], retrigger_characters=[" "]),
    )
    async def signature_help(ls: Any, params: Any) -> Any:
        text = ls.workspace.get_text_document(params.text_document.uri).source
        try:
            sig = tools.signature_at(text, _offset(text, params.position, _encoding(ls)))
        except Exception as exc:  # never a traceback for a half-written model
            _log(ls, types, f"signature help: {exc!r}")
            return None
        if sig is None:
            return None
        info = types.SignatureInformation(
            label=sig.label,
            documentation=types.MarkupContent(kind=types.MarkupKind.Markdown, value=sig.doc),
            parameters=[
                types.ParameterInformation(label=o, documentation=d) for o, d in zip(sig.options, sig.option_docs)
            ],
        )
        return types.SignatureHelp(signatures=[info], active_signature=0, active_parameter=sig.active)


def run_query_on_file(name: str, uri: str, options: dict[str, Any] | None = None) -> dict:
    """Answer the query ``name`` for the problem saved in the file at ``uri``: the query's
    ``--json`` document, or a ``catc.error/1`` document for input errors."""
    from catc.interfaces.api import CatError, load
    from catc.queries import registry
    from catc.queries.base import InputError, Kind

    query = registry.get(name)
    try:
        model = load(uri_to_path(uri))
        values = {**query.defaults(), **(options or {})}
        for option in query.options:
            if option.kind is Kind.PLAN_FILE and values.get(option.name) is None:
                raise InputError(f"catc.{name} needs '{option.name}': a catc.plan/1 document")
        why = query.check(model.instance, values) if query.check is not None else None
        if why is not None:
            raise InputError(why)
        result = model.query(name, **query.run_options(values))
    except CatError as exc:
        return {"schema": "catc.error/1", "status": "error", "diagnostics": [d.to_json() for d in exc.diagnostics]}
    except (InputError, ValueError) as exc:
        return {"schema": "catc.error/1", "status": "error", "diagnostics": [{"message": str(exc)}]}
    return query.to_json(model.instance, result)


def _register_queries(server: Any, types: Any) -> None:
    """``catc.<query>`` commands: arguments ``[uri]`` or ``[uri, {option: value}]``; they
    answer for the saved file, as the command line would."""
    from catc.interfaces.lsp_framing import readable_path
    from catc.queries import registry

    def command_for(name: str) -> Any:
        def handler(ls: Any, *args: Any) -> dict:
            uri, options = (args[0] if args else None), (args[1] if len(args) > 1 else None)
            known = set(ls.workspace.text_documents)
            roots = [uri_to_path(f.uri) for f in ls.workspace.folders.values()] + [ls.workspace.root_path or ""]
            if readable_path(uri, known, roots) is None:  # issue 28: no other file is read
                message = f"not a file: URI of an open document or of the workspace: {uri!r}"
                return {"schema": "catc.error/1", "status": "error", "diagnostics": [{"message": message}]}
            return run_query_on_file(name, str(uri), options)

        return handler

    for name in registry.names():  # in pygls's threads: a long query never blocks the server
        server.command(f"catc.{name}")(server.thread()(command_for(name)))


@click.command("lsp")
@click.option("--stdio", is_flag=True, help="Talk over standard input/output (the default; accepted for editors).")
def lsp_command(stdio: bool) -> None:
    """Run the .cat language server over stdio (needs the 'lsp' extra).

    Diagnostics as `catc check`, hover, go to definition, completion, document symbols,
    references, rename, formatting, quick fixes, semantic tokens, unit hints and signature
    help.
    """
    try:
        import lsprotocol  # noqa: F401
        import pygls  # noqa: F401
    except ImportError:
        click.echo(MISSING, err=True)
        sys.exit(2)
    from catc.interfaces.lsp_framing import CanonicalHeaders

    build_server().start_io(CanonicalHeaders(sys.stdin.buffer))
