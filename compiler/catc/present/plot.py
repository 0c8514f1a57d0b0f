"""Pictures of a Pareto front: as text for the terminal, and as PNG/SVG with matplotlib.

Each point is a tuple of exact objective values; the first two objectives are the axes, a
third (when there is one) the colour.
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction

Point = Sequence[Fraction]


_LETTERS = "abcdefghijklmnopqrstuvwxyz"


def _mark(n: int) -> str:
    """Point ``n``'s mark: 1-9 its digit, 10-35 a letter (a = 10), later ones ``+``."""
    if n < 10:
        return str(n)
    return _LETTERS[n - 10] if n - 10 < len(_LETTERS) else "+"


def ascii_plot(points: Sequence[Point], labels: list[str], width: int = 56, height: int = 14) -> str:
    """The front on the first two objectives, as text (no plotting library needed).  A
    front of one point is not drawn (a sentence says so); when every point has the same
    second value the plot is one row high.  The legend names only the marks drawn."""
    xs = [float(p[0]) for p in points]
    ys = [float(p[1]) for p in points]
    if not xs:
        return ""
    if len(xs) == 1:
        return "a front of one point: nothing to plot"
    x0, x1 = min(xs), max(xs)
    y0, y1 = min(ys), max(ys)
    if y1 == y0:
        height = 1
    grid = [[" "] * width for _ in range(height)]
    for n, (x, y) in enumerate(zip(xs, ys), 1):
        col = 0 if x1 == x0 else round((x - x0) / (x1 - x0) * (width - 1))
        row = 0 if y1 == y0 else round((y - y0) / (y1 - y0) * (height - 1))
        cell = grid[height - 1 - row][col]
        grid[height - 1 - row][col] = _mark(n) if cell == " " else "*"
    drawn = {c for cells in grid for c in cells}
    y_hi, y_lo = f"{y1:.4g}", f"{y0:.4g}"
    pad = max(len(y_hi), len(y_lo))
    lines = [f"{labels[1]} ↑"]
    for i, cells in enumerate(grid):
        tick = y_hi if i == 0 else y_lo if i == height - 1 else ""
        lines.append(f"{tick.rjust(pad)} |{''.join(cells)}")
    lines.append(" " * pad + " +" + "-" * width)
    left, right = f"{x0:.4g}", f"{x1:.4g}"
    lines.append(" " * (pad + 2) + left + " " * max(1, width - len(left) - len(right)) + right)
    legend = []
    if drawn & set("123456789"):
        legend.append("digits: the points' numbers in the table")
    letters = sorted(drawn & set(_LETTERS))
    if letters:
        first, last = letters[0], letters[-1]
        span = first if first == last else f"{first}-{last}"
        legend.append(f"{span}: point{'s' if first != last else ''} {_LETTERS.index(first) + 10}"
                      + ("" if first == last else f"-{_LETTERS.index(last) + 10}"))  # fmt: skip
    if "+" in drawn:
        legend.append(f"+: a point after {len(_LETTERS) + 9}")
    if "*" in drawn:
        legend.append("*: several points in one place")
    lines.append(" " * (pad + 2) + f"{labels[0]} →   ({'; '.join(legend)})")
    return "\n".join(lines)


def draw_front(points: Sequence[Point], labels: list[str], path: str) -> None:
    """PNG or SVG via matplotlib (the optional 'plots' extra); RuntimeError without it."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise RuntimeError("--plot needs matplotlib: pip install 'catc-lang[plots]'") from exc
    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=120)
    xs = [float(p[0]) for p in points]
    ys = [float(p[1]) for p in points]
    extra = len(labels) > 2
    colours = [float(p[2]) for p in points] if extra else None
    sc = ax.scatter(xs, ys, c=colours, cmap="viridis" if extra else None, s=42, zorder=3)
    order = sorted(range(len(xs)), key=lambda i: (xs[i], ys[i]))
    if not extra:
        ax.plot([xs[i] for i in order], [ys[i] for i in order], color="0.6", lw=1, zorder=2)
    for n, (x, y) in enumerate(zip(xs, ys), 1):
        ax.annotate(str(n), (x, y), textcoords="offset points", xytext=(4, 4), fontsize=8)
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    if extra:
        fig.colorbar(sc, ax=ax, label=labels[2])
    ax.set_title(f"Pareto front: {len(points)} non-dominated compositions")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
