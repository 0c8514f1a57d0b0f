"""``catc export cat``: a checked model written back as ``.cat`` source by the one writer,
:mod:`catc.targets.catsource` — the domain self-contained (what it imported written into it)
and the problem naming it — in ``catc fmt``'s layout.

The layout is the front end's formatter, which no stage past the front end may import (it
reads tokens): the target names its texts through :attr:`~catc.targets.base.Target.layout`,
and each interface passes the formatter in (``catc.interfaces.layout``), so the command
line, ``Model.export("cat")`` and the language server give the same files."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from catc import ir
from catc.queries.base import Kind, Option, Use, json_option
from catc.targets.base import InputError, Target, load_options
from catc.targets.catsource import CatSourceError, instance_texts
from catgrammar import codes
from catgrammar.record import Record, set_field


class CatFiles(Record):
    """The two texts of an export: ``domain`` (written to ``domain.cat``) and ``problem``
    (``problem.cat``)."""

    __slots__ = ("domain", "problem")
    domain: str
    problem: str

    def __init__(self, domain: str, problem: str) -> None:
        set_field(self, "domain", domain)
        set_field(self, "problem", problem)


def export_cat(inst: ir.Instance, *, header: str | None = None) -> CatFiles:
    """The model as ``.cat`` texts, one section per line (:func:`layout` lays them out);
    ``header``: a comment on top of both.  :class:`InputError` when ``.cat`` cannot spell
    something in it, or the model is projected by a view."""
    try:
        domain, problem = instance_texts(inst, domain_header=header, problem_header=header)
    except CatSourceError as exc:
        raise InputError(f"cannot write the model as .cat: {exc}", codes.EXPORT_UNSUPPORTED) from exc
    return CatFiles(domain, problem)


def layout(files: CatFiles, lay_out: Callable[[str], str]) -> CatFiles:
    """Both texts laid out by ``lay_out`` (the interfaces pass ``catc fmt``'s formatter)."""
    return CatFiles(lay_out(files.domain), lay_out(files.problem))


def _write(inst: ir.Instance, files: CatFiles, options: Mapping[str, Any]) -> list[str]:
    out = Path(options["output"])
    out.mkdir(parents=True, exist_ok=True)
    dom, prob = out / "domain.cat", out / "problem.cat"
    dom.write_text(files.domain, encoding="utf-8")
    prob.write_text(files.problem, encoding="utf-8")
    return [f"wrote {dom}, {prob}"]


_, _PATH, _PROBLEM = load_options("(unused: a view's projection cannot be written back)")

TARGET = Target(
    "cat",
    summary="Write a model back as .cat source: a self-contained domain and its problem.",
    description=(
        "PATHS is PROBLEM, or DOMAIN PROBLEM.  The domain is written with what it imports written "
        "into it; both files are in catc fmt's layout and read back as the same model."
    ),
    options=(
        _PATH,
        _PROBLEM,
        Option("header", ("--header",), Kind.NAME, "A comment written on top of both files.", use=Use.RUN),
        Option(
            "output",
            ("-o", "--output"),
            Kind.OUTPUT_FOLDER,
            "Write domain.cat and problem.cat into this folder (default: print both).",
            use=Use.OUTPUT,
        ),
        json_option("catc.export-cat/1"),
    ),
    run=export_cat,
    to_json=lambda inst, files: {"schema": "catc.export-cat/1", "domain": files.domain, "problem": files.problem},
    render=lambda inst, files: files.domain + "\n" + files.problem,
    write=_write,
    layout=layout,
)
