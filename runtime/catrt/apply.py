"""Applying a change event to the model: the new model state, checked by catc's own checker
before anything is stored, or a rejection that says which field of the event is wrong.

Text an event brings (a goal, a metric, soft constraints, morphisms) becomes part of a
``.cat`` file, so it is first checked to be what its field says — one balanced expression,
or ``(:morphism ...)`` declarations — and can never close the section it is put in.  The
candidate model is then written out and checked in memory (:func:`catc.api.loads`); every
error is mapped back to the event field whose text it points into.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from catc import ir
from catc.api import CatError, Model, loads
from catgrammar.diagnostics import Diagnostic
from catrt.changes import registry as changes
from catrt.changes.base import Rejection
from catrt.events import Event
from catrt.model import PROBLEM_FILE, ModelState, Region, problem_text, texts

__all__ = ["Candidate", "Rejection", "apply_change", "check", "check_values"]


@dataclass
class Candidate:
    """A model state and its checked instance (with the files it was checked as)."""

    state: ModelState
    model: Model
    files: dict[str, str] = field(default_factory=dict)

    @property
    def instance(self) -> ir.Instance:
        return self.model.instance


# ---------------------------------------------------------------- applying


def apply_change(
    state: ModelState, inst: ir.Instance, sources: Mapping[str, str], event: Event
) -> tuple[ModelState, dict[str, str]]:
    """The model state after a change event, and the origins of its generated text
    (``init.budget`` → ``set.budget``, ...); Rejection when a field cannot apply.  Each kind
    of change the event carries applies in turn (:mod:`catrt.changes.registry`)."""
    origins: dict[str, str] = {}
    for change in changes.for_fields(event.body):
        state = change.apply(state, inst, sources, event.body, origins)
    return state, origins


def _only_values(body: Mapping[str, Any]) -> bool:
    """The event changes initial values and nothing else."""
    return set(body) == {"set"}


def check_values(current: Candidate, state: ModelState, body: Mapping[str, Any]) -> Candidate | None:
    """The candidate after an event that only sets numeric or Boolean initial values, made
    from the checked ``current`` one without parsing or checking the sources again: each
    value was converted and checked for its sort by :func:`apply_change`; here it is checked
    against its resource's bounds and put into the problem.  Only the problem's text is
    written anew (for the model files and the digest); the other files cannot change.
    None when the event is of another kind, or a value is out of bounds, or of a resource
    of another sort: then :func:`check` checks the whole model, and says what is wrong."""
    if not _only_values(body):
        return None
    inst = current.instance
    init = dict(inst.problem.init)
    for name in body["set"]:
        r, old, value = inst.resources.get(name), init.get(name), state.problem.init.get(name)
        if r is None or old is None or not isinstance(old.value, ir.Const) or isinstance(value, list):
            return None
        if r.sort.is_numeric and isinstance(value, str):
            number = Fraction(value)
            if (r.lower is not None and number < r.lower) or (r.upper is not None and number > r.upper):
                return None
            new: Fraction | bool = number
        elif r.sort.kind is ir.SortKind.BOOL and isinstance(value, bool):
            new = value
        else:
            return None
        init[name] = dataclasses.replace(old, value=dataclasses.replace(old.value, value=new, span=None), span=None)
    problem = dataclasses.replace(inst.problem, init=ir.frozen(init))
    model = Model(dataclasses.replace(inst, problem=problem), current.model.limits)
    files = dict(current.files)
    path = next(p for p in files if p.endswith("/" + PROBLEM_FILE))
    files[path] = problem_text(state.problem, path, {})[0]
    return Candidate(state, model, files)


def check(
    state: ModelState,
    sources: Mapping[str, str],
    folder: str,
    origins: Mapping[str, str] | None = None,
    cache: Any = None,
) -> Candidate:
    """Check a model state as catc would check its files; Rejection (the errors mapped to
    the event fields behind them) when it does not check.  ``cache``
    (:func:`catc.api.text_cache`): the files and domains of the runtime's earlier checks,
    reused where unchanged — usually all but the problem."""
    files, regions = texts(state, sources, folder, origins)
    problem = next(p for p in files if p.endswith("/problem.cat"))
    try:
        model = loads(files, problem, cache=cache)
    except CatError as exc:
        details = [_locate(d, files, regions) for d in exc.diagnostics if d.severity.value == "error"]
        fields = sorted({d["field"] for d in details if d["field"] != "model"})
        what = f"its {', '.join(fields)} would not check" if fields else "the model would not check"
        raise Rejection(what, details) from None
    return Candidate(state, model, files)


def _locate(d: Diagnostic, files: Mapping[str, str], regions: list[Region]) -> dict[str, Any]:
    """A checker error as (field, line, column) within the event field it points into."""
    out: dict[str, Any] = {"code": d.code, "severity": d.severity.value, "message": d.message, "field": "model"}
    span = d.span
    if span is None:
        return out
    for region in regions:
        if region.file == span.file and region.start <= span.start < max(region.end, region.start + 1):
            if region.origin == "model":
                break
            text = files[region.file][region.start : span.start]
            out["field"], _, at = region.origin.partition("@")
            if out["field"].startswith("set."):  # a value, not text: "(= ram -1)" has no column of the event's
                return out
            lines, columns = (int(n) for n in at.split(":")) if at else (0, 0)
            out["line"] = lines + text.count("\n") + 1
            out["column"] = len(text) - (text.rfind("\n") + 1) + 1 + (0 if "\n" in text else columns)
            return out
    out["field"] = "model"
    out["line"], out["column"], out["file"] = span.line, span.column, span.file
    return out
