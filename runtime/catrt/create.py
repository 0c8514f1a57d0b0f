"""``catrt init``: a new state folder for a model.

The model is checked as ``catc`` checks it; every file it is made of — the domain, the
domains it imports, the standard library's among them — is stored as it is, so that the
runtime's model never changes under it when files on disk or catc's standard library do.
Problem definitions are cut out of the stored files (the problem lives in the store as data,
:mod:`catrt.model`).  The folder gets the store, ``config.toml`` (from a template unless
given), ``spool/`` for events, and ``model/`` with the model as files.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

from catc import __version__ as catc_version
from catc import ir
from catc.api import CatError, load, outline
from catrt.apply import check
from catrt.config import CONFIG_NAME, TEMPLATE
from catrt.model import initial_model
from catrt.runtime import MODEL_FOLDER
from catrt.store import Store, StoreError

SPOOL = "spool"


def model_files(inst: ir.Instance) -> list[str]:
    """Every file the checked instance's domain is made of."""
    d = inst.domain
    spans = [d.span]
    for table in (d.sorts, d.constants, d.resources, d.morphisms, d.holes, d.views):
        spans += [getattr(item, "span", None) for item in table.values()]
    return sorted({s.file for s in spans if s is not None and s.file})


def without_problems(path: str, text: str) -> str:
    """``text`` with every ``(define (problem ...))`` cut out (the store keeps the problem as data)."""
    try:
        definitions = outline(text, path)
    except CatError:
        return text
    cuts = sorted((d.start, d.end) for d in definitions if d.kind == "problem")
    out, pos = [], 0
    for start, end in cuts:
        out += [text[pos:start], "; (a problem: the runtime keeps it in its store)"]
        pos = end
    return "".join(out) + text[pos:]


def create(
    folder: Path,
    problem: str,
    domain: str | None = None,
    *,
    problem_name: str | None = None,
    search_paths: Iterable[str] = (),
    config_text: str | None = None,
) -> Store:
    """A new store for the model in ``problem`` (and ``domain``); CatError when it does not
    check, StoreError when ``folder`` holds a store already."""
    if (folder / "catrt.sqlite").exists():
        raise StoreError("E1006", f"{folder} already holds a catrt store; use another folder, or delete it first")
    model = load(
        *([] if domain is None else [domain]), problem, problem_name=problem_name, search_paths=list(search_paths)
    )
    inst = model.instance
    files = model_files(inst)
    sources: dict[str, str] = {}
    for path in files:
        name = os.path.basename(path)
        if name in sources or name == "problem.cat":
            raise StoreError("E1005", f"two files of the model are named {name}: catrt keeps them in one folder")
        sources[name] = without_problems(path, Path(path).read_text(encoding="utf-8"))
    domain_file = os.path.basename(inst.domain.span.file) if inst.domain.span else files[0]
    problem_text = Path(inst.problem.span.file if inst.problem.span else problem).read_text(encoding="utf-8")
    state = initial_model(inst, problem_text, domain_file)
    check(state, sources, str(folder / MODEL_FOLDER))  # the stored model checks as the given one did
    store = Store.create(folder, sources, {"model": state.to_json(), "incumbent": None, "enacting": None,
                                           "generation": 0}, catc_version)  # fmt: skip
    with store.transaction():
        store.journal("init", {"model": state.to_json(), "sources": {n: t for n, t in sources.items()},
                               "problem_file": str(problem), "problem_text": problem_text,
                               "catc_version": catc_version})  # fmt: skip
    (folder / SPOOL).mkdir(exist_ok=True)
    config = folder / CONFIG_NAME
    if not config.exists():
        config.write_text(config_text if config_text is not None else TEMPLATE, encoding="utf-8")
    return store
