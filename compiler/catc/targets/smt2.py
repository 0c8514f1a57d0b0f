"""``catc compile``: a problem as SMT-LIB2 text (:func:`catc.smt.smtlib.emit_smt2`), its named
assertions mapping cores back to the source."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from catc import ir
from catc.queries.base import Kind, Option, Use, timeout_option
from catc.targets.base import Target, horizon_option, load_options


def smt2(
    inst: ir.Instance, *, horizon: int | None = None, sequential: bool = False, timeout: float | None = None
) -> str:
    """The SMT-LIB2 script of ``inst`` unrolled to ``horizon`` steps (default: the problem's)."""
    from catc.semantics.horizon import horizon_of
    from catc.smt.smtlib import emit_smt2

    return emit_smt2(inst, horizon_of(inst, horizon), sequential=sequential)


def _write(inst: ir.Instance, text: str, options: Mapping[str, Any]) -> list[str]:
    Path(options["output"]).write_text(text, encoding="utf-8")
    return []


_VIEW, _PATH, _PROBLEM = load_options("Compile this view (overrides the problem's (:view ...)).")

TARGET = Target(
    "smt2",
    command=("compile",),
    summary="Compile a problem to SMT-LIB2 (named assertions map cores back to source).",
    description="PATHS is PROBLEM, or DOMAIN PROBLEM.",
    options=(
        horizon_option(
            "Most steps a composition may take (default: the problem's (:horizon), else the sum of use limits, "
            "else 10)."
        ),
        _VIEW,
        Option(
            "sequential",
            ("--sequential",),
            Kind.FLAG,
            "One morphism per step (default: parallel steps with non-interference).",
        ),
        _PATH,
        _PROBLEM,
        Option(
            "emit",
            ("--emit",),
            Kind.CHOICE,
            "Output language.",
            default="smt2",
            choices=("smt2",),
            show_default=True,
            use=Use.OUTPUT,
        ),
        Option(
            "output", ("-o", "--output"), Kind.OUTPUT_FILE, "Write here instead of standard output.", use=Use.OUTPUT
        ),
        timeout_option("Give up after this many seconds (exit 3, error E1109)."),
    ),
    run=smt2,
    to_json=lambda inst, text: {"schema": "catc.export-smt2/1", "smt2": text},
    render=lambda inst, text: text,
    write=_write,
)
