"""Hover text and the names in scope of an analysed document (no pygls)."""

from __future__ import annotations

from typing import Any

from catc.interfaces.lsp.analysis import Analysis, Definition, lookup, same_name
from catgrammar.span import Span


def _grounding_text(g: object) -> str:
    """One line: what the morphism becomes on the robot (its ``:ground`` block)."""
    from catc.ir import grounding as gr

    if isinstance(g, gr.HardwareGrounding):
        text = "".join(p if isinstance(p, str) else "{" + str(p.name) + "}" for p in g.instruction.parts)
        return f"grounded as a hardware step: “{text}”"
    if isinstance(g, gr.SoftwareGrounding):
        return f"grounded as ROS 2 node `{g.node}` in image `{g.image}` ({g.profile.value})"
    if isinstance(g, gr.BehaviorGrounding):
        skill = f", skill image `{g.image}`" if g.image else ""
        return f"grounded as behaviour-tree node `{g.node_id}`{skill}"
    return "no grounding: `catc ground` writes nothing for it (W0106)"


def _unit_text(text: str) -> str:
    """``GB (information)``: the unit with its dimension (docs/language.md §Units)."""
    from catc.frontend import units

    try:
        return f"{text} ({units.parse(text).dimension})"
    except units.UnitError:
        return text


def _declaration(a: Analysis, d: Definition, max_lines: int = 8) -> str | None:
    """The declaration of ``d`` as written (its first line and an ellipsis when long)."""
    text = a.text if same_name(d.whole.file, a.path) else a.sources.get(d.whole.file)
    if text is None:
        text = next((t for p, t in a.sources.items() if same_name(p, d.whole.file)), None)
    if text is None:
        return None
    code = text[d.whole.start : d.whole.end]
    lines = code.split("\n")
    if len(lines) > max_lines or d.kind in ("domain", "problem", "morphism"):
        return lines[0].rstrip() + (" …" if len(lines) > 1 else "")
    indent = min((len(x) - len(x.lstrip()) for x in lines[1:] if x.strip()), default=0)
    return "\n".join([lines[0], *(x[indent:] for x in lines[1:])])


def _fenced(code: str) -> str:
    fence = "```"
    while fence in code:
        fence += "`"
    return f"{fence}cat\n{code}\n{fence}"


def hover_text(a: Analysis, name: str, at: Span | None = None) -> str | None:
    """The hover of ``name`` (written at ``at``) as Markdown: the declaration as written (a
    fenced ``cat`` block), what it is, then its details; paragraphs are separated by blank
    lines, so that every Markdown renderer keeps them apart.  Names of a domain that does
    not check (yet) still show their declaration; details of the last version that checked
    are marked as such."""
    if name.startswith(":"):
        from catc.interfaces.lsp.tools import OPTION_DOCS

        option = OPTION_DOCS.get(name)
        return f"{_fenced(option[0])}\n\n**option** `{name}`: {option[1]}" if option else None
    defs = lookup(a, name)
    d = defs[0] if defs else None
    if at is not None:
        from catc.interfaces.lsp.tools import target

        found = target(a, name, at)
        if found is not None:
            d = found[0]
    blocks: list[str] = []
    if d is not None:
        code = _declaration(a, d)
        if code:
            blocks.append(_fenced(code))
    details = _details(a, name, d)
    if details is None:
        if d is None:
            return None
        owner = f"{'morphism' if d.kind == 'parameter' else 'in'} `{d.owner}`" if d.owner else ""
        blocks.append(f"**{d.kind}** `{d.name}`" + (f" ({owner})" if owner else ""))
        if d.kind not in ("domain", "problem", "parameter"):
            blocks.append("*Only the declaration is shown: its definition does not check yet.*")
        return "\n\n".join(blocks)
    blocks += details
    return "\n\n".join(blocks)


def _bounds(lower: Any, upper: Any) -> str:
    from catc.ir.numbers import number_text

    lo = number_text(lower) if lower is not None else "*"
    hi = number_text(upper) if upper is not None else "*"
    return f"({lo} {hi})"


def _morphism_details(m: Any) -> list[str]:
    """A morphism's hover blocks: kind, doc, weights, θ parameters, preconditions, effects
    and grounding (each list after its own paragraph)."""
    from catc.ir.numbers import number_text
    from catc.ir.text import effect_text, to_text

    blocks = [f"**morphism** `{m.name}` ({m.kind.value})"]
    if m.doc:
        blocks.append(m.doc)
    extra = [f"churn {number_text(m.churn)}"]
    if m.uses == 0:
        extra.append("switched off (:uses 0)")
    elif m.uses is not None:
        extra.append(f"uses ≤ {m.uses}")
    if m.cost is not None:
        extra.append(f"cost {to_text(m.cost)}")
    blocks.append(", ".join(extra))
    if m.params:
        rows = []
        for p in m.params:
            b = f" in {_bounds(p.lower, p.upper)}" if p.lower is not None or p.upper is not None else ""
            u = f" [{p.unit}]" if p.unit else ""
            rows.append(f"- `{p.name}` : {_sort_text(p.sort)}{u}{b}{' (fixed)' if p.fixed else ''}")
        blocks += ["parameters:", "\n".join(rows)]
    if m.pre:
        blocks += [
            "preconditions:",
            "\n".join(f"- `{to_text(lit.expr)}`" for lit in m.pre),
        ]
    if m.effects:
        blocks += ["effects:", "\n".join(f"- `{effect_text(e)}`" for e in m.effects)]
    blocks.append(_grounding_text(m.grounding))
    return blocks


def _details(a: Analysis, name: str, d: Definition | None) -> list[str] | None:
    """The Markdown blocks that describe ``name`` from the checked model, or None."""
    bounds = _bounds

    def where(kind: str, owner: object) -> str:
        stale = " — *as it last checked*" if id(owner) in a.stale else ""
        return f"*{kind} `{owner.name}`*{stale}"  # type: ignore[attr-defined]

    if d is not None and d.kind == "parameter":
        for dom in a.domains:
            m = dom.morphisms.get(d.owner or "")
            p = next((p for p in m.params if p.name == name), None) if m is not None else None
            if m is not None and p is not None:
                b = f" in {bounds(p.lower, p.upper)}" if p.lower is not None or p.upper is not None else ""
                fixed = " (fixed: one value for the composition)" if p.fixed else ""
                u = f" [{_unit_text(p.unit)}]" if p.unit else ""
                return [
                    f"**parameter** `{name}` : {_sort_text(p.sort)}{u}{b}{fixed}",
                    where("morphism", m),
                ]
        return None
    for dom in a.domains:
        r = dom.resources.get(name)
        if r is not None:
            facts = []
            if r.unit:
                facts.append(f"unit: {_unit_text(r.unit)}")
            if r.group:
                facts.append(f"group: {r.group}")
            if r.lower is not None or r.upper is not None:
                facts.append(f"bounds: {bounds(r.lower, r.upper)}")
            blocks = [f"**resource** `{r.name}` : {_sort_text(r.sort)}"]
            if facts:
                blocks.append("\n".join(f"- {f}" for f in facts))
            if r.doc:
                blocks.append(r.doc)
            return [*blocks, where("domain", dom)]
    for dom in a.domains:
        m = dom.morphisms.get(name)
        if m is not None:
            return [*_morphism_details(m), where("domain", dom)]
    for dom in a.domains:
        s = dom.sorts.get(name)
        if s is not None:
            return [
                f"**sort** `{name}`: {_sort_text(s, expand=True)}",
                where("domain", dom),
            ]
        c = dom.constants.get(name)
        if c is not None:
            return [
                f"**constant** `{name}` : {_sort_text(c.sort)}",
                where("domain", dom),
            ]
        v = dom.views.get(name)
        if v is not None:
            return [
                f"**view** `{name}`: keeps {', '.join(sorted(v.kept)) or 'nothing'}",
                where("domain", dom),
            ]
        h = dom.holes.get(name)
        if h is not None:
            bits = [f"view {h.view}" if h.view else "no view"]
            if h.max_effects is not None:
                bits.append(f"at most {h.max_effects} effects")
            if h.max_preconditions is not None:
                bits.append(f"at most {h.max_preconditions} preconditions")
            return [f"**hole** `{name}`: {', '.join(bits)}", where("domain", dom)]
    for p in a.problems:
        o = p.objects.get(name)
        if o is not None:
            return [f"**object** `{name}` : {_sort_text(o.sort)}", where("problem", p)]
    return None


def _sort_text(sort, expand: bool = False) -> str:
    kind = getattr(sort.kind, "value", str(sort.kind))
    if getattr(sort, "element", None) is not None:
        return f"(set {sort.element.name})"
    if expand and sort.values:
        return f"(enum {' '.join(sort.values)})"
    if expand and sort.parent:
        return f"{kind} (a kind of {sort.parent})"
    if expand:
        return f"{kind} sort"
    return sort.name or kind
