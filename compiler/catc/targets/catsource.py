"""Write a checked instance (:mod:`catc.ir`) back as ``.cat`` source: a domain and a problem.

The inverse of the front end, for models that were not written as ``.cat`` text (a PDDL or
unified-planning import, a generated model): ``catc check`` reads the text back as the same
IR, spans aside (``tests/test_catsource.py`` checks this over every example). The domain is
written *self-contained*: what it imported is written into it, and ``:import`` is left out.
Requirements are written as the checker expanded them.

The text has one section per line and no other layout: the interfaces pass it through the
formatter (``catc fmt``'s :func:`~catc.frontend.formatter.format_text`), which this stage may
not import, so the files written are the ones ``catc fmt --check`` leaves unchanged.

What the language cannot spell (a name that is not a ``.cat`` name, a string with a line
break) raises :class:`CatSourceError` with the reason; nothing is dropped.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from fractions import Fraction

from catc import ir
from catc.ir.grounding import (
    BehaviorGrounding,
    Deployment,
    Grounding,
    HardwareGrounding,
    Profile,
    SoftwareGrounding,
    Template,
    Value,
    ValueKind,
)
from catc.ir.numbers import number_text
from catc.ir.text import to_text

__all__ = ["CatSourceError", "domain_text", "instance_texts", "problem_text"]

_NAME = re.compile(r"[a-zA-Z_][a-zA-Z0-9_-]*\Z")


class CatSourceError(ValueError):
    """The instance holds something ``.cat`` text cannot spell (the message says what)."""


def _name(n: str, what: str) -> str:
    if not _NAME.match(n):
        raise CatSourceError(f"{what} '{n}' is not a .cat name ([a-zA-Z_][a-zA-Z0-9_-]*)")
    return n


def _string(s: str) -> str:
    if "\n" in s or "\r" in s:
        raise CatSourceError(f"the string {s!r} has a line break, which a .cat string cannot hold")
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _word(s: str) -> str:
    """A name where it is one, else a string (``:unit``, ``:project``)."""
    return s if _NAME.match(s) else _string(s)


def _num(v: Fraction) -> str:
    return number_text(v)


def _bound(v: Fraction | None) -> str:
    return "*" if v is None else _num(v)


def _bounds(lo: Fraction | None, hi: Fraction | None) -> str:
    return "" if lo is None and hi is None else f" :bounds ({_bound(lo)} {_bound(hi)})"


def _conj(exprs: list[str]) -> str:
    return exprs[0] if len(exprs) == 1 else "(and" + "".join(" " + e for e in exprs) + ")"


def _typed(items: Iterable[tuple[str, str]]) -> str:
    """``a b - s  c - t`` from (name, sort) pairs, grouping runs of one sort."""
    out: list[str] = []
    run: list[str] = []
    last: str | None = None
    for name, sort in items:
        if sort != last and run:
            out.append(" ".join(run) + f" - {last}")
            run = []
        run.append(name)
        last = sort
    if run:
        out.append(" ".join(run) + f" - {last}")
    return " ".join(out)


# ---------------------------------------------------------------- the domain


def _sort(s: ir.Sort) -> str:
    if s.kind is ir.SortKind.ENUM:
        return _name(s.name, "sort") + " - (enum " + " ".join(_name(v, "value") for v in s.values) + ")"
    return f"{_name(s.name, 'sort')} - {s.parent or 'symbol'}"


def _resource(r: ir.Resource) -> str:
    text = f"({_name(r.name, 'resource')} {r.sort}"
    if r.group is not None:
        text += f" :group {_name(r.group, 'group')}"
    if r.unit is not None:
        text += f" :unit {_word(r.unit)}"
    text += _bounds(r.lower, r.upper)
    if r.doc is not None:
        text += f" :doc {_string(r.doc)}"
    return text + ")"


def _param(p: ir.Param) -> str:
    unit = "" if p.unit is None else f" :unit {_word(p.unit)}"
    return f"({_name(p.name, 'parameter')} {p.sort}{unit}{_bounds(p.lower, p.upper)}{' :fixed' if p.fixed else ''})"


def _effect(e: ir.Effect) -> str:
    return f"({e.kind.value} {e.resource} {to_text(e.value)})"


def _template(t: Template) -> str:
    parts = []
    for p in t.parts:
        if isinstance(p, Value):
            parts.append("{" + (p.name or "") + "}")
        else:
            parts.append(p.replace("{", "{{").replace("}", "}}"))
    return _string("".join(parts))


def _value(v: Value) -> str:
    if v.kind is ValueKind.KEY:
        return f"(key {v.name})"
    if v.kind is ValueKind.LITERAL:
        lit = v.literal
        if isinstance(lit, bool):
            return "true" if lit else "false"
        if isinstance(lit, str):
            return _string(lit)
        assert isinstance(lit, Fraction)
        return _num(lit)
    return v.name or ""


def _bindings(key: str, pairs: tuple[tuple[str, Value], ...]) -> str:
    if not pairs:
        return ""
    return f" {key} (" + " ".join(f"({_word(n)} {_value(v)})" for n, v in pairs) + ")"


def _ground(g: Grounding) -> str:
    if isinstance(g, HardwareGrounding):
        text = f"(hardware :instruction {_template(g.instruction)}"
        if g.check is not None:
            text += f" :check {_template(g.check)}"
        if g.parts:
            text += " :parts (" + " ".join(_string(p) for p in g.parts) + ")"
        return text + ")"
    if isinstance(g, SoftwareGrounding):
        text = f"(software :image {_string(g.image)} :node {_word(g.node)}"
        if g.profile is not Profile.DRIVERS:
            text += f" :profile {g.profile.value}"
        return text + _bindings(":params", g.params) + _bindings(":remap", g.remap) + ")"
    assert isinstance(g, BehaviorGrounding)
    text = f"(behavior :id {_word(g.node_id)}"
    text += _bindings(":inputs", g.inputs) + _bindings(":outputs", g.outputs)
    if g.image is not None:
        text += f" :image {_string(g.image)}"
    if g.profile is not Profile.SKILLSETS:
        text += f" :profile {g.profile.value}"
    return text + ")"


def _morphism(m: ir.Morphism) -> str:
    lines = [f"(:morphism {_name(m.name, 'morphism')}", f":kind {m.kind.value}"]
    if m.churn != 1:
        lines.append(f":churn {_num(m.churn)}")
    if m.uses is not None:
        lines.append(f":uses {m.uses}")
    if m.cost is not None:
        lines.append(f":cost {to_text(m.cost)}")
    if m.doc is not None:
        lines.append(f":doc {_string(m.doc)}")
    if m.params:
        lines.append(":parameters (" + " ".join(_param(p) for p in m.params) + ")")
    if m.pre:
        lines.append(":precondition " + _conj([to_text(lit.expr) for lit in m.pre]))
    if m.effects:
        lines.append(":effect " + _conj([_effect(e) for e in m.effects]))
    if m.grounding is not None:
        lines.append(":ground " + _ground(m.grounding))
    return "\n".join(lines) + ")"


def _view(v: ir.View, resources: frozenset[str]) -> str:
    """A view over the domain's ``resources``: names it lists that the domain no longer has
    (an instance's projection left them out: docs/stdlib.md) mean nothing and are not written."""
    kept, dropped = v.kept & resources, v.dropped & resources
    if dropped and len(kept) > len(dropped):
        return f"(:view {v.name} :drop ({' '.join(sorted(dropped))}))"
    return f"(:view {v.name} :keep ({' '.join(sorted(kept))}))"


def _hole(h: ir.Hole) -> str:
    text = f"(:hole {_name(h.name, 'hole')}"
    if h.view is not None:
        text += f" :view {h.view}"
    if h.max_effects is not None:
        text += f" :max-effects {h.max_effects}"
    if h.max_preconditions is not None:
        text += f" :max-preconditions {h.max_preconditions}"
    return text + ")"


def _deployment(d: Deployment) -> str:
    text = f"(:deployment :project {_word(d.project)}"
    if d.executor is not None:
        text += f" :executor {_string(d.executor)}"
    return text + ")"


def domain_text(domain: ir.Domain, *, header: str | None = None) -> str:
    """The domain as ``.cat`` text (unformatted: one section per line); ``header`` becomes a
    comment above it."""
    out = [f"(define (domain {_name(domain.name, 'domain')})"]
    if domain.requirements:
        out.append("(:requirements " + " ".join(_flags(domain.requirements)) + ")")
    declared = [s for s in domain.sorts.values() if s.kind in (ir.SortKind.SYMBOL, ir.SortKind.ENUM)]
    if declared:
        out.append("(:sorts " + " ".join(_sort(s) for s in _parents_first(declared)) + ")")
    constants = [c for c in domain.constants.values() if c.sort.kind is not ir.SortKind.ENUM]  # enum values: above
    if constants:
        out.append("(:constants " + _typed((_name(c.name, "constant"), c.sort.name) for c in constants) + ")")
    if domain.resources:
        out.append("(:resources\n" + "\n".join(_resource(r) for r in domain.resources.values()) + ")")
    out.extend(_morphism(m) for m in domain.morphisms.values())
    out.extend(_view(v, frozenset(domain.resources)) for v in domain.views.values())
    out.extend(_hole(h) for h in domain.holes.values())
    if domain.deployment is not None:
        out.append(_deployment(domain.deployment))
    return _comment(header) + "\n".join(out) + ")\n"


def _flags(names: Iterable[str]) -> list[str]:
    """Requirement flags as written (``:numeric``; an IR built in code may leave out the colon)."""
    return sorted({n if n.startswith(":") else ":" + n for n in names})


def _parents_first(sorts: list[ir.Sort]) -> list[ir.Sort]:
    names = {s.name for s in sorts}
    done: set[str] = set()
    out: list[ir.Sort] = []
    pending = list(sorts)
    while pending:
        rest = []
        for s in pending:
            if s.parent is None or s.parent not in names or s.parent in done:
                out.append(s)
                done.add(s.name)
            else:
                rest.append(s)
        if len(rest) == len(pending):  # a cycle cannot pass the checker; keep the order
            out.extend(rest)
            break
        pending = rest
    return out


def _comment(header: str | None) -> str:
    if not header:
        return ""
    return "".join(f"; {line}".rstrip() + "\n" for line in header.splitlines()) + "\n"


# ---------------------------------------------------------------- the problem


def _init(v: ir.InitValue, sort: ir.Sort) -> str:
    if sort.kind is ir.SortKind.BOOL and isinstance(v.value, ir.Const) and isinstance(v.value.value, bool):
        return v.resource if v.value.value else f"(not {v.resource})"
    return f"(= {v.resource} {to_text(v.value)})"


def _objective(o: ir.Objective) -> str:
    return f"({o.sense.value} {to_text(o.term)})"


def _metric(m: ir.Metric) -> str:
    if m.mode is ir.MetricMode.SINGLE:
        (o,) = m.objectives
        return f"(:metric {o.sense.value} {to_text(o.term)})"
    return f"(:metric {m.mode.value} " + " ".join(_objective(o) for o in m.objectives) + ")"


def problem_text(inst: ir.Instance, *, header: str | None = None) -> str:
    """The problem of ``inst`` as ``.cat`` text (unformatted); it names ``inst.domain``."""
    p, d = inst.problem, inst.domain
    out = [f"(define (problem {_name(p.name, 'problem')})", f"(:domain {_name(d.name, 'domain')})"]
    own = set(_flags(p.requirements)) - set(_flags(d.requirements))
    if own:
        out.append("(:requirements " + " ".join(_flags(own)) + ")")
    if p.objects:
        out.append("(:objects " + _typed((_name(c.name, "object"), c.sort.name) for c in p.objects.values()) + ")")
    if p.init:
        out.append("(:init " + " ".join(_init(v, d.resources[v.resource].sort) for v in p.init.values()) + ")")
    goal = [to_text(lit.expr) for lit in p.goal]
    out.append(f"(:goal {_conj(goal) if goal else '(and)'})")
    if p.horizon is not None:
        out.append(f"(:horizon {p.horizon})")
    for s in p.softs:
        weight = "" if s.weight == 1 else f" :weight {_num(s.weight)}"
        out.append(f"(:soft {to_text(s.expr)}{weight})")
    if p.metric is not None:
        out.append(_metric(p.metric))
    if p.deployed:
        out.append("(:deployed " + " ".join(p.deployed) + ")")
    if p.view is not None:
        out.append(f"(:view {p.view})")
    return _comment(header) + "\n".join(out) + ")\n"


def instance_texts(
    inst: ir.Instance, *, domain_header: str | None = None, problem_header: str | None = None
) -> tuple[str, str]:
    """``(domain text, problem text)`` of a checked, unprojected instance (unformatted)."""
    if inst.view is not None:
        raise CatSourceError(f"the instance is projected by view '{inst.view}': write the unprojected one")
    return domain_text(inst.domain, header=domain_header), problem_text(inst, header=problem_header)
