"""The modelling tools of ``catc lsp`` that need no pygls: references and rename across the
files of a workspace, semantic tokens, unit inlay hints, signature help for a form's
options and formatting.  Positions here are catc's (1-based lines, code-point columns,
character offsets); :mod:`catc.interfaces.lsp.server` converts them for the client.

Names are found with the language's own tokenizer, so comments never count and a string
counts only where it holds a grounding template's ``{θ}`` hole.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from catgrammar.span import Source, Span

if TYPE_CHECKING:  # pragma: no cover
    from catc.interfaces.lsp.analysis import Analysis, Definition

NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_-]*")


class RenameError(Exception):
    """A rename that cannot be done; the message says why (shown by the editor)."""


# ---------------------------------------------------------------- tokens


@dataclass(frozen=True)
class Word:
    """A NAME token (or a ``{θ}`` hole's name inside a string) and where it is."""

    text: str
    span: Span
    in_string: bool = False


_HOLE = re.compile(r"\{([A-Za-z_][A-Za-z0-9_-]*)\}")


def words(path: str, text: str) -> Iterator[Word]:
    """The names written in ``text``, in order; a character no token starts with ends the
    scan (the rest of a broken file is not guessed at)."""
    from catgrammar._lalr import UnexpectedCharacters
    from catgrammar.tokens import tokenize

    src = Source(path, text)
    try:
        for tok in tokenize(text):
            start = tok.start_pos or 0
            if tok.type == "NAME":
                yield Word(tok.value, src.span(start, start + len(tok.value)))
            elif tok.type == "STRING" and "{" in tok.value and "\\" not in tok.value and "\n" not in tok.value:
                for m in _HOLE.finditer(tok.value):
                    yield Word(
                        m.group(1),
                        src.span(start + m.start(1), start + m.end(1)),
                        in_string=True,
                    )
    except UnexpectedCharacters:
        return


def tokens(text: str) -> list[tuple[str, str, int]]:
    """(type, text, offset) of every token up to the first character no token starts with."""
    from catgrammar._lalr import UnexpectedCharacters
    from catgrammar.tokens import tokenize

    out: list[tuple[str, str, int]] = []
    try:
        for tok in tokenize(text):
            out.append((tok.type, str(tok.value), tok.start_pos or 0))
    except UnexpectedCharacters:
        pass
    return out


def _key(path: str) -> str:
    return os.path.normcase(os.path.abspath(path))


def _inside(span: Span, outer: Span) -> bool:
    return _key(span.file) == _key(outer.file) and outer.start <= span.start and span.end <= outer.end


# ---------------------------------------------------------------- what a name means


def builtin_words() -> frozenset[str]:
    """Words a model cannot rename: keywords, operators, built-in sorts and constants."""
    from catgrammar.symbols import RESERVED_NAMES, all_keywords

    return frozenset(RESERVED_NAMES) | {w for ws in all_keywords().values() for w in ws}


def _morphism_of(a: Analysis, param: Definition) -> Definition | None:
    for d in a.definitions:
        same = d.kind == "morphism" and d.name == param.owner and _key(d.span.file) == _key(param.span.file)
        if same and d.whole.start <= param.span.start <= d.whole.end:
            return d
    return None


def param_scopes(a: Analysis, path: str) -> dict[str, list[Span]]:
    """θ name → the morphisms of the file ``path`` that declare it (their spans)."""
    key = _key(path)
    morphisms: dict[str, list[Span]] = {}
    for d in a.definitions:
        if d.kind == "morphism" and _key(d.span.file) == key:
            morphisms.setdefault(d.name, []).append(d.whole)
    out: dict[str, list[Span]] = {}
    for d in a.definitions:
        if d.kind == "parameter" and _key(d.span.file) == key:
            for whole in morphisms.get(d.owner or "", ()):
                if whole.start <= d.span.start <= whole.end:
                    out.setdefault(d.name, []).append(whole)
    return out


def target(a: Analysis, name: str, at: Span) -> tuple[Definition, Span | None] | None:
    """The definition the name written at ``at`` means, and the span it is limited to (a
    parameter: its morphism), or None when it names nothing of the model."""
    from catc.interfaces.lsp.analysis import lookup

    defs = lookup(a, name)
    for d in defs:
        if d.kind == "parameter":
            m = _morphism_of(a, d)
            if m is not None and _inside(at, m.whole):
                return d, m.whole
    others = [d for d in defs if d.kind != "parameter"]
    return (others[0], None) if others else None


def in_stdlib(path: str) -> bool:
    from catc.frontend.workspace import stdlib_dir

    try:
        return Path(path).resolve().is_relative_to(stdlib_dir())
    except OSError:  # pragma: no cover
        return False


def workspace_files(a: Analysis, texts: Mapping[str, str]) -> dict[str, str]:
    """The files a name may be used in (path → text), paired as the workspace pairs them
    (:mod:`catc.frontend.workspace`: a problem uses the domain of its own folder first):
    the document, the files its analysis read and the other ``.cat`` files of their folders
    (the domain beside its problems), and the open documents (their editor text, as every
    file that is open).  The standard library's folder is not scanned (it is read-only)."""
    out: dict[str, str] = {}
    seen: set[str] = set()
    open_texts = {_key(p): t for p, t in texts.items()}
    open_texts[_key(a.path)] = a.text

    def add(path: str, text: str | None = None) -> None:
        key = _key(path)
        if key in seen:
            return
        seen.add(key)
        text = open_texts.get(key, text)
        if text is None:
            try:
                if os.path.getsize(path) > 4_000_000:
                    return
                with open(path, encoding="utf-8") as fh:
                    text = fh.read()
            except (OSError, UnicodeDecodeError):
                return
        out[path] = text

    add(a.path)
    folders: set[Path] = set()
    for p, t in [*a.sources.items(), (a.path, a.text)]:
        add(p, t)
        if os.path.isfile(p) and not in_stdlib(p):  # not an unsaved (untitled:) document's folder
            folders.add(Path(p).resolve().parent)
    for folder in sorted(folders):
        for f in sorted(folder.glob("*.cat")):
            add(str(f))
    for p, t in texts.items():
        add(p, t)
    return out


def _related(
    text: str,
    path: str,
    owner_domains: set[str],
    definition_file: str,
    files: Mapping[str, str],
    loaded: frozenset[str] = frozenset(),
) -> bool:
    """Whether a file may use names of the domains ``owner_domains``: it is the defining
    file, or it names one of them (``(:domain NAME)``, ``(:import NAME)``) and its own folder
    defines no other domain of that name (which it would use instead) — a file the analysis
    itself read (``loaded``, keys of :func:`_key`) is the domain of that name, not another."""
    from catc.frontend.workspace import defined_domains

    if _key(path) == _key(definition_file):
        return True
    if not any(o in text for o in owner_domains):
        return False
    if not any(w.text in owner_domains for w in words(path, text) if not w.in_string):
        return False
    folder = Path(path).resolve().parent
    if folder == Path(definition_file).resolve().parent:
        return True
    for other, other_text in files.items():  # a domain of that name beside it wins
        beside = _key(other) not in loaded and _key(other) != _key(definition_file)
        beside = beside and Path(other).resolve().parent == folder
        if beside and owner_domains & set(defined_domains(other_text)):
            return False
    return True


def _owner_domains(a: Analysis, d: Definition) -> set[str]:
    """The domain (or problem) a definition belongs to, and the domains that import it."""
    owner = d.name if d.kind in ("domain", "problem") else d.owner
    if d.kind == "parameter":
        m = _morphism_of(a, d)
        owner = m.owner if m is not None else owner
    names = {owner} if owner else set()
    changed = True
    while changed:  # domains importing an owner see its names too
        changed = False
        for dom in a.domains:
            if dom.name not in names and names & set(getattr(dom, "imports", ()) or ()):
                names.add(dom.name)
                changed = True
    return names


def references(
    a: Analysis,
    name: str,
    at: Span,
    files: Mapping[str, str],
    include_declaration: bool = True,
) -> list[Span]:
    """Every place the name written at ``at`` is used, across ``files``."""
    found = target(a, name, at)
    if found is None:
        return []
    d, limit = found
    out: list[Span] = []
    if limit is not None:  # a parameter: its morphism only (with its grounding's {θ} holes)
        text = next((t for p, t in files.items() if _key(p) == _key(limit.file)), None)
        if text is None:
            return []
        out = [w.span for w in words(limit.file, text) if w.text == name and _inside(w.span, limit)]
    else:
        owners = _owner_domains(a, d)
        problem_local = d.kind == "object"
        for path, text in files.items():
            if name not in text or (problem_local and _key(path) != _key(d.span.file)):
                continue
            loaded = frozenset(_key(p) for p in (*a.sources, a.path))
            if _related(text, path, owners, d.span.file, files, loaded):
                hidden = param_scopes(a, path).get(name, [])  # a θ of that name hides it there
                out += [
                    w.span
                    for w in words(path, text)
                    if w.text == name and not w.in_string and not any(_inside(w.span, m) for m in hidden)
                ]
    if not include_declaration:
        out = [s for s in out if not (_key(s.file) == _key(d.span.file) and s.start == d.span.start)]
    out.sort(key=lambda s: (_key(s.file) != _key(a.path), s.file, s.start))
    return out


def check_rename(a: Analysis, name: str, at: Span, new: str | None = None) -> Definition:
    """The definition to rename, or :class:`RenameError` saying why it cannot be renamed
    (to ``new`` when given)."""
    from catc.interfaces.lsp.analysis import names_in_scope

    if name in builtin_words() or name.startswith(":"):
        raise RenameError(f"'{name}' is a keyword or built-in of the language and cannot be renamed")
    found = target(a, name, at)
    if found is None:
        raise RenameError(f"'{name}' names nothing declared in this model")
    d, limit = found
    if in_stdlib(d.span.file):
        raise RenameError(
            f"'{name}' is declared in the standard library ({Path(d.span.file).name}), which is read-only"
        )
    if new is None:
        return d
    if not NAME.fullmatch(new):
        raise RenameError(
            f"'{new}' is not a name: a name starts with a letter or '_' and holds letters, digits, '_', '-'"
        )
    if new in builtin_words():
        raise RenameError(f"'{new}' is a keyword or built-in of the language")
    if new == name:
        return d
    scope = names_in_scope(a)
    if limit is not None:  # a parameter: the other parameters of its morphism, then the names in scope
        for other in a.definitions:
            if other.kind == "parameter" and other.name == new and _inside(other.span, limit):
                raise RenameError(f"'{new}' is already a parameter of morphism '{d.owner}'")
    if new in scope:
        raise RenameError(f"'{new}' is already the name of a {scope[new]}; choose a name not in use")
    return d


def rename_edits(a: Analysis, name: str, at: Span, new: str, files: Mapping[str, str]) -> dict[str, list[Span]]:
    """file → the spans to replace by ``new`` (raises :class:`RenameError`)."""
    check_rename(a, name, at, new)
    out: dict[str, list[Span]] = {}
    for span in references(a, name, at, files):
        if in_stdlib(span.file):
            continue
        out.setdefault(span.file, []).append(span)
    return out


# ---------------------------------------------------------------- semantic tokens

#: The legend: token types and modifiers, in the order their indices are sent.
TOKEN_TYPES = (
    "namespace",
    "type",
    "variable",
    "function",
    "parameter",
    "enumMember",
    "interface",
    "struct",
)
TOKEN_MODIFIERS = ("declaration", "defaultLibrary")

_KIND_TYPE = {
    "domain": "namespace",
    "problem": "namespace",
    "sort": "type",
    "resource": "variable",
    "morphism": "function",
    "parameter": "parameter",
    "constant": "enumMember",
    "object": "enumMember",
    "enum value": "enumMember",
    "view": "interface",
    "hole": "struct",
}

_BUILTIN_SORTS = frozenset({"bool", "int", "real", "symbol"})


def semantic_tokens(a: Analysis) -> list[tuple[Span, str, tuple[str, ...]]]:
    """(span, token type, modifiers) of every name of the document that means something of
    the model: resources, morphisms, θ parameters, constants/objects, sorts, ..."""
    from catc.interfaces.lsp.analysis import names_in_scope

    scope = names_in_scope(a)
    declared = {d.span.start for d in a.definitions if _key(d.span.file) == _key(a.path)}
    params = param_scopes(a, a.path)
    stdlib = {d.name for d in a.definitions if in_stdlib(d.span.file)}
    out: list[tuple[Span, str, tuple[str, ...]]] = []
    for w in words(a.path, a.text):
        kind = None
        if any(_inside(w.span, m) for m in params.get(w.text, ())):
            kind = "parameter"
        if kind is None and w.in_string:
            continue
        if kind is None:
            kind = scope.get(w.text)
        mods: tuple[str, ...] = ()
        if kind is None and w.text in _BUILTIN_SORTS:
            kind, mods = "sort", ("defaultLibrary",)
        if kind is None or kind not in _KIND_TYPE:
            continue
        if w.span.start in declared:
            mods = ("declaration",)
        elif w.text in stdlib:
            mods = ("defaultLibrary",)
        out.append((w.span, _KIND_TYPE[kind], mods))
    return out


# ---------------------------------------------------------------- inlay hints


def unit_hints(a: Analysis) -> list[tuple[Span, str, str]]:
    """(span of a use, unit, resource) for every use of a resource with a ``:unit`` in the
    document's expressions (not its declaration, not a view's or hole's list)."""
    from catgrammar import ast

    units: dict[str, str] = {}
    for dom in a.domains:
        for r in dom.resources.values():
            if r.unit and r.name not in units:
                units[r.name] = str(r.unit)
    if not units:
        return []
    skip: list[Span] = []  # declarations and name lists
    params = param_scopes(a, a.path)
    if a.tree is not None:
        for top in a.tree.definitions:
            for s in top.sections:
                if isinstance(s, (ast.Resources, ast.ViewDecl, ast.HoleDecl, ast.Requirements)):
                    skip.append(s.span)
    out: list[tuple[Span, str, str]] = []
    for w in words(a.path, a.text):
        unit = units.get(w.text)
        if unit is None or w.in_string or any(_inside(w.span, s) for s in skip):
            continue
        if any(_inside(w.span, m) for m in params.get(w.text, ())):
            continue  # a parameter of that name hides the resource
        out.append((w.span, unit, w.text))
    return out


# ---------------------------------------------------------------- signature help

#: What each option of a form takes and does (docs/language.md); every option the grammar
#: accepts for a morphism, resource, parameter, hole or view has an entry (a test checks it).
OPTION_DOCS: dict[str, tuple[str, str]] = {
    ":kind": (
        ":kind hardware|software|behavior",
        "what the component is (default software)",
    ),
    ":churn": (
        ":churn Q",
        "weight of adding or removing it in recomposition (default 1)",
    ),
    ":uses": (
        ":uses N",
        "at most N activations (default unlimited; 0 switches it off)",
    ),
    ":cost": (
        ":cost E",
        "cost per activation, a number or an expression over the parameters (default 1)",
    ),
    ":parameters": (
        ":parameters ((θ SORT ...) ...)",
        "the θ parameters the solver chooses",
    ),
    ":precondition": (":precondition P", "what must hold before an activation"),
    ":effect": (
        ":effect E",
        "(and ...), (assign r v), (increase r v), (decrease r v), (add s x), (remove s x)",
    ),
    ":doc": (':doc "text"', "documentation, shown on hover"),
    ":ground": (
        ":ground (hardware|software|behavior ...)",
        "what it becomes on the robot (docs/grounding.md)",
    ),
    ":group": (
        ":group NAME",
        "the partial state it belongs to (electromechanical, compute, info, external, ...)",
    ),
    ":unit": (":unit NAME", "its unit, shown with values and relaxations"),
    ":bounds": (":bounds (LO HI)", "an invariant in every state; * leaves a side open"),
    ":fixed": (":fixed", "one value shared by every activation"),
    ":view": (":view NAME", "the view the hole's morphisms are written in"),
    ":max-effects": (":max-effects N", "at most N effects per synthesised morphism"),
    ":max-preconditions": (
        ":max-preconditions N",
        "at most N preconditions per synthesised morphism",
    ),
    ":keep": (":keep (r ...)", "the resources the view keeps"),
    ":drop": (":drop (r ...)", "the resources the view hides"),
}


@dataclass(frozen=True)
class Signature:
    label: str
    doc: str
    options: tuple[str, ...]  # the label of each option (as in ``label``)
    option_docs: tuple[str, ...]
    active: int | None


def _forms() -> dict[str, tuple[str, tuple[str, ...]]]:
    from catgrammar.symbols import (
        HOLE_OPTIONS,
        MORPHISM_OPTIONS,
        PARAMETER_OPTIONS,
        RESOURCE_OPTIONS,
        VIEW_OPTIONS,
    )

    def keys(opts) -> tuple[str, ...]:
        return tuple(o.value for o in opts)

    return {
        "morphism": ("(:morphism NAME", keys(MORPHISM_OPTIONS)),
        "resource": ("(NAME SORT", keys(RESOURCE_OPTIONS)),
        "parameter": ("(θ SORT", keys(PARAMETER_OPTIONS)),
        "hole": ("(:hole NAME", keys(HOLE_OPTIONS)),
        "view": ("(:view NAME", keys(VIEW_OPTIONS)),
    }


def signature_at(text: str, offset: int) -> Signature | None:
    """The options of the form the cursor (a character offset) is in: a morphism, a
    resource of ``(:resources ...)``, a θ of ``:parameters``, a hole or a view; the active
    one is the last option keyword before the cursor."""
    stack: list[list[tuple[str, str]]] = []  # each open parenthesis: its tokens so far
    parents: list[str] = []  # what each open parenthesis is (by its head)
    for kind, value, pos in tokens(text[:offset]):
        if pos >= offset:
            break
        if kind == "LPAR":
            head = stack[-1] if stack else []
            parents.append(_what(head, parents[-1] if parents else ""))
            stack.append([])
        elif kind == "RPAR":
            if stack:
                stack.pop()
                parents.pop()
        elif stack:
            stack[-1].append((kind, value))
    # the innermost form with options
    forms = _forms()
    for depth in range(len(stack) - 1, -1, -1):
        frame, parent = stack[depth], parents[depth]
        form = _form_of(frame, parent)
        if form is None:
            continue
        opener, options = forms[form]
        labels = tuple(OPTION_DOCS.get(o, (o, ""))[0] for o in options)
        docs = tuple(OPTION_DOCS.get(o, (o, ""))[1] for o in options)
        active = None  # the last option written before the cursor (inside its value, or after it)
        for _, value in reversed(frame):
            if value in options:
                active = options.index(value)
                break
        return Signature(
            f"{opener} {' '.join(labels)})",
            f"the options of a {form}",
            labels,
            docs,
            active,
        )
    return None


def _what(frame: list[tuple[str, str]], enclosing: str) -> str:
    """What a parenthesis opened after ``frame``'s tokens is, from that frame (of kind
    ``enclosing``): an item of ``(:resources ...)``, the list of ``:parameters`` or one θ."""
    if enclosing == "parameters":
        return "params-item"
    if not frame:
        return ""
    if frame[0][1] == ":resources":
        return "resources-item"
    if frame[0][1] == ":morphism" and frame[-1][1] == ":parameters":
        return "parameters"
    return ""


def _form_of(frame: list[tuple[str, str]], parent: str) -> str | None:
    if not frame:
        return None
    head = frame[0][1]
    if head == ":morphism":
        return "morphism"
    if head == ":hole":
        return "hole"
    if head == ":view":
        return "view"
    if parent == "resources-item" and frame[0][0] == "NAME":
        return "resource"
    if parent == "params-item" and frame[0][0] == "NAME":
        return "parameter"
    return None


# ---------------------------------------------------------------- formatting


def formatted(text: str) -> str | None:
    """``catc fmt`` of ``text``, or None when the text does not parse (nothing to do)."""
    from catc.frontend.formatter import FormatError, format_text
    from catgrammar.diagnostics import Diagnostics
    from catgrammar.parser import parse_source

    diags = Diagnostics()
    if parse_source(Source("<format>", text), diags) is None or diags.has_errors:
        return None
    try:
        return format_text(text)
    except FormatError:
        return None
