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
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from catc import ir
from catc.api import CatError, Model, Token, TokenError, convert, loads, tokens
from catc.ir.numbers import ratio_text
from catgrammar.diagnostics import Diagnostic, did_you_mean
from catrt.events import Event, exact, quantity
from catrt.model import PROBLEM_FILE, ModelState, Region, StoredValue, morphisms_in_sources, problem_text, texts


class Rejection(ValueError):
    """Why an event cannot be applied: ``details`` are (field, line, column, code, message)
    — the field of the event an error points into, or ``model`` — each located within that
    field's text."""

    def __init__(self, message: str, details: list[dict[str, Any]] | None = None) -> None:
        super().__init__(message)
        self.message, self.details = message, details or []

    def to_json(self) -> dict[str, Any]:
        return {"message": self.message, "details": self.details}

    def text(self) -> str:
        lines = [self.message]
        for d in self.details:
            where = d.get("file") or d["field"]
            if d.get("line"):
                where += f":{d['line']}:{d['column']}"
            lines.append(f"  = {where}: {d['severity']}[{d['code']}]: {d['message']}")
        return "\n".join(lines)


@dataclass
class Candidate:
    """A model state and its checked instance (with the files it was checked as)."""

    state: ModelState
    model: Model
    files: dict[str, str] = field(default_factory=dict)

    @property
    def instance(self) -> ir.Instance:
        return self.model.instance


# ---------------------------------------------------------------- text fields


def _balanced(text: str, what: str) -> list[Token]:
    """The tokens of ``text`` when it is balanced (never closes more than it opened, closes
    all it opens), else Rejection."""
    try:
        found = tokens(text)
    except TokenError as exc:
        column = exc.column
        raise Rejection(
            f"{what}: a character the language does not have" + (f" at column {column}" if column else "")
        ) from None
    depth = 0
    for tok in found:
        if tok.opens:
            depth += 1
        elif tok.closes:
            depth -= 1
            if depth < 0:
                raise Rejection(f"{what}: a ')' at {tok.line}:{tok.column} closes more than the text opened")
    if depth:
        raise Rejection(f"{what}: {depth} '(' never closed (the text ends at {found[-1].line}:{found[-1].column})")
    if not found:
        raise Rejection(f"{what}: empty")
    return found


def _one_expression(text: str, what: str) -> None:
    depth, tops = 0, 0
    for tok in _balanced(text, what):
        if depth == 0:
            tops += 1
        depth += tok.opens - tok.closes
    if tops != 1:
        raise Rejection(f"{what}: one condition is expected, {tops} were given (combine them with (and ...))")


def _morphisms(text: str) -> list[tuple[str, str, int]]:
    """``(:morphism NAME ...) ...`` → [(NAME, its text, where it starts)], else Rejection."""
    found = _balanced(text, "catalog.add")
    out: list[tuple[str, str, int]] = []
    i = 0
    while i < len(found):
        tok = found[i]
        if not tok.opens or i + 2 >= len(found) or found[i + 1].text != ":morphism":
            raise Rejection(
                f"catalog.add: only (:morphism NAME ...) declarations, found '{tok.text}' at {tok.line}:{tok.column}"
            )
        name = found[i + 2].text
        depth, j = 0, i
        while True:
            depth += found[j].opens - found[j].closes
            if depth == 0:
                break
            j += 1
        out.append((name, text[tok.start : found[j].end], tok.start))
        i = j + 1
    return out


# ---------------------------------------------------------------- values


def _stored(name: str, value: Any, r: ir.Resource) -> StoredValue:
    kind = r.sort.kind
    if r.sort.is_numeric:
        number = exact(value) if isinstance(value, str) else None
        with_unit = quantity(value) if isinstance(value, str) and number is None else None
        if with_unit is not None:
            number = _in_unit(name, value, with_unit, r)
        if number is None:
            raise Rejection(f"set.{name}: {name} is a number ({kind.value}); {json_text(value)} is not one")
        if kind is ir.SortKind.INT and number.denominator != 1:
            raise Rejection(f"set.{name}: {name} is an integer; {value} is not")
        return ratio_text(number)
    if kind is ir.SortKind.BOOL:
        if isinstance(value, bool):
            return value
        if value in ("true", "false"):
            return value == "true"
        raise Rejection(f"set.{name}: {name} is true or false; {json_text(value)} is not")
    if kind is ir.SortKind.SET:
        if not isinstance(value, list):
            raise Rejection(f"set.{name}: {name} is a set: give a list of symbols, not {json_text(value)}")
        bad = [v for v in value if not isinstance(v, str) or not _SYMBOL.fullmatch(v)]
        if bad:
            raise Rejection(f"set.{name}: {json_text(bad[0])} is not a symbol")
        return sorted(set(value))
    # a symbol is written into the problem's (:init ...) as it is: one name, nothing else
    if not isinstance(value, str) or not _SYMBOL.fullmatch(value):
        raise Rejection(f"set.{name}: {name} holds a symbol of {r.sort.name}; {json_text(value)} is not one")
    return value


def _in_unit(name: str, text: str, with_unit: tuple[Fraction, str], r: ir.Resource) -> Fraction:
    """``"2 GB"`` for a resource in MB: 2000, converted exactly as catc converts a ``.cat`` literal."""
    number, unit = with_unit
    if r.unit is None:
        raise Rejection(f"set.{name}: {name} has no unit; give a plain number, not '{text}'")
    try:
        return convert(number, unit, r.unit)
    except ValueError as exc:
        raise Rejection(f"set.{name}: '{text}': {exc}") from None


_SYMBOL = re.compile(r"[A-Za-z_][A-Za-z0-9_-]*")  # a name of the language (catgrammar.tokens)


def json_text(value: Any) -> str:
    import json

    return json.dumps(value)


# ---------------------------------------------------------------- applying


def apply_change(
    state: ModelState, inst: ir.Instance, sources: Mapping[str, str], event: Event
) -> tuple[ModelState, dict[str, str]]:
    """The model state after a change event, and the origins of its generated text
    (``init.budget`` → ``set.budget``, ...); Rejection when a field cannot apply."""
    body, origins = event.body, {}
    if "set" in body:
        values: dict[str, StoredValue] = {}
        for name, value in body["set"].items():
            r = inst.resources.get(name)
            if r is None:
                raise Rejection(f"set.{name}: no resource named '{name}'{did_you_mean(name, inst.resources)}")
            values[name] = _stored(name, value, r)
            origins[f"init.{name}"] = f"set.{name}"
        state = state.with_init(values)
    if "goal" in body:
        _one_expression(body["goal"], "goal")
        state, origins["goal"] = state.with_problem(goal=body["goal"]), "goal"
    if "metric" in body:
        if body["metric"] is not None:
            _balanced(body["metric"], "metric")
        state, origins["metric"] = state.with_problem(metric=body["metric"]), "metric"
    if "softs" in body:
        for i, soft in enumerate(body["softs"]):
            _balanced(soft, f"softs[{i}]")
            origins[f"softs.{i}"] = f"softs[{i}]"
        state = state.with_problem(softs=tuple(body["softs"]))
    if "horizon" in body:
        state, origins["horizon"] = state.with_problem(horizon=body["horizon"]), "horizon"
    state = _apply_catalog(state, inst, sources, body, origins)
    return state, origins


def _apply_catalog(
    state: ModelState, inst: ir.Instance, sources: Mapping[str, str], body: Mapping[str, Any], origins: dict[str, str]
) -> ModelState:
    catalog, health = body.get("catalog") or {}, body.get("health") or {}
    if not catalog and not health:
        return state
    known = set(morphisms_in_sources(sources)) | state.catalog_names
    known -= set(state.removed)
    for name in catalog.get("remove", []):
        if name not in known:
            raise Rejection(f"catalog.remove: no morphism named '{name}'{did_you_mean(name, sorted(known))}")
    for key in ("failed", "recovered"):
        for name in health.get(key, []):
            if name not in known:
                raise Rejection(f"health.{key}: no morphism named '{name}'{did_you_mean(name, sorted(known))}")
    for name in health.get("recovered", []):
        if name not in state.failed:
            raise Rejection(f"health.recovered: '{name}' is not failed")
    added = _morphisms(catalog["add"]) if "add" in catalog else []
    for name, _, _ in added:  # replacing is explicit: remove it in the same event
        if name in known and name not in catalog.get("remove", []):
            raise Rejection(
                f"catalog.add: '{name}' is already in the catalogue; to replace it, remove it in the same event "
                f'({{"catalog": {{"remove": ["{name}"], "add": ...}}}})'
            )
    for name, _, start in added:  # catalog.add@LINES:COLUMNS: how far into the field its text starts
        before = catalog["add"][:start]
        origins[f"catalog.{name}"] = f"catalog.add@{before.count(chr(10))}:{len(before) - before.rfind(chr(10)) - 1}"
    return state.with_catalog(
        add=[(name, text) for name, text, _ in added],
        remove=catalog.get("remove", []),
        failed=health.get("failed", []),
        recovered=health.get("recovered", []),
        sources=sources,
    )


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
    state: ModelState, sources: Mapping[str, str], folder: str, origins: Mapping[str, str] | None = None
) -> Candidate:
    """Check a model state as catc would check its files; Rejection (the errors mapped to
    the event fields behind them) when it does not check."""
    files, regions = texts(state, sources, folder, origins)
    problem = next(p for p in files if p.endswith("/problem.cat"))
    try:
        model = loads(files, problem)
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
