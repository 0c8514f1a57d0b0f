"""The legend: which items it shows, their widths and rows, and the symbol each draws."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Callable

from catc.present.diagram.style import FS_SMALL, INK, KIND_STYLE, PORT_R, STEM_W, WIRE, text_width
from catc.present.diagram.writer import _Svg


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
