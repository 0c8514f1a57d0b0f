"""The diagram's style (colours, sizes, spacing) and its text helpers: widths estimated
from character counts in a monospace family, text made safe for XML, values printed exactly."""

from __future__ import annotations

import unicodedata
from collections.abc import Sequence
from fractions import Fraction
from typing import Any

from catc.ir.numbers import ratio_text

GROUP_ORDER = ("electromechanical", "compute", "info", "external")


OTHERS = "others"


FONT_FAMILY = "DejaVu Sans Mono, Menlo, Consolas, Liberation Mono, monospace"


CHAR_EM = 0.602  # advance of one monospace character, in em (DejaVu Sans Mono)


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
