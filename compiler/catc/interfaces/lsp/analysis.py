"""The analysis of a .cat document for the language server, without pygls: its definitions,
the word at a position, positions in the client's encoding, and file URIs."""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from urllib.parse import unquote, urlparse

from catgrammar import ast
from catgrammar.span import Source, Span

MISSING = "catc lsp needs the 'lsp' extra: pip install 'catc-lang[lsp]'"

WORD = re.compile(r"[:A-Za-z_][A-Za-z0-9_-]*")


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


def same_name(a: str, b: str) -> bool:
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
                                out.append(
                                    Definition(
                                        "enum value",
                                        v.text,
                                        v.span,
                                        g.parent.span,
                                        owner,
                                    )
                                )
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
                                    out.append(
                                        Definition(
                                            "parameter",
                                            p.name.text,
                                            p.name.span,
                                            p.span,
                                            s.name.text,
                                        )
                                    )
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
    path: str,
    text: str,
    search_paths: tuple[str, ...] = (),
    cancelled: Callable[[], bool] | None = None,
    texts: Mapping[str, str] | None = None,
) -> Analysis:
    """``catc check`` on one document's in-memory text; the files it reads come from
    ``texts`` (path → the text of another document open in the editor) or from disk.
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
    ws = Workspace(diags, search_paths, texts={p: t for p, t in (texts or {}).items() if not same_name(p, path)})
    ws.files[normalise_path(path)] = tree
    instances: dict = {}
    if tree is not None:
        for d in tree.definitions:
            ws.index(d, path)
        if cancelled is not None and cancelled():
            raise Cancelled
        _, instances = check_parsed(ws, [(path, tree)], diags)
    result.sources = {p: src.text for p, src in diags.sources.items()}
    result.diagnostics = [d for d in diags if d.span is None or same_name(d.span.file, path)]
    result.domains = ws.checked_domains()
    result.problems = [i.problem for i in instances.values()]
    if tree is not None:
        result.definitions = definitions_of(tree)
    seen = {id(tree)}
    for key, other in ws.files.items():
        if other is not None and id(other) not in seen and not same_name(key, path):
            seen.add(id(other))
            result.definitions += definitions_of(other)
    return result


def word_at(text: str, line: int, character: int) -> str | None:
    """The name (or :keyword) under a 0-based position (``character`` in code points)."""
    lines = text.split("\n")
    if not 0 <= line < len(lines):
        return None
    s = lines[line]
    for m in WORD.finditer(s):
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
    found.sort(key=lambda d: (not same_name(d.span.file, a.path),))
    return found


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
