"""Writing SVG: a thin builder over :mod:`xml.etree.ElementTree` that formats numbers
deterministically (0.1 px, no ``-0``) and cleans every text it sets."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Mapping
from typing import Any

from catc.present.diagram.style import INK, _clean, _num


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
