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

import unicodedata
import xml.etree.ElementTree as ET
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir.numbers import ratio_text
from catc.semantics.plan import Activation, Plan

__all__ = ["GROUP_ORDER", "KIND_STYLE", "format_value", "render_svg"]

# ---------------------------------------------------------------- style

GROUP_ORDER = ("electromechanical", "compute", "info", "external")
OTHERS = "others"

FONT_FAMILY = "DejaVu Sans Mono, Menlo, Consolas, Liberation Mono, monospace"
CHAR_EM = 0.602  # advance of one monospace character, in em (DejaVu Sans Mono)

# Okabe–Ito colours (safe for the common colour-vision deficiencies): a light tint fills
# the box, the full colour (darkened where needed for contrast) draws its border.
KIND_STYLE: dict[str, dict[str, str]] = {
    "hardware": {"fill": "#FBE3B0", "stroke": "#C07F00", "label": "hardware"},
    "software": {"fill": "#CCE3F3", "stroke": "#0072B2", "label": "software"},
    "behavior": {"fill": "#C9EBDD", "stroke": "#009E73", "label": "behavior"},
    "unknown": {"fill": "#EEEEEE", "stroke": "#777777", "label": "not in the model"},
}

INK = "#222222"
WIRE = "#333333"
MUTED = "#666666"
BAND = "#F4F4F4"

FS_NAME = 12.0  # morphism name (bold)
FS_THETA = 11.0  # parameter values
FS_WIRE = 12.0  # wire labels
FS_SMALL = 10.0  # values, headings, legend
FS_TITLE = 15.0

MARGIN = 16.0
SPACING = 28.0  # between wires
GROUP_HEAD = 18.0  # room for a group's heading above its first wire
GROUP_GAP = 6.0
BOX_PAD_Y = 9.0  # box edge beyond its outermost touched wire
BOX_PAD_X = 10.0
BOX_MIN_W = 64.0
SUB_GAP = 16.0  # between parallel boxes of one step
STEP_GAP = 40.0  # between steps
LEAD = 30.0  # wire before the first and after the last step
PORT_R = 3.6
BREAK_RUN = 3  # break a box across this many consecutive untouched wires, or more
MIN_STEM = SPACING  # parts of a box closer than this merge
STEM_W = 8.0
STEM_GAP = 4.5  # half the break in a stem where a wire crosses it
LINE_NAME = 15.0
LINE_THETA = 13.0
LABEL_PAD_Y = 5.0
THETA_CHARS = 26  # wrap θ lines beyond this many characters (or the name's length)
VALUE_CHARS = 30  # truncate one θ value or state tag beyond this
BETWEEN_CHARS = 14  # truncate a between-steps value beyond this
MAX_FOOT_CHARS = 110


# ---------------------------------------------------------------- text helpers


def _char_w(ch: str) -> float:
    if unicodedata.combining(ch):
        return 0.0
    return 2.0 if unicodedata.east_asian_width(ch) in ("W", "F") else 1.0


def text_width(text: str, size: float) -> float:
    """Estimated advance of ``text`` set in the monospace family at ``size`` px."""
    return sum(_char_w(c) for c in text) * CHAR_EM * size


def _clean(text: str) -> str:
    """Text that XML 1.0 can carry: control characters become U+FFFD, newlines spaces."""
    out = []
    for ch in text:
        o = ord(ch)
        if ch in "\n\r\t":
            out.append(" ")
        elif o < 0x20 or 0xD800 <= o <= 0xDFFF or o in (0xFFFE, 0xFFFF):
            out.append("\ufffd")
        else:
            out.append(ch)
    return "".join(out)


def _clip(text: str, chars: int) -> str:
    return text if len(text) <= chars else text[: max(1, chars - 1)] + "…"


def _num(x: float) -> str:
    """A coordinate, rounded to 0.1 px and printed without a trailing '.0'."""
    r = round(x * 10) / 10
    if r == 0:
        r = 0.0  # no '-0'
    s = f"{r:.1f}"
    return s[:-2] if s.endswith(".0") else s


def format_value(v: Any) -> str:
    """A state or θ value as the diagram prints it.

    Numbers are exact: integers plainly (``16``), terminating decimals as decimals
    (``4.25``), any other rational as ``a/b``; booleans ``true``/``false``; sets sorted
    in braces (``∅`` when empty); symbols as they are."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, Fraction):
        return ratio_text(v)
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, (frozenset, set)):
        if not v:
            return "∅"
        return "{" + ", ".join(sorted(format_value(x) for x in v)) + "}"
    return str(v)


def _wrap_items(items: Sequence[str], limit: int) -> list[str]:
    """Greedy wrap of comma-separated items into lines of at most ``limit`` characters."""
    lines: list[str] = []
    current = ""
    for i, item in enumerate(items):
        piece = item + ("," if i < len(items) - 1 else "")
        if not current:
            current = piece
        elif len(current) + 1 + len(piece) <= limit:
            current = f"{current} {piece}"
        else:
            lines.append(current)
            current = piece
    if current:
        lines.append(current)
    return lines


# ---------------------------------------------------------------- layout model


@dataclass
class _Wire:
    name: str
    label: str
    group: str
    y: float = 0.0


@dataclass
class _Group:
    name: str
    top: float
    bottom: float


@dataclass
class _Box:
    step: int  # 0-based
    act: Activation
    kind: str
    morphism: ir.Morphism | None
    lines: list[str]  # name first, then wrapped θ
    reads: list[str]  # wire names, in wire order
    writes: list[str]
    touched: list[str]
    w: float
    x: float = 0.0
    pieces: list[list[float]] = field(default_factory=list)  # [top, bottom] of each part
    label_piece: int = 0

    @property
    def top(self) -> float:
        return self.pieces[0][0]

    @property
    def bottom(self) -> float:
        return self.pieces[-1][1]


@dataclass
class _Step:
    boxes: list[_Box] = field(default_factory=list)
    x: float = 0.0
    w: float = 0.0
    header: str = ""


def _group_key(group: str) -> tuple[int, int, str]:
    if group in GROUP_ORDER:
        return (0, GROUP_ORDER.index(group), "")
    if group == OTHERS:
        return (2, 0, "")
    return (1, 0, group)


def _wires(instance: ir.Instance, plan: Plan) -> tuple[list[_Wire], list[str]]:
    """The drawn wires in diagram order, and the names of the omitted resources."""
    touched: set[str] = set()
    for _, act in plan.activations:
        m = instance.morphisms.get(act.morphism)
        if m is not None:
            touched |= m.reads | m.writes
    declared = list(instance.resources)
    if touched:
        drawn = [r for r in declared if r in touched]
        drawn += sorted(touched - set(declared))  # only if the IR is inconsistent
    else:
        drawn = declared  # nothing is touched: draw the identity on the whole state
    omitted = [r for r in declared if r not in set(drawn)]

    wires: list[_Wire] = []
    for name in drawn:
        res = instance.resources.get(name)
        group = (res.group if res is not None else None) or OTHERS
        label = name if res is None or not res.unit else f"{name} [{res.unit}]"
        wires.append(_Wire(name, _clean(label), group))
    order = {w.name: i for i, w in enumerate(wires)}
    wires.sort(key=lambda w: (_group_key(w.group), order[w.name]))
    return wires, omitted


def _box_lines(act: Activation, m: ir.Morphism | None) -> list[str]:
    name = _clean(act.morphism)
    declared = [p.name for p in m.params] if m is not None else []
    keys = [k for k in declared if k in act.params] + [k for k in act.params if k not in declared]
    items = [_clean(f"{k}={_clip(format_value(act.params[k]), VALUE_CHARS)}") for k in keys]
    lines = [name] + _wrap_items(items, max(len(name), THETA_CHARS))
    if m is None:
        lines.append("(not in the model)")
    return lines


def _pieces(ys: list[float], ranks: list[int], need: float, mid_y: float) -> tuple[list[list[float]], int]:
    """The vertical parts of a box, and which part carries the label.

    A box spans from its top-most to its bottom-most touched wire; where a run of at least
    ``BREAK_RUN`` drawn wires lies between two touched ones, the box is broken into parts
    joined by a narrow stem, so that the long run of wires it does not touch stays readable.
    The tallest part carries the label (grown to fit it); parts that come too close merge."""
    if not ys:
        return [[mid_y - need / 2, mid_y + need / 2]], 0
    pieces = [[ys[0] - BOX_PAD_Y, ys[0] + BOX_PAD_Y]]
    for k in range(1, len(ys)):
        if ranks[k] - ranks[k - 1] - 1 >= BREAK_RUN:
            pieces.append([ys[k] - BOX_PAD_Y, ys[k] + BOX_PAD_Y])
        else:
            pieces[-1][1] = ys[k] + BOX_PAD_Y
    label = max(range(len(pieces)), key=lambda i: (pieces[i][1] - pieces[i][0], -i))
    top, bottom = pieces[label]
    if bottom - top < need:
        grow = (need - (bottom - top)) / 2
        pieces[label] = [top - grow, bottom + grow]
    k = 0
    while k < len(pieces) - 1:
        if pieces[k + 1][0] - pieces[k][1] < MIN_STEM:
            pieces[k] = [min(pieces[k][0], pieces[k + 1][0]), max(pieces[k][1], pieces[k + 1][1])]
            del pieces[k + 1]
            if label > k:
                label -= 1
            k = max(0, k - 1)
        else:
            k += 1
    return pieces, label


def _label_height(lines: list[str]) -> float:
    return LINE_NAME + LINE_THETA * (len(lines) - 1) + 2 * LABEL_PAD_Y


def _box_width(lines: list[str]) -> float:
    widths = [text_width(lines[0], FS_NAME)] + [text_width(t, FS_THETA) for t in lines[1:]]
    return max(BOX_MIN_W, max(widths) + 2 * BOX_PAD_X)


# ---------------------------------------------------------------- the renderer


class _Svg:
    """A thin builder over ElementTree that formats numbers deterministically."""

    def __init__(self) -> None:
        self.root = ET.Element("svg")

    @staticmethod
    def el(parent: ET.Element, tag: str, attrs: Mapping[str, Any] | None = None, text: str | None = None) -> ET.Element:
        node = ET.SubElement(parent, tag)
        for k, v in (attrs or {}).items():
            if v is None:
                continue
            node.set(k, _num(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else _clean(str(v)))
        if text is not None:
            node.text = _clean(text)
        return node

    def text(
        self,
        parent: ET.Element,
        x: float,
        y: float,
        s: str,
        *,
        size: float,
        anchor: str = "start",
        fill: str = INK,
        weight: str | None = None,
        style: str | None = None,
        cls: str | None = None,
    ) -> ET.Element:
        return self.el(
            parent,
            "text",
            {
                "class": cls,
                "x": x,
                "y": y,
                "font-size": size,
                "text-anchor": anchor,
                "fill": fill,
                "font-weight": weight,
                "font-style": style,
            },
            s,
        )


@dataclass
class _Tags:
    """The state values written on the wires: wire → (shown text, full text)."""

    initial: dict[str, tuple[str, str]] = field(default_factory=dict)
    final: dict[str, tuple[str, str]] = field(default_factory=dict)
    between: list[dict[str, tuple[str, str]]] = field(default_factory=list)  # after step i (not the last)


@dataclass
class _Columns:
    """The horizontal layout of the wires (the steps' columns lie between ``wire_start`` and ``final``)."""

    label_end: float  # the wire labels at the left end here
    wire_start: float
    final: float  # final-value tags start here
    wire_end: float
    right_label: float  # the wire names at the right start here
    right: float  # the diagram's right edge (the legend and title may widen the picture)


@dataclass
class _Rows:
    """The vertical layout around the wires: title, step headers, legend and footnote."""

    top: float
    header_y: float
    title_y: float | None
    legend_top: float
    legend_rows: list[list[tuple[str, float]]]
    foot_lines: list[str]
    bottom: float


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


# ---------------------------------------------------------------- layout steps


def _place_wires(wires: list[_Wire]) -> list[_Group]:
    """Set each wire's height, group by group; return the groups with their extents."""
    groups: list[_Group] = []
    y = 0.0
    for w in wires:
        if not groups or groups[-1].name != w.group:
            if groups:
                groups[-1].bottom = y - SPACING / 2
                y += GROUP_GAP - SPACING / 2
            groups.append(_Group(w.group, y, y))
            y += GROUP_HEAD + SPACING / 2
        w.y = y
        y += SPACING
    if groups:
        groups[-1].bottom = y - SPACING / 2
    return groups


def _place_boxes(instance: ir.Instance, plan: Plan, wires: list[_Wire], mid_y: float) -> list[_Step]:
    """The steps with their boxes: label lines, width, and vertical parts (not yet placed across)."""
    wire_at = {w.name: w for w in wires}
    rank = {w.name: i for i, w in enumerate(wires)}
    steps: list[_Step] = []
    for i, step in enumerate(plan.steps):
        st = _Step(header=f"t={i + 1}" + (" ⊗" if len(step) > 1 else ""))
        for act in step:
            m = instance.morphisms.get(act.morphism)
            kind = m.kind.value if m is not None else "unknown"
            reads = sorted((r for r in (m.reads if m else ()) if r in wire_at), key=rank.__getitem__)
            writes = sorted((r for r in (m.writes if m else ()) if r in wire_at), key=rank.__getitem__)
            touched = sorted(set(reads) | set(writes), key=rank.__getitem__)
            lines = _box_lines(act, m)
            box = _Box(i, act, kind, m, lines, reads, writes, touched, _box_width(lines))
            box.pieces, box.label_piece = _pieces(
                [wire_at[t].y for t in touched], [rank[t] for t in touched], _label_height(lines), mid_y
            )
            st.boxes.append(box)
        steps.append(st)
    return steps


def _tag_text(v: Any, chars: int) -> tuple[str, str]:
    full = _clean(format_value(v))
    return _clip(full, chars), full


def _state_tags(wires: list[_Wire], n_steps: int, states: Sequence[Mapping[str, Any]] | None) -> _Tags:
    """The initial and final values of the wires, and the values each step (but the last) changes."""
    tags = _Tags()
    if not states:
        return tags
    tags.initial = {w.name: _tag_text(states[0][w.name], VALUE_CHARS) for w in wires if w.name in states[0]}
    tags.final = {w.name: _tag_text(states[-1][w.name], VALUE_CHARS) for w in wires if w.name in states[-1]}
    for i in range(n_steps - 1):
        before, after = states[i], states[i + 1]
        tags.between.append(
            {
                w.name: _tag_text(after[w.name], BETWEEN_CHARS)
                for w in wires
                if w.name in after and (w.name not in before or before[w.name] != after[w.name])
            }
        )
    return tags


def _place_columns(wires: list[_Wire], groups: list[_Group], steps: list[_Step], tags: _Tags) -> _Columns:
    """Place the steps and their boxes left to right; return where the wires and their labels go."""
    label_w = max(
        [text_width(w.label, FS_WIRE) for w in wires] + [text_width(g.name, FS_SMALL) for g in groups] + [0.0]
    )
    init_w = max([text_width(s, FS_SMALL) + 10 for s, _ in tags.initial.values()] + [0.0])
    final_w = max([text_width(s, FS_SMALL) + 10 for s, _ in tags.final.values()] + [0.0])
    right_label_w = max([text_width(w.name, FS_SMALL) for w in wires] + [0.0])

    label_end = MARGIN + label_w
    wire_start = label_end + 8
    x = wire_start + (init_w + 8 if init_w else 0) + LEAD
    for i, st in enumerate(steps):
        inner = sum(b.w for b in st.boxes) + SUB_GAP * max(0, len(st.boxes) - 1)
        st.w = max(inner, text_width(st.header, FS_SMALL + 1) + 8, BOX_MIN_W if not st.boxes else 0)
        st.x = x
        bx = x + (st.w - inner) / 2
        for b in st.boxes:
            b.x = bx
            bx += b.w + SUB_GAP
        x += st.w
        if i < len(steps) - 1:
            gap = STEP_GAP
            if tags.between and tags.between[i]:
                gap = max(gap, max(text_width(s, FS_SMALL - 1) for s, _ in tags.between[i].values()) + 14)
            x += gap
    if not steps:
        x += 2 * LEAD  # an empty composition: bare identity wires
    final = x + LEAD
    wire_end = final + (final_w + 8 if final_w else 0)
    right_label = wire_end + 8
    return _Columns(label_end, wire_start, final, wire_end, right_label, right_label + right_label_w)


def _place_rows(
    steps: list[_Step],
    wires_top: float,
    wires_bottom: float,
    title: str | None,
    diagram_right: float,
    with_states: bool,
    omitted: list[str],
) -> _Rows:
    """The title and step headers above the wires and boxes, the legend and footnote below."""
    content_top = min([wires_top] + [b.top for st in steps for b in st.boxes])
    content_bottom = max([wires_bottom] + [b.bottom for st in steps for b in st.boxes])
    header_y = content_top - 10
    top = header_y - FS_SMALL - 8 if steps else content_top - 4
    title_y = None
    if title:
        title_y = top - 6
        top = title_y - FS_TITLE - 4
    legend_rows = _legend_rows(_legend_items(with_states), max(diagram_right - MARGIN, 560.0))
    legend_top = content_bottom + 22
    foot_lines = _footnote(omitted)
    if not steps:
        foot_lines.insert(0, "The empty composition: the identity on every resource.")
    bottom = legend_top + 20 * len(legend_rows) + 14 * len(foot_lines) + 6
    return _Rows(top, header_y, title_y, legend_top, legend_rows, foot_lines, bottom)


def _legend_rows(items: list[tuple[str, float]], width_avail: float) -> list[list[tuple[str, float]]]:
    """The legend items, wrapped into rows no wider than ``width_avail``."""
    rows: list[list[tuple[str, float]]] = [[]]
    row_w = 0.0
    for item, w in items:
        if rows[-1] and row_w + w > width_avail:
            rows.append([])
            row_w = 0.0
        rows[-1].append((item, w))
        row_w += w + 18
    return rows


# ---------------------------------------------------------------- drawing steps


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


# ---------------------------------------------------------------- pieces


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


def _legend_items(with_states: bool) -> list[tuple[str, float]]:
    items = [(k, 26 + text_width(KIND_STYLE[k]["label"], FS_SMALL)) for k in ("hardware", "software", "behavior")]
    items += [
        ("read", 30 + text_width(_LEGEND_TEXT["read"], FS_SMALL)),
        ("write", 30 + text_width(_LEGEND_TEXT["write"], FS_SMALL)),
        ("passover", 38 + text_width(_LEGEND_TEXT["passover"], FS_SMALL)),
        ("stem", 32 + text_width(_LEGEND_TEXT["stem"], FS_SMALL)),
        ("steps", text_width(_LEGEND_TEXT["steps"], FS_SMALL)),
    ]
    if with_states:
        items.append(("states", 34 + text_width(_LEGEND_TEXT["states"], FS_SMALL)))
    return items


_LEGEND_TEXT = {
    "read": "reads (precondition port)",
    "write": "writes (effect port)",
    "passover": "passes over, not touched",
    "stem": "one box, broken where untouched wires cross",
    "steps": "t=k: step k; ⊗ parallel in a step; steps compose left → right (∘)",
    "states": "state value: initial at left, final at right, changes after each step",
}


def _legend_item(svg: _Svg, parent: ET.Element, item: str, x: float, y: float) -> None:
    g = svg.el(parent, "g", {"class": f"legend-item {item}"})
    if item in KIND_STYLE:
        _legend_kind(svg, g, item, x, y)
    elif item in _LEGEND_SYMBOLS:
        _LEGEND_SYMBOLS[item](svg, g, item, x, y)
    else:
        svg.text(g, x, y + 4, _LEGEND_TEXT[item], size=FS_SMALL)


def _legend_kind(svg: _Svg, g: ET.Element, item: str, x: float, y: float) -> None:
    st = KIND_STYLE[item]
    svg.el(
        g,
        "rect",
        {
            "class": "legend-symbol",
            "x": x,
            "y": y - 6,
            "width": 20,
            "height": 13,
            "rx": 3,
            "fill": st["fill"],
            "stroke": st["stroke"],
            "stroke-width": 1.4,
        },
    )
    svg.text(g, x + 26, y + 4, st["label"], size=FS_SMALL)


def _legend_port(svg: _Svg, g: ET.Element, item: str, x: float, y: float) -> None:
    svg.el(
        g,
        "line",
        {"class": "legend-symbol", "x1": x, "y1": y, "x2": x + 20, "y2": y, "stroke": WIRE, "stroke-width": 1.4},
    )
    filled = item == "write"
    svg.el(
        g,
        "circle",
        {
            "class": "legend-symbol",
            "cx": x + 10,
            "cy": y,
            "r": PORT_R,
            "fill": INK if filled else "#FFFFFF",
            "stroke": INK,
            "stroke-width": 1.4,
        },
    )
    svg.text(g, x + 30, y + 4, _LEGEND_TEXT[item], size=FS_SMALL)


def _legend_passover(svg: _Svg, g: ET.Element, item: str, x: float, y: float) -> None:
    svg.el(
        g,
        "rect",
        {
            "class": "legend-symbol",
            "x": x,
            "y": y - 7,
            "width": 28,
            "height": 14,
            "rx": 3,
            "fill": "#E6E6E6",
            "stroke": "#999999",
            "stroke-width": 1,
        },
    )
    svg.el(
        g,
        "line",
        {
            "class": "legend-symbol",
            "x1": x + 1,
            "y1": y,
            "x2": x + 27,
            "y2": y,
            "stroke": "#7A7A7A",
            "stroke-width": 1,
            "stroke-dasharray": "3 3",
        },
    )
    svg.text(g, x + 38, y + 4, _LEGEND_TEXT[item], size=FS_SMALL)


def _legend_stem(svg: _Svg, g: ET.Element, item: str, x: float, y: float) -> None:
    for y0, y1 in ((y - 9, y - 3), (y + 3, y + 9)):
        svg.el(
            g,
            "rect",
            {
                "class": "legend-symbol",
                "x": x + 8,
                "y": y0,
                "width": STEM_W,
                "height": y1 - y0,
                "fill": "#E6E6E6",
                "stroke": "#999999",
                "stroke-width": 1,
            },
        )
    svg.el(
        g,
        "line",
        {"class": "legend-symbol", "x1": x, "y1": y, "x2": x + 24, "y2": y, "stroke": WIRE, "stroke-width": 1.4},
    )
    svg.text(g, x + 32, y + 4, _LEGEND_TEXT[item], size=FS_SMALL)


def _legend_states(svg: _Svg, g: ET.Element, item: str, x: float, y: float) -> None:
    svg.el(
        g,
        "rect",
        {
            "class": "legend-symbol",
            "x": x,
            "y": y - 7.5,
            "width": 24,
            "height": 15,
            "rx": 3,
            "fill": "#FFFFFF",
            "stroke": "#8E7CC3",
            "stroke-width": 0.9,
        },
    )
    svg.text(g, x + 4, y + 3.5, "v", size=FS_SMALL, fill="#3F2A6B")
    svg.text(g, x + 34, y + 4, _LEGEND_TEXT[item], size=FS_SMALL)


#: How each legend item other than the kinds draws its symbol and text (``steps`` has text only).
_LEGEND_SYMBOLS: dict[str, Callable[[_Svg, ET.Element, str, float, float], None]] = {
    "read": _legend_port,
    "write": _legend_port,
    "passover": _legend_passover,
    "stem": _legend_stem,
    "states": _legend_states,
}


def _footnote(omitted: Iterable[str]) -> list[str]:
    omitted = list(omitted)
    if not omitted:
        return []
    n = len(omitted)
    head = f"{n} resource{'s' if n != 1 else ''} not read or written by this composition, not drawn: "
    return _wrap_text(head, [_clean(r) for r in omitted], MAX_FOOT_CHARS)


def _wrap_text(head: str, items: list[str], limit: int) -> list[str]:
    lines = [head.rstrip()]
    for i, item in enumerate(items):
        piece = item + ("," if i < len(items) - 1 else ".")
        if len(lines[-1]) + 1 + len(piece) <= limit:
            lines[-1] = f"{lines[-1]} {piece}"
        else:
            lines.append("  " + piece)
    return lines
