"""A composition drawn as a string diagram, in SVG.

The picture follows the string diagrams of free symmetric monoidal categories:

* every **wire** is a resource (an atom of the category's objects), running left → right;
  only the resources the composition's morphisms read or write are drawn (an empty plan
  draws them all: it is the identity on the whole state), grouped by ``Resource.group``;
* every **activation** is a box labelled with its morphism and its parameter values θ,
  coloured by kind (hardware / software / behavior); it spans from the top-most to the
  bottom-most wire it touches, and a wire it merely passes over is drawn *over* the box,
  dashed and light, so that touched and untouched wires never look alike;
* **ports** sit where a touched wire meets the box: a hollow circle on the left edge when the
  morphism reads the wire (a precondition, or a value its effects use), a filled circle on
  the right edge when it writes it (an effect);
* where at least three untouched wires separate the wires a box touches, the box is broken
  into parts joined by a narrow stem, interrupted where those wires cross in front of it;
* serial composition (∘) runs left to right, one column per step; the activations of one
  step run in parallel (⊗) and stand side by side in sub-columns of that step's column;
* with ``states`` (s₀..sₙ) the initial values are tagged on the wires at the left, the
  final ones at the right, and a value that a step changes is written just after it.

The SVG is built as an :mod:`xml.etree.ElementTree` tree (so all text is escaped), has a
``viewBox``, references nothing external (no fonts, scripts or images) and is deterministic:
the same instance, plan and states give a byte-identical document.  Text is set in a
monospace family so widths can be estimated from character counts.

Semantic class attributes make the picture machine-checkable: ``wire``, ``activation``,
``morphism`` (a box's rectangle, one per part), ``stem``, ``passover``, ``port read``,
``port write``, ``state initial``/``state final``/``state between``, ``step-header``,
``footnote``.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence
from typing import Any

from catc import ir
from catc.present.diagram.draw import (
    _draw_between,
    _draw_box,
    _draw_groups,
    _draw_headers,
    _draw_legend,
    _draw_wires,
    _frame,
)
from catc.present.diagram.layout import _place_boxes, _place_columns, _place_rows, _place_wires, _state_tags, _wires
from catc.present.diagram.style import GROUP_ORDER, KIND_STYLE, format_value
from catc.present.diagram.writer import _Svg
from catc.semantics.plan import Plan

__all__ = ["GROUP_ORDER", "KIND_STYLE", "format_value", "render_svg"]


def render_svg(
    instance: ir.Instance, plan: Plan, *, states: Sequence[Mapping[str, Any]] | None = None, title: str | None = None
) -> str:
    """Draw ``plan`` over ``instance`` as a string diagram; return the SVG document.

    ``states``, when given, is the list s₀..sₙ of states (resource → value), one more
    than the plan has steps; it annotates the wires with their initial and final values
    and with every value a step changes."""
    if states is not None and len(states) != len(plan.steps) + 1:
        raise ValueError(
            f"states must be s_0..s_n: {len(plan.steps) + 1} states for {len(plan.steps)} steps, got {len(states)}"
        )
    wires, omitted = _wires(instance, plan)
    wire_at = {w.name: w for w in wires}
    groups = _place_wires(wires)
    wires_top = groups[0].top if groups else 0.0
    wires_bottom = groups[-1].bottom if groups else 0.0
    steps = _place_boxes(instance, plan, wires, (wires_top + wires_bottom) / 2)
    tags = _state_tags(wires, len(steps), states)
    cols = _place_columns(wires, groups, steps, tags)
    rows = _place_rows(steps, wires_top, wires_bottom, title, cols.right, bool(states), omitted)

    svg = _Svg()
    root = svg.root
    _frame(svg, instance, steps, wires, cols, rows, title)
    _draw_groups(svg, root, groups, cols.right)
    _draw_headers(svg, root, steps, rows.header_y)
    _draw_wires(svg, root, wires, cols, tags)
    _draw_between(svg, root, steps, wire_at, tags.between)
    box_g = svg.el(root, "g", {"class": "activations"})
    for st in steps:
        for b in st.boxes:
            _draw_box(svg, box_g, b, wires, wire_at)
    _draw_legend(svg, root, rows)
    ET.indent(root, space=" ")
    return ET.tostring(root, encoding="unicode") + "\n"
