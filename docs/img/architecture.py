"""Draw docs/img/architecture.svg from the import contracts in pyproject.toml.

    python docs/img/architecture.py          # rewrite the picture
    python docs/img/architecture.py --check  # exit 1 when it is out of date (tests/test_architecture.py)

The stages and their order come from the layers contract (the same one `lint-imports`
enforces), each stage's modules from the source tree, and each module's job from the first
line of its docstring; so the picture cannot drift from the code.
"""

from __future__ import annotations

import ast
import re
import sys
import tomllib
import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
OUT = Path(__file__).resolve().parent / "architecture.svg"
PACKAGE = ROOT / "compiler" / "catc"

WIDTH = 1040
BAND = 26  # height per line of a stage box
GAP = 14
FONT = "DejaVu Sans, Verdana, sans-serif"
COLOURS = ["#fdf2e9", "#eaf2f8", "#e9f7ef", "#f4ecf7", "#fef9e7", "#ebf5fb", "#f2f3f4"]


def layers() -> list[list[str]]:
    """The stages, top (imports the most) to bottom, siblings in one list."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    for contract in config["tool"]["importlinter"]["contracts"]:
        if contract["type"] == "layers":
            return [[name.strip() for name in layer.split("|")] for layer in contract["layers"]]
    raise SystemExit("no layers contract in pyproject.toml")


def job(path: Path, name: str | None = None) -> str:
    """The module's job: the first line of its docstring, markup removed, cut at its first
    clause (``name: ...`` prefixes dropped)."""
    doc = ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))) or ""
    line = re.sub(r":\w+:`~?([^`]+)`", r"\1", doc.strip().split("\n")[0]).replace("``", "")
    line = re.sub(rf"^(catc )?{re.escape(name or path.stem)}: ", "", line, flags=re.IGNORECASE)
    return re.split(r" — |; |: (?=[a-z])", line.rstrip("."))[0]


def modules(stage: str) -> list[tuple[str, str]]:
    """(module name, its job) for every module of a stage."""
    path = PACKAGE / stage
    if path.is_dir():
        files = [p for p in path.glob("*.py") if p.name != "__init__.py"]
        files += [p / "__init__.py" for p in path.iterdir() if (p / "__init__.py").is_file()]  # subpackages
        named = [(p.parent.name + "/" if p.name == "__init__.py" else p.stem, p) for p in files]
        return [(name, job(p, name.rstrip("/"))) for name, p in sorted(named)]
    return [(stage, job(path.with_suffix(".py")))]


def clip(text: str, chars: int) -> str:
    return text if len(text) <= chars else text[: chars - 1] + "…"


def text(
    parent: ET.Element,
    x: float,
    y: float,
    s: str,
    size: int = 12,
    weight: str = "normal",
    fill: str = "#1b2631",
    anchor: str = "start",
) -> None:
    t = ET.SubElement(
        parent,
        "text",
        {
            "x": f"{x:g}",
            "y": f"{y:g}",
            "font-family": FONT,
            "font-size": str(size),
            "font-weight": weight,
            "fill": fill,
            "text-anchor": anchor,
        },
    )
    t.text = s


def draw() -> str:
    stages = layers()
    rows = [max(len(modules(s)) for s in row) for row in stages]
    height = 90 + sum(BAND * (n + 1) + GAP for n in rows) + 130
    svg = ET.Element(
        "svg",
        {
            "xmlns": "http://www.w3.org/2000/svg",
            "width": str(WIDTH),
            "height": str(height),
            "viewBox": f"0 0 {WIDTH} {height}",
        },
    )
    ET.SubElement(svg, "rect", {"x": "0", "y": "0", "width": str(WIDTH), "height": str(height), "fill": "white"})
    text(svg, 20, 32, "catc: stages, top to bottom; each imports only the stages below it", 18, "bold")
    text(
        svg,
        20,
        56,
        "siblings on one row are independent of each other; lint-imports enforces this (pyproject.toml)",
        12,
        fill="#566573",
    )
    y = 80
    left, right = 20, WIDTH - 190
    for i, (row, n) in enumerate(zip(stages, rows)):
        h = BAND * (n + 1)
        w = (right - left - GAP * (len(row) - 1)) / len(row)
        for j, stage in enumerate(row):
            x = left + j * (w + GAP)
            ET.SubElement(
                svg,
                "rect",
                {
                    "x": f"{x:g}",
                    "y": f"{y:g}",
                    "width": f"{w:g}",
                    "height": f"{h:g}",
                    "rx": "6",
                    "fill": COLOURS[i % len(COLOURS)],
                    "stroke": "#5d6d7e",
                },
            )
            text(svg, x + 10, y + 18, f"catc.{stage}", 14, "bold")
            chars = int(w / 6.1) - 4
            for k, (name, job) in enumerate(modules(stage)):
                line = f"{name}: {job}" if name != stage else job
                text(svg, x + 14, y + 18 + BAND * (k + 1) - 6, clip(line, chars), 11)
        y += h + GAP
    ax = right + 60
    ET.SubElement(
        svg,
        "line",
        {
            "x1": str(ax),
            "y1": "120",
            "x2": str(ax),
            "y2": f"{y - 24:g}",
            "stroke": "#5d6d7e",
            "stroke-width": "2",
            "marker-end": "url(#arrow)",
        },
    )
    text(svg, ax, 96, "imports", 12, fill="#566573", anchor="middle")
    text(svg, ax, 110, "point down", 12, fill="#566573", anchor="middle")
    defs = ET.SubElement(svg, "defs")
    marker = ET.SubElement(
        defs,
        "marker",
        {"id": "arrow", "markerWidth": "8", "markerHeight": "8", "refX": "4", "refY": "4", "orient": "auto"},
    )
    ET.SubElement(marker, "path", {"d": "M0,0 L8,4 L0,8 z", "fill": "#5d6d7e"})
    y += 10
    ET.SubElement(
        svg,
        "rect",
        {
            "x": str(left),
            "y": f"{y:g}",
            "width": f"{right - left:g}",
            "height": "34",
            "rx": "6",
            "fill": "#fbfcfc",
            "stroke": "#5d6d7e",
            "stroke-dasharray": "4 3",
        },
    )
    text(
        svg,
        left + 10,
        y + 22,
        "catgrammar: the language (grammar, parser, AST with spans, diagnostics and their "
        "codes, Pygments lexer); knows nothing of catc",
        12,
    )
    y += 56
    text(
        svg,
        left,
        y,
        "data path: text → tokens → AST (frontend) → checked IR (ir) → view functor → SMT script (smt)",
        12,
        fill="#566573",
    )
    text(
        svg,
        left + 62,
        y + 18,
        "→ backend → model → composition → validator (semantics) → output (present, targets)",
        12,
        fill="#566573",
    )
    ET.indent(svg)
    return ET.tostring(svg, encoding="unicode") + "\n"


def main() -> int:
    picture = draw()
    if "--check" in sys.argv:
        return 0 if OUT.exists() and OUT.read_text(encoding="utf-8") == picture else 1
    OUT.write_text(picture, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
