"""Where everything goes: the wires in their groups, the boxes of each step (broken into parts
across runs of untouched wires), the state tags, the columns and the rows around them."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from catc import ir
from catc.present.diagram.legend import _legend_items, _legend_rows
from catc.present.diagram.style import (
    BETWEEN_CHARS,
    BOX_MIN_W,
    BOX_PAD_X,
    BOX_PAD_Y,
    BREAK_RUN,
    FS_NAME,
    FS_SMALL,
    FS_THETA,
    FS_TITLE,
    FS_WIRE,
    GROUP_GAP,
    GROUP_HEAD,
    GROUP_ORDER,
    LABEL_PAD_Y,
    LEAD,
    LINE_NAME,
    LINE_THETA,
    MARGIN,
    MAX_FOOT_CHARS,
    MIN_STEM,
    OTHERS,
    SPACING,
    STEP_GAP,
    SUB_GAP,
    THETA_CHARS,
    VALUE_CHARS,
    _clean,
    _clip,
    _wrap_items,
    format_value,
    text_width,
)
from catc.semantics.plan import Activation, Plan


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
