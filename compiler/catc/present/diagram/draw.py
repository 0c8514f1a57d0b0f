"""Drawing the laid-out diagram: the document frame, group bands, step headers, wires with
their state tags, the boxes with their parts, stems, labels and ports, and the legend."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Mapping

from catc import ir
from catc.present.diagram.layout import _Box, _Columns, _Group, _label_height, _Rows, _Step, _Tags, _Wire
from catc.present.diagram.legend import _legend_item
from catc.present.diagram.style import (
    BAND,
    FONT_FAMILY,
    FS_NAME,
    FS_SMALL,
    FS_THETA,
    FS_TITLE,
    FS_WIRE,
    INK,
    KIND_STYLE,
    LABEL_PAD_Y,
    LINE_NAME,
    LINE_THETA,
    MARGIN,
    MUTED,
    PORT_R,
    STEM_GAP,
    STEM_W,
    WIRE,
    _num,
    format_value,
    text_width,
)
from catc.present.diagram.writer import _Svg


def _frame(
    svg: _Svg,
    instance: ir.Instance,
    steps: list[_Step],
    wires: list[_Wire],
    cols: _Columns,
    rows: _Rows,
    title: str | None,
) -> None:
    """The document's attributes (viewBox, size, font), its title and description, the background."""
    right = max(
        cols.right,
        MARGIN + max(sum(w + 18 for _, w in row) - 18 for row in rows.legend_rows),
        MARGIN + max([text_width(t, FS_SMALL) for t in rows.foot_lines] + [0.0]),
        MARGIN + (text_width(title, FS_TITLE) if title else 0.0),
    )
    vb_x, vb_y = 0.0, rows.top - MARGIN
    vb_w, vb_h = right + MARGIN, rows.bottom + MARGIN - vb_y
    root = svg.root
    root.set("xmlns", "http://www.w3.org/2000/svg")
    root.set("viewBox", " ".join(_num(v) for v in (vb_x, vb_y, vb_w, vb_h)))
    root.set("width", _num(vb_w))
    root.set("height", _num(vb_h))
    root.set("font-family", FONT_FAMILY)
    root.set("role", "img")
    root.set("class", "catc-diagram")
    name = instance.problem.name
    svg.el(root, "title", None, title or f"composition for {name}")
    svg.el(
        root,
        "desc",
        None,
        f"String diagram of a {len(steps)}-step composition over {len(wires)} resource wires "
        f"(domain {instance.domain.name}, problem {name}).",
    )
    svg.el(
        root, "rect", {"class": "background", "x": vb_x, "y": vb_y, "width": vb_w, "height": vb_h, "fill": "#FFFFFF"}
    )
    if title and rows.title_y is not None:
        svg.text(root, MARGIN, rows.title_y, title, size=FS_TITLE, weight="bold", cls="title")


def _draw_groups(svg: _Svg, root: ET.Element, groups: list[_Group], diagram_right: float) -> None:
    """Every other group on a light band; every group's name above its first wire."""
    bands = svg.el(root, "g", {"class": "groups"})
    for k, g in enumerate(groups):
        if k % 2 == 0:
            svg.el(
                bands,
                "rect",
                {
                    "class": "group-band",
                    "x": MARGIN - 6,
                    "y": g.top,
                    "width": diagram_right - MARGIN + 12,
                    "height": g.bottom - g.top,
                    "fill": BAND,
                    "rx": 4,
                },
            )
        svg.text(bands, MARGIN, g.top + 12, g.name, size=FS_SMALL, fill=MUTED, style="italic", cls="group-name")


def _draw_headers(svg: _Svg, root: ET.Element, steps: list[_Step], header_y: float) -> None:
    cols = svg.el(root, "g", {"class": "steps"})
    for st in steps:
        cx = st.x + st.w / 2
        svg.text(
            cols,
            cx,
            header_y,
            st.header,
            size=FS_SMALL + 1,
            anchor="middle",
            fill=INK,
            weight="bold",
            cls="step-header",
        )


def _draw_wires(svg: _Svg, root: ET.Element, wires: list[_Wire], cols: _Columns, tags: _Tags) -> None:
    """The wires with their labels and initial/final values (drawn first: boxes cover them)."""
    wire_g = svg.el(root, "g", {"class": "wires"})
    for w in wires:
        g = svg.el(wire_g, "g", {"class": "wire", "data-resource": w.name})
        svg.el(
            g,
            "line",
            {"x1": cols.wire_start, "y1": w.y, "x2": cols.wire_end, "y2": w.y, "stroke": WIRE, "stroke-width": 1.4},
        )
        svg.text(g, cols.label_end, w.y + 4, w.label, size=FS_WIRE, anchor="end", cls="wire-label")
        svg.text(g, cols.right_label, w.y + 3.5, w.name, size=FS_SMALL, fill=MUTED, cls="wire-label-right")
        if w.name in tags.initial:
            _tag(svg, g, cols.wire_start + 4, w.y, *tags.initial[w.name], "state initial")
        if w.name in tags.final:
            _tag(svg, g, cols.final, w.y, *tags.final[w.name], "state final")


def _draw_between(
    svg: _Svg,
    root: ET.Element,
    steps: list[_Step],
    wire_at: dict[str, _Wire],
    between: list[dict[str, tuple[str, str]]],
) -> None:
    """The values after each step (only those that change), the full value as a tooltip when cut."""
    if not between:
        return
    bg = svg.el(root, "g", {"class": "between"})
    for i, changed in enumerate(between):
        xs = steps[i].x + steps[i].w + 5
        for wname, (short, full) in changed.items():
            holder = bg
            if short != full:
                holder = svg.el(bg, "g")
                svg.el(holder, "title", None, full)
            t = svg.text(
                holder, xs, wire_at[wname].y - 4, short, size=FS_SMALL - 1, fill="#5A3E85", cls="state between"
            )
            t.set("data-resource", wname)


def _draw_legend(svg: _Svg, root: ET.Element, rows: _Rows) -> None:
    leg = svg.el(root, "g", {"class": "legend"})
    ly = rows.legend_top
    for row in rows.legend_rows:
        lx = MARGIN
        for item, w in row:
            _legend_item(svg, leg, item, lx, ly)
            lx += w + 18
        ly += 20
    for line in rows.foot_lines:
        svg.text(leg, MARGIN, ly + 4, line, size=FS_SMALL, fill=MUTED, cls="footnote")
        ly += 14


def _tag(svg: _Svg, parent: ET.Element, x: float, y: float, text: str, full: str, cls: str) -> None:
    """A state value sitting on a wire: a small white label with a thin border."""
    w = text_width(text, FS_SMALL) + 8
    g = svg.el(parent, "g", {"class": cls})
    if full != text:
        svg.el(g, "title", None, full)
    svg.el(
        g,
        "rect",
        {
            "x": x,
            "y": y - 7.5,
            "width": w,
            "height": 15,
            "rx": 3,
            "fill": "#FFFFFF",
            "stroke": "#8E7CC3",
            "stroke-width": 0.9,
        },
    )
    svg.text(g, x + 4, y + 3.5, text, size=FS_SMALL, fill="#3F2A6B")


def _draw_box(svg: _Svg, parent: ET.Element, b: _Box, wires: list[_Wire], wire_at: dict[str, _Wire]) -> None:
    """One activation: its tooltip, the stems between its parts, the parts, its label and its ports."""
    style = KIND_STYLE.get(b.kind, KIND_STYLE["unknown"])
    g = svg.el(parent, "g", {"class": f"activation {b.kind}", "data-step": b.step + 1, "data-morphism": b.act.morphism})
    svg.el(g, "title", None, _box_tooltip(b, style))
    _draw_stems(svg, g, b, wires, style)
    _draw_parts(svg, g, b, wires, style)
    _draw_label(svg, g, b, style)
    _draw_ports(svg, g, b, wire_at)


def _box_tooltip(b: _Box, style: Mapping[str, str]) -> str:
    tip = [f"{b.act.morphism} ({style['label']}), step t={b.step + 1}"]
    if b.act.params:
        tip.append("θ: " + ", ".join(f"{k}={format_value(v)}" for k, v in b.act.params.items()))
    if b.morphism is not None:
        tip.append("reads: " + (", ".join(b.reads) or "—"))
        tip.append("writes: " + (", ".join(b.writes) or "—"))
    return "\n".join(tip).replace("\n", "; ")


def _draw_stems(svg: _Svg, g: ET.Element, b: _Box, wires: list[_Wire], style: Mapping[str, str]) -> None:
    """The stems joining the parts of a broken box, interrupted where a wire crosses in front."""
    cx = b.x + b.w / 2
    for (_, upper), (lower, _) in zip(b.pieces, b.pieces[1:]):
        y0 = upper
        for w in wires:
            if upper < w.y < lower:
                _stem(svg, g, cx, y0, w.y - STEM_GAP, style)
                y0 = w.y + STEM_GAP
        _stem(svg, g, cx, y0, lower, style)


def _draw_parts(svg: _Svg, g: ET.Element, b: _Box, wires: list[_Wire], style: Mapping[str, str]) -> None:
    """The box's parts, and over each the wires it merely passes over, light and dashed."""
    touched = set(b.touched)
    for top, bottom in b.pieces:
        svg.el(
            g,
            "rect",
            {
                "class": "morphism",
                "x": b.x,
                "y": top,
                "width": b.w,
                "height": bottom - top,
                "rx": 6,
                "fill": style["fill"],
                "stroke": style["stroke"],
                "stroke-width": 1.6,
                "stroke-dasharray": "4 3" if b.kind == "unknown" else None,
            },
        )
        for w in wires:
            if top < w.y < bottom and w.name not in touched:
                svg.el(
                    g,
                    "line",
                    {
                        "class": "passover",
                        "data-resource": w.name,
                        "x1": b.x + 1,
                        "y1": w.y,
                        "x2": b.x + b.w - 1,
                        "y2": w.y,
                        "stroke": "#7A7A7A",
                        "stroke-width": 1,
                        "stroke-dasharray": "3 3",
                        "stroke-opacity": 0.8,
                    },
                )


def _draw_label(svg: _Svg, g: ET.Element, b: _Box, style: Mapping[str, str]) -> None:
    """The label, centred in its part, on a patch of the box colour so dashed wires do not cross the text."""
    cx = b.x + b.w / 2
    top, bottom = b.pieces[b.label_piece]
    lh = _label_height(b.lines)
    ly = (top + bottom) / 2 - lh / 2
    lw = max(text_width(b.lines[0], FS_NAME), *([text_width(t, FS_THETA) for t in b.lines[1:]] + [0.0])) + 8
    svg.el(
        g,
        "rect",
        {"class": "label-patch", "x": cx - lw / 2, "y": ly + 1, "width": lw, "height": lh - 2, "fill": style["fill"]},
    )
    ty = ly + LABEL_PAD_Y + 11
    svg.text(g, cx, ty, b.lines[0], size=FS_NAME, anchor="middle", weight="bold", cls="morphism-name")
    ty += LINE_NAME - 2
    for line in b.lines[1:]:
        svg.text(g, cx, ty + 1, line, size=FS_THETA, anchor="middle", fill="#333333", cls="theta")
        ty += LINE_THETA


def _draw_ports(svg: _Svg, g: ET.Element, b: _Box, wire_at: dict[str, _Wire]) -> None:
    """The ports: hollow = read (left edge), filled = write (right edge)."""
    for cls, x, fill, names in (("port read", b.x, "#FFFFFF", b.reads), ("port write", b.x + b.w, INK, b.writes)):
        for r in names:
            svg.el(
                g,
                "circle",
                {
                    "class": cls,
                    "data-resource": r,
                    "cx": x,
                    "cy": wire_at[r].y,
                    "r": PORT_R,
                    "fill": fill,
                    "stroke": INK,
                    "stroke-width": 1.4,
                },
            )


def _stem(svg: _Svg, parent: ET.Element, cx: float, y0: float, y1: float, style: Mapping[str, str]) -> None:
    if y1 - y0 < 1:
        return
    svg.el(
        parent,
        "rect",
        {
            "class": "stem",
            "x": cx - STEM_W / 2,
            "y": y0 - 1,
            "width": STEM_W,
            "height": y1 - y0 + 2,
            "fill": style["fill"],
            "stroke": style["stroke"],
            "stroke-width": 1.2,
        },
    )
