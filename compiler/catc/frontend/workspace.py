"""Finding, parsing and checking files: the workspace.

A :class:`Workspace` owns every parsed file of a run.  Domains are found by name, in this
order: a file already loaded from the folder of the file that refers to the domain; a file
the user gave (on the command line, or as text); the other ``.cat`` files of that folder;
the other loaded files; the extra search paths (``--path`` and ``CATC_PATH``); and the
standard library (``stdlib_domains``).  Each domain is checked once; import cycles are
reported.

Files that were not asked for are read with care: only regular files (a FIFO or a device
could block or never end) of at most the input-bytes limit (docs/limits.md), searched for
``(define (domain NAME`` with the language's own tokenizer (a comment inside the header
changes nothing), and parsed on their own: one that fails to parse is passed over when
another file defines the domain, and its errors are shown only when none does.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Mapping
from pathlib import Path

from catc import ir
from catc.frontend.check import DomainChecker, ProblemChecker
from catc.frontend.stdlib_cache import StdlibCache, stdlib_dir
from catgrammar import ast, codes, limits
from catgrammar._lalr import UnexpectedCharacters
from catgrammar.diagnostics import Diagnostics, Note, Suggestion
from catgrammar.parser import decode_source, parse_source, read_regular, read_source
from catgrammar.span import Source, Span
from catgrammar.tokens import tokenize


def stdlib_names() -> list[str]:
    """The standard library's domains, by its registry (``stdlib_domains.DOMAINS``)."""
    try:
        from stdlib_domains import DOMAINS
    except ImportError:  # pragma: no cover - running from a bare checkout
        return sorted(p.stem for p in stdlib_dir().glob("*.cat"))
    return sorted(DOMAINS)


class _Stdlib:
    """Not found outside the standard library: look there (a sentinel)."""


_STDLIB = _Stdlib()


class Loaded:
    """A parsed file and where it was read from."""

    __slots__ = ("path", "file")

    def __init__(self, path: str, file: ast.SourceFile) -> None:
        self.path = path
        self.file = file


def normalise_path(path: str) -> str:
    """The key of a file among those loaded (absolute, case-normalised where the OS is)."""
    return os.path.normcase(os.path.abspath(path))


def _folder(path: str) -> Path:
    return Path(path).resolve().parent


_HEADER = ("LPAR", "_DEFINE_WORD", "LPAR", "_DOMAIN_WORD")


def defined_domains(text: str) -> list[str]:
    """The names of the domains ``text`` defines (``(define (domain NAME``), found by the
    language's tokenizer, so comments and strings never count and a comment inside the
    header changes nothing; a character no token starts with ends the search."""
    if "domain" not in text:
        return []
    names: list[str] = []
    window: tuple[str, ...] = ("",) * len(_HEADER)
    try:
        for tok in tokenize(text):
            if tok.type == "NAME" and window == _HEADER:
                names.append(tok.value)
            window = (*window[1:], tok.type)
    except UnexpectedCharacters:
        pass
    return names


class TextCache:
    """What one check of a model leaves for the next (the runtime checks its model after
    every change, and usually only the problem's text changed): each file parsed without a
    word, by (path, text), and each domain checked without a word, by its parsed node.  A
    checked domain is reused only when no file that defines a domain was parsed anew
    (:func:`catc.frontend.session.load_texts` checks again without the cache otherwise)."""

    def __init__(self) -> None:
        self.files: dict[str, tuple[str, ast.SourceFile]] = {}  # path → (its text, parsed): the latest only
        self.domains: dict[int, tuple[ast.Domain, ir.Domain]] = {}  # id(node) → (node, IR): the node kept alive

    def parsed(self, path: str, text: str) -> ast.SourceFile | None:
        kept = self.files.get(path)
        return kept[1] if kept is not None and kept[0] == text else None

    def keep(self, path: str, text: str, parsed: ast.SourceFile) -> None:
        """Keep ``parsed`` as the file at ``path``; the domains of the file it replaces go."""
        old = self.files.get(path)
        if old is not None:
            for d in old[1].definitions:
                self.domains.pop(id(d), None)
        self.files[path] = (text, parsed)


class Workspace:
    def __init__(
        self,
        diags: Diagnostics,
        search_paths: list[str] | tuple[str, ...] = (),
        texts: Mapping[str, str] | None = None,
        scan_max_bytes: int | None = None,
        stdlib_cache: StdlibCache | None = None,
        text_cache: TextCache | None = None,
    ):
        """``search_paths``: extra folders to look for domains in, in order (the interfaces
        add ``--path`` and ``CATC_PATH``; nothing here reads the environment).  ``texts``:
        files given as text (path → text), read instead of the disk (the runtime's model).
        ``scan_max_bytes``: the largest file read while looking for a domain (default: the
        input-bytes limit in force, :mod:`catgrammar.limits`).  ``stdlib_cache``: where
        checked standard-library domains are kept between runs (the command line's; none:
        each is parsed and checked).  ``text_cache``: files and domains of an earlier check
        of the same model, reused where unchanged (:class:`TextCache`)."""
        self.diags = diags
        self.texts = {normalise_path(k): v for k, v in (texts or {}).items()}
        self.search_paths = [Path(p) for p in search_paths]
        self.files: dict[str, ast.SourceFile | None] = {}
        #: every loaded definition by name: several when unrelated folders reuse a name
        self.domains: dict[str, list[tuple[ast.Domain, str]]] = {}
        self.problems: dict[str, list[tuple[ast.Problem, str]]] = {}
        self._checked: dict[int, ir.Domain | None] = {}  # id(ast.Domain) → checked IR
        self._stack: list[tuple[str, int]] = []
        self.stdlib = stdlib_dir()
        self.scan_max_bytes = limits.current().input_bytes if scan_max_bytes is None else scan_max_bytes
        #: files loaded while looking for a domain (the others were given)
        self.discovered: set[str] = set()
        self._defines: dict[str, list[str]] = {}  # a file not loaded → the domains it defines
        self._listed: dict[Path, list[Path]] = {}  # a folder → its .cat files, sorted (listed once)
        self._resolved: dict[str, Path] = {}  # a file → its folder, resolved (once)
        self._real: dict[Path, Path] = {}  # a folder → itself, resolved (once)
        self.stdlib_cache = stdlib_cache
        self._cached: dict[str, ir.Domain] = {}  # standard-library domains read from stdlib_cache
        self.text_cache = text_cache
        self.fresh_domains = False  # a file defining a domain was parsed anew (not from text_cache)
        self.reused_domains = False  # a checked domain came from text_cache

    # -------------------------------------------------------------- files
    def load(self, path: str) -> ast.SourceFile | None:
        key = normalise_path(path)
        if key in self.files:
            return self.files[key]
        self.files[key] = None
        src = Source(path, self.texts[key]) if key in self.texts else read_source(path, self.diags)
        cache = self.text_cache
        parsed = cache.parsed(key, src.text) if cache is not None and src is not None else None
        if parsed is not None and src is not None:
            self.diags.add_source(src)  # the source its diagnostics point into
        elif src is not None:
            reported = len(self.diags)
            parsed = parse_source(src, self.diags)
            if parsed is not None and any(isinstance(d, ast.Domain) for d in parsed.definitions):
                self.fresh_domains = True
            if cache is not None and parsed is not None and len(self.diags) == reported:
                cache.keep(key, src.text, parsed)
        self.files[key] = parsed
        if parsed is not None:
            for d in parsed.definitions:
                self.index(d, path)
        return parsed

    def index(self, d: ast.Definition, path: str) -> None:
        """Record a definition.  Two definitions of one name in one folder are ambiguous
        (a reference from that folder could mean either); in different folders they are not."""
        table = self.domains if isinstance(d, ast.Domain) else self.problems
        what = "domain" if isinstance(d, ast.Domain) else "problem"
        entries = table.setdefault(d.name.text, [])
        folder = _folder(path)
        for prev, prev_path in entries:
            if _folder(prev_path) == folder:
                where = (
                    "twice in one file"
                    if normalise_path(prev_path) == normalise_path(path)
                    else "in two files of one folder"
                )
                self.diags.report(
                    codes.DUPLICATE_DEFINITION,
                    f"{what} '{d.name.text}' is defined {where}",
                    d.name.span,
                    Note("also defined here", prev.name.span),
                )
                return
        entries.append((d, path))  # type: ignore[arg-type]

    def _scan(self, folder: Path, name: str) -> tuple[ast.Domain, str] | None:
        """Load the ``.cat`` files of ``folder`` that define domain ``name`` (by their
        tokens), until one parses; the errors of those that do not are reported only when
        none does."""
        if not folder.is_dir():
            return None
        found = self._in_folder(name, folder)
        if found:
            return found
        failed: Diagnostics | None = None
        for path, src in self._candidates(folder, name):
            local = Diagnostics()
            parsed = parse_source(src, local)
            self.files[normalise_path(path)] = parsed
            self.discovered.add(normalise_path(path))
            if parsed is None:
                failed = failed or local
                continue
            self.diags.extend(local)
            for d in parsed.definitions:
                self.index(d, path)
            found = self._in_folder(name, folder)
            if found:
                return found
        if failed is not None:
            self.diags.extend(failed)
        return None

    def _candidates(self, folder: Path, name: str) -> Iterator[tuple[str, Source]]:
        """The files of ``folder`` not loaded yet whose tokens define domain ``name``
        (``NAME.cat`` first): regular files of at most ``scan_max_bytes``, valid UTF-8."""
        preferred = folder / f"{name}.cat"
        listed = self._listed.get(folder)
        if listed is None:
            listed = self._listed[folder] = sorted(folder.glob("*.cat"))
        for p in [preferred, *(p for p in listed if p != preferred)]:
            key = normalise_path(str(p))
            if key in self.files:
                continue
            src = self._sibling_source(str(p), key)
            if src is None:
                continue
            if key not in self._defines:
                self._defines[key] = defined_domains(src.text)
            if name in self._defines[key]:
                yield str(p), src

    def _sibling_source(self, path: str, key: str) -> Source | None:
        """A file nobody asked for, or None when it is not a regular file, is larger than
        ``scan_max_bytes``, cannot be read or is not UTF-8 text (it is passed over)."""
        if key in self.texts:
            return Source(path, self.texts[key])
        try:
            data = read_regular(path, self.scan_max_bytes)
        except OSError:
            return None
        if len(data) > self.scan_max_bytes:
            return None
        return decode_source(path, data, Diagnostics())

    def _in_folder(self, name: str, folder: Path) -> tuple[ast.Domain, str] | None:
        target = self._real.get(folder)
        if target is None:
            target = self._real[folder] = folder.resolve()
        for d, p in self.domains.get(name, []):
            found = self._resolved.get(p)
            if found is None:
                found = self._resolved[p] = _folder(p)
            if found == target:
                return d, p
        return None

    def find_domain(self, name: str, near: str | None, ref: Span | None = None) -> tuple[ast.Domain, str] | None:
        """The domain ``name`` as seen from the file ``near``: a loaded file of its own folder,
        the one given file that defines it, the other files of that folder, the other loaded
        files (when exactly one folder defines it), ``--path``, the stdlib."""
        found = self._find_outside_stdlib(name, near, ref)
        return self._scan(self.stdlib, name) if isinstance(found, _Stdlib) else found

    def _find_outside_stdlib(
        self, name: str, near: str | None, ref: Span | None
    ) -> tuple[ast.Domain, str] | _Stdlib | None:
        """What :meth:`find_domain` finds before the stdlib: a domain, None (not found, and
        an error reported: defined in several folders), or ``_STDLIB`` (look there)."""
        if near is not None:
            found = self._in_folder(name, Path(near).parent)
            if found:
                return found
        given = [(d, p) for d, p in self.domains.get(name, []) if normalise_path(p) not in self.discovered]
        if len(given) == 1:  # a file the user named wins over one beside the problem
            return given[0]
        if near is not None:
            found = self._scan(Path(near).parent, name)  # unresolved: keep the user's relative paths
            if found:
                return found
        loaded = self.domains.get(name, [])
        if len(loaded) == 1:
            return loaded[0]
        if len(loaded) > 1:
            self.diags.report(
                codes.DUPLICATE_DEFINITION,
                f"domain '{name}' is defined in several folders; keep the problem next to the one it means "
                f"or pass only that one",
                ref,
                *[Note("defined here", d.name.span) for d, _ in loaded],
            )
            return None
        for folder in self.search_paths:
            found = self._scan(folder, name)
            if found:
                return found
        return _STDLIB

    def scanned(self) -> list[str]:
        """The files read only to look for a domain's header (:meth:`_candidates`), by key."""
        return list(self._defines)

    def known_domain_names(self) -> list[str]:
        return sorted(set(self.domains) | set(stdlib_names()))

    # -------------------------------------------------------------- checking
    def domain_ir(self, name: str, near: str | None, ref: Span | None, importing: bool = False) -> ir.Domain | None:
        found = self._find_outside_stdlib(name, near, ref)
        if isinstance(found, _Stdlib):
            cached = self._from_cache(name)
            if cached is not None:
                return cached
            found = self._scan(self.stdlib, name)
        if found is None:
            if not self.domains.get(name) or len(self.domains[name]) <= 1:
                code = codes.UNKNOWN_IMPORT if importing else codes.UNKNOWN_DOMAIN
                what = "imported domain" if importing else "domain"
                hint = Suggestion(name, self.known_domain_names(), ref)
                self.diags.report(
                    code,
                    f"{what} '{name}' not found (searched the folder of this file, the loaded files, "
                    f"--path/CATC_PATH and the standard library){hint.hint}",
                    ref,
                    fixes=hint.fixes,
                )
            return None
        node, path = found
        key = id(node)
        if any(k == key for _, k in self._stack):
            names = [n for n, _ in self._stack]
            cycle = " -> ".join(names[names.index(name) :] + [name])
            self.diags.report(codes.CIRCULAR_IMPORT, f"circular import: {cycle}", ref)
            return None
        if key in self._checked:
            return self._checked[key]
        kept = self.text_cache.domains.get(key) if self.text_cache is not None and not self.fresh_domains else None
        if kept is not None and kept[0] is node:
            self._checked[key], self.reused_domains = kept[1], True
            return kept[1]
        self._stack.append((name, key))
        reported = len(self.diags)
        try:
            result = DomainChecker(self, node, path, self.diags).run()
        finally:
            self._stack.pop()
        self._checked[key] = result
        if self.text_cache is not None and result is not None and len(self.diags) == reported:
            self.text_cache.domains[key] = (node, result)
        if self.stdlib_cache is not None and result is not None and len(self.diags) == reported:
            self._keep(name, path, result)
        return result

    def _keep(self, name: str, path: str, domain: ir.Domain) -> None:
        """Keep a standard-library domain that checked without a word (its file named after it)."""
        if self.stdlib_cache is not None and _folder(path) == self.stdlib.resolve() and Path(path).stem == name:
            self.stdlib_cache.put(name, domain)

    def _from_cache(self, name: str) -> ir.Domain | None:
        """The standard-library domain ``name`` as kept by :attr:`stdlib_cache` (None: not kept)."""
        if self.stdlib_cache is None or name not in stdlib_names():
            return None
        if name not in self._cached:
            found = self.stdlib_cache.get(name)
            if found is None:
                return None
            self._cached[name] = found
        return self._cached[name]

    def checked_domains(self) -> list[ir.Domain]:
        return [d for d in self._checked.values() if d is not None] + list(self._cached.values())

    def check_problem(self, node: ast.Problem, path: str) -> ir.Instance | None:
        return ProblemChecker(self, node, path, self.diags).run()


def load_instance(
    domain_path: str | None,
    problem_path: str,
    diags: Diagnostics,
    search_paths: list[str] | tuple[str, ...] = (),
    problem_name: str | None = None,
    workspace: Workspace | None = None,
) -> tuple[Workspace, ir.Instance | None]:
    """The common front end of every query command: files → checked instance (in
    ``workspace`` when given: one with files given as text)."""
    ws = workspace if workspace is not None else Workspace(diags, search_paths)
    if domain_path is not None:
        ws.load(domain_path)
    parsed = ws.load(problem_path)
    if parsed is None:
        return ws, None
    problems = [d for d in parsed.definitions if isinstance(d, ast.Problem)]
    if problem_name is not None:
        problems = [p for p in problems if p.name.text == problem_name]
    if not problems:
        _no_problem(ws, parsed, problem_path, problem_name)
        return ws, None
    if len(problems) > 1:
        names = ", ".join(p.name.text for p in problems)
        diags.report(
            codes.MISSING_OPTION,
            f"{problem_path} defines several problems ({names}); choose one with --problem",
            problems[1].name.span,
        )
        return ws, None
    return ws, ws.check_problem(problems[0], problem_path)


def _no_problem(ws: Workspace, parsed: ast.SourceFile, path: str, problem_name: str | None) -> None:
    """The file holds no (such) problem: check the domains it defines, so that their own
    errors are shown as ``catc check`` shows them, and say so at its first definition."""
    domains = [d for d in parsed.definitions if isinstance(d, ast.Domain)]
    for d in domains:
        ws.domain_ir(d.name.text, path, d.name.span)
    what = f"no problem named '{problem_name}'" if problem_name else "no (define (problem ...)) found"
    defines = ", ".join(
        f"{'domain' if isinstance(d, ast.Domain) else 'problem'} '{d.name.text}'" for d in parsed.definitions
    )
    first = parsed.definitions[0].name.span if parsed.definitions else None
    ws.diags.report(codes.MISSING_OPTION, f"{what} in {path} (it defines {defines})", first)
