"""Front-end entry points shared by the CLI, the language server and the Python API:
files → checked IR, with every error and lint in a :class:`Diagnostics`.

The parser, the checker and the lints load when a function here first needs them: a query
whose model is kept checked between runs (:mod:`catc.frontend.model_cache`) answers
without them (the start-up of every query: docs/benchmarks.md)."""

from __future__ import annotations

import os
import time
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from catc import ir
from catc.ir.views import ViewError, apply_view
from catgrammar import codes
from catgrammar.diagnostics import Diagnostics

if TYPE_CHECKING:
    from catc.frontend.workspace import TextCache, Workspace
    from catgrammar import ast


def new_text_cache() -> TextCache:
    """An empty :class:`~catc.frontend.workspace.TextCache` (for :func:`load_texts`)."""
    from catc.frontend.workspace import TextCache

    return TextCache()


def is_user_file(path: str) -> bool:
    """Lints are reported for the user's files, not for the standard library."""
    from catc.frontend.workspace import stdlib_dir

    try:
        return stdlib_dir() not in Path(path).resolve().parents
    except OSError:  # pragma: no cover
        return True


def check_files(
    files: list[str], diags: Diagnostics, search_paths: tuple[str, ...] | list[str] = ()
) -> tuple[dict[str, ir.Domain], dict[str, ir.Instance]]:
    """Check every definition in ``files``: errors and lints go to ``diags``."""
    from catc.frontend.workspace import Workspace

    ws = Workspace(diags, search_paths)
    parsed: list[tuple[str, ast.SourceFile]] = []
    for f in files:
        sf = ws.load(f)
        if sf is not None:
            parsed.append((f, sf))
    return check_parsed(ws, parsed, diags)


def check_parsed(
    ws: Workspace, parsed: list[tuple[str, ast.SourceFile]], diags: Diagnostics
) -> tuple[dict[str, ir.Domain], dict[str, ir.Instance]]:
    """Check the definitions of files already loaded into ``ws`` (the CLI and the
    language server share this): domains, then problems with their views, then lints."""
    from catc.frontend.lints import lint_domain, lint_instance
    from catgrammar import ast

    domains: dict[str, ir.Domain] = {}
    instances: dict[str, ir.Instance] = {}
    for path, sf in parsed:
        for d in sf.definitions:
            if isinstance(d, ast.Domain) and any(d is e for e, _ in ws.domains.get(d.name.text, [])):
                dom = ws.domain_ir(d.name.text, path, d.name.span)
                if dom is not None:
                    domains[dom.name] = dom
    checked: list[ir.Instance] = []
    for path, sf in parsed:
        for d in sf.definitions:
            if isinstance(d, ast.Problem) and any(d is e for e, _ in ws.problems.get(d.name.text, [])):
                inst = ws.check_problem(d, path)
                if inst is None:
                    continue
                try:
                    apply_view(inst, None)
                except ViewError as exc:
                    diags.report(codes.BAD_VIEW, str(exc), exc.span or d.name.span)
                    continue
                instances[inst.problem.name] = inst
                checked.append(inst)
    for dom in ws.checked_domains():
        # an instance may hold a projection of its domain (imported resources left out): same name and place
        mine = [i.problem for i in checked if i.domain is dom or (i.domain.name, i.domain.span) == (dom.name, dom.span)]
        lint_domain(dom, diags, is_user_file, mine)
    for inst in checked:
        lint_instance(inst, diags, is_user_file)
    return domains, instances


def load_texts(
    texts: Mapping[str, str],
    problem: str,
    diags: Diagnostics,
    *,
    view: str | None = None,
    problem_name: str | None = None,
    search_paths: Iterable[str | os.PathLike[str]] = (),
    text_cache: TextCache | None = None,
) -> ir.Instance | None:
    """Files given as text (path → text; imports not among them come from the disk) → the
    checked instance of the problem in ``texts[problem]``, or None with errors in ``diags``.
    Every given file is loaded first, so a domain among them is found by name wherever its
    path points (the runtime checks candidate models this way before it writes them).
    ``text_cache``: what an earlier check of the same model parsed and checked, reused where
    the files are unchanged (:class:`~catc.frontend.workspace.TextCache`)."""
    from catc.frontend.workspace import Workspace, load_instance

    found = Diagnostics() if text_cache is not None else diags
    ws = Workspace(found, tuple(str(p) for p in search_paths), texts, text_cache=text_cache)
    for path in texts:
        if path != problem:
            ws.load(path)
    _, inst = load_instance(None, problem, found, problem_name=problem_name, workspace=ws)
    if ws.reused_domains and ws.fresh_domains:  # a domain parsed anew after one was reused: check afresh
        return load_texts(texts, problem, diags, view=view, problem_name=problem_name, search_paths=search_paths)
    if found is not diags:
        diags.extend(found)
    return _viewed(inst, view, diags)


def _viewed(inst: ir.Instance | None, view: str | None, diags: Diagnostics) -> ir.Instance | None:
    """A loaded instance with its view applied, or None (errors in ``diags``)."""
    if inst is None or diags.has_errors:
        return None
    try:
        return apply_view(inst, view)
    except ViewError as exc:
        diags.report(codes.BAD_VIEW, str(exc), exc.span)
        return None


def load_checked(
    problem: str | os.PathLike[str],
    domain: str | os.PathLike[str] | None,
    diags: Diagnostics,
    *,
    view: str | None = None,
    problem_name: str | None = None,
    search_paths: Iterable[str | os.PathLike[str]] = (),
    stdlib_cache: Path | None = None,
    model_cache: Path | None = None,
) -> ir.Instance | None:
    """Files → the checked instance with its view applied, or None with errors in ``diags``
    (the front end of every query: the command line, the API, the language server).  Paths
    are written as ``catc check`` writes them (``./x.cat`` is ``x.cat``) in diagnostics.
    ``stdlib_cache``: a folder where checked standard-library domains are kept between runs
    (:mod:`catc.frontend.stdlib_cache`; the command line's, under the user's cache folder).
    ``model_cache``: a folder where checked models are kept between runs, with
    ``stdlib_cache`` (:mod:`catc.frontend.model_cache`; the command line's)."""
    from catc.frontend.stdlib_cache import StdlibCache, stdlib_dir

    problem = str(Path(problem))
    domain = None if domain is None else str(Path(domain))
    found = tuple(str(p) for p in search_paths)
    stdlib = None if stdlib_cache is None else StdlibCache(stdlib_cache, stdlib_dir())
    kept = None
    if stdlib is not None and model_cache is not None:
        from catc.frontend.model_cache import ModelCache

        kept = ModelCache(model_cache, stdlib)
        request = kept.request(problem, domain, view, problem_name, found)
        inst = kept.get(request)
        if inst is not None:
            return inst
    paths = [problem] if domain is None else [domain, problem]
    for p in paths:
        if Path(p).is_dir():
            diags.report(codes.UNREADABLE_FILE, f"cannot read '{p}': it is a folder; give a .cat file", None)
        elif not Path(p).is_file():
            diags.report(codes.UNREADABLE_FILE, f"cannot read '{p}': no such file", None)
    if diags.has_errors:
        return None
    from catc.frontend.workspace import Workspace, load_instance

    ws = Workspace(diags, found, stdlib_cache=stdlib)
    began = time.time_ns()
    _, inst = load_instance(None if domain is None else str(domain), str(problem), diags, found, problem_name, ws)
    viewed = _viewed(inst, view, diags)
    if kept is not None and viewed is not None and len(diags) == 0:
        from catc.frontend.model_cache import reads

        read = reads(ws, began)
        if read is not None:
            kept.put(request, read, viewed)
    return viewed
