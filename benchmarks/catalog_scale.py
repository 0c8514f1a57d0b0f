"""Issue 24's scaling benchmark: every lifelong query on benchmarks/catalog_gen.py's catalogs,
as processes with a time limit, beside ENHSP on the SAT variant; a table, a growth table
with the fitted exponent per query, and the answers checked against the constructed ones.

    python benchmarks/catalog_scale.py [--sizes 25,50,100,200,400] [--depths 3,6,12,24]
                                       [--variant budget] [--timeout 60] [--seed 24]
                                       [--no-enhsp] [--quick] [--queries Q1,Q2]
                                       [--trees main=/work/main,branch=.] [--plot FILE]

Each cell is the wall time of one ``catc`` process (start-up included), or ``timeout`` /
``unknown`` (exit 3) / ``WRONG`` (an answer that differs from the constructed one: the
script exits 1).  ``UNSAT solve`` must be final (no composition of any length).
``--trees NAME=DIR,...`` runs every cell once per source tree (``DIR/compiler``,
``DIR/runtime`` and ``DIR`` on ``PYTHONPATH``), one after the other, so that trees are
compared side by side under the same load; ``--plot FILE`` draws time against n on
log-log axes, one panel per query (needs the ``plots`` extra: matplotlib).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time
from fractions import Fraction
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import catalog_gen as gen  # noqa: E402

QUERIES = (
    "solve SAT",
    "UNSAT solve",
    "diagnose",
    "relax",
    "recompose (stability)",
    "recompose (objective)",
    "ENHSP SAT",
)


def _env(tree: Path | None) -> dict[str, str]:
    env = dict(os.environ)
    if tree is not None:
        env["PYTHONPATH"] = os.pathsep.join(str(tree / x) for x in ("compiler", "runtime", ""))
    return env


def _run(args: list[str], timeout: float, cwd: Path, tree: Path | None = None) -> tuple[float | str, int, str]:
    start = time.perf_counter()
    try:
        p = subprocess.run(args, cwd=cwd, capture_output=True, text=True, timeout=timeout + 15, env=_env(tree))
    except subprocess.TimeoutExpired:
        return "timeout", 3, ""
    wall = time.perf_counter() - start
    return wall, p.returncode, p.stdout


def _doc(out: str) -> dict:
    try:
        return json.loads(out)
    except json.JSONDecodeError:
        return {}


def measure(
    n: int,
    d: int,
    variant: str,
    timeout: float,
    seed: int,
    enhsp: bool,
    tmp: Path,
    tree: Path | None = None,
    queries: tuple[str, ...] = QUERIES,
) -> dict[str, object]:
    cat = gen.build(n, d, seed)
    expect = gen.write(cat, tmp)[variant]
    rec = gen.write(cat, tmp)["recompose"]
    dom = "missing-domain.cat" if variant == "missing" else "domain.cat"
    t = ["--timeout", str(timeout)]
    catc = [sys.executable, "-m", "catc"]
    row: dict[str, object] = {"components": cat.components}

    def cell(name: str, args: list[str], ok) -> None:
        if name not in queries:
            return
        wall, rc, out = _run(catc + args, timeout, tmp, tree)
        if wall == "timeout" or rc == 3:
            row[name] = "timeout" if wall == "timeout" else "unknown"
            return
        row[name] = wall if ok(rc, _doc(out)) else "WRONG"

    cell("solve SAT", ["solve", "domain.cat", "sat.cat", "--json", *t], lambda rc, j: j.get("status") == "sat")
    cell(
        "UNSAT solve",
        ["solve", dom, f"{variant}.cat", "--json", *t],
        lambda rc, j: j.get("status") == "unsat" and j.get("unsat", {}).get("final") is True,
    )

    def core_ok(rc: int, j: dict) -> bool:
        cores = j.get("cores") or []
        labels = {x.get("label") for x in cores[0]} if cores else set()
        return j.get("status") == "unsat" and set(expect["core_contains"]) <= labels

    cell("diagnose", ["diagnose", dom, f"{variant}.cat", "--json", *t], core_ok)

    def relax_ok(rc: int, j: dict) -> bool:
        if expect["relax"] is None:
            return j.get("status") == "unsat"
        got = {r["label"]: r["delta"] for r in j.get("relaxations", [])}
        want = {k: str(v) for k, v in expect["relax"].items()}
        return j.get("status") == "relaxed" and j.get("proven") is True and {k: str(v) for k, v in got.items()} == want

    cell("relax", ["relax", dom, f"{variant}.cat", "--json", *t], relax_ok)
    rtext = gen.problem_text(cat, "recompose")[0]
    rinit = {r: int(v) for r, v in re.findall(r"\(= (\w+) (-?\d+)\)", rtext)}
    deployed = re.search(r"\(:deployed ([^)]*)\)", rtext)
    best = best_selection(cat, rinit, deployed.group(1).split()) if deployed else None

    def recompose_ok(rc: int, j: dict, p: str) -> bool:
        """opt; stability first the constructed least churn; objective first the best
        selection's budget left and at most its churn (see best_selection)."""
        if j.get("status") != "opt" or (p == "stability" and j.get("churn") != rec["churn"]):
            return False
        if p == "stability" or best is None:
            return True
        budget = next((v.get("value") for v in j.get("objectives", []) if v.get("term") == "budget"), None)
        return budget is not None and Fraction(str(budget)) == best[0] and Fraction(str(j.get("churn"))) <= best[1]

    for priority in ("stability", "objective"):
        cell(
            f"recompose ({priority})",
            ["recompose", "domain.cat", "recompose.cat", "--priority", priority, "--json", *t],
            lambda rc, j, p=priority: recompose_ok(rc, j, p),
        )
    if enhsp:
        args = ["export", "pddl", "domain.cat", "sat.cat", "-o", "pddl", "--run", "--grid", "speed=1", *t]
        cell("ENHSP SAT", args, lambda rc, j: rc == 0)
    return row


def best_selection(cat: gen.Catalog, init: dict[str, int], deployed: list[str]) -> tuple[int, int] | None:
    """By dynamic programming, independently of catc: the most budget left, then the least
    churn, over the *selections* (one alternative per level, speeds at ``lo``) that fit
    ``init`` — churn counting each deployed alternative a selection leaves out and each it
    adds (weight 1); None when none fits.  By the construction (catalog_gen.py's docstring)
    every composition reaching the goal holds a selection, and anything else it holds only
    consumes more: so the best budget among compositions is the best here, and the churn
    here is one some composition has (a composition may do better by keeping a deployed
    component beside a new one: at most this).  The key is a sum over levels, and the
    software levels share no resource with the others (RAM and GPU memory against budget
    and power), so each group is solved alone over its used amounts (budget left out: it is
    minimised first, so the best key fits it whenever anything does) and the optima add up."""
    chosen = set(deployed)
    spent, churn = 0, 0
    for group in (("power",), ("ram", "gpu")):
        states: dict[tuple[int, ...], tuple[int, int]] = {tuple(0 for _ in group): (0, 0)}
        for alts in cat.levels:
            if (alts[0].kind == "software") != (group[0] == "ram"):
                continue
            new: dict[tuple[int, ...], tuple[int, int]] = {}
            for used, (b, c) in states.items():
                for a in alts:
                    need = a.need()
                    u = tuple(x + need[r] for x, r in zip(used, group, strict=True))
                    if any(x > init[r] for x, r in zip(u, group, strict=True)):
                        continue
                    key = (b + need["budget"], c + sum((x.name in chosen) != (x is a) for x in alts))
                    if u not in new or key < new[u]:
                        new[u] = key
            states = new
        if not states:
            return None
        best = min(states.values())
        spent, churn = spent + best[0], churn + best[1]
    return (init["budget"] - spent, churn) if spent <= init["budget"] else None


def fit_exponent(points: list[tuple[float, float]]) -> float | None:
    pts = [(math.log(x), math.log(y)) for x, y in points if y > 0]
    if len(pts) < 2:
        return None
    mx = sum(x for x, _ in pts) / len(pts)
    my = sum(y for _, y in pts) / len(pts)
    sxx = sum((x - mx) ** 2 for x, _ in pts)
    return None if sxx == 0 else sum((x - mx) * (y - my) for x, y in pts) / sxx


def plot(rows: list[tuple[int, int, str, dict]], queries: list[str], out: Path, timeout: float) -> None:
    """Time against n on log-log axes, one panel per query, a line per (tree, d); a cell
    without an answer is drawn at the time limit with an open marker."""
    import matplotlib  # the plots extra: imported only here

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    cols = min(4, len(queries))
    nrows = math.ceil(len(queries) / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(4 * cols, 3.4 * nrows), squeeze=False)
    for ax, q in zip([a for r in axes for a in r], queries, strict=False):
        for d in sorted({d for _, d, _, _ in rows}):
            for tree in dict.fromkeys(t for _, _, t, _ in rows):
                pts = [(n, row.get(q)) for n, dd, t, row in rows if dd == d and t == tree and q in row]
                if not pts:
                    continue
                label = f"{tree} d={d}".strip()
                xs = [n for n, _ in pts]
                ys = [v if isinstance(v, float) else timeout for _, v in pts]
                (line,) = ax.plot(xs, ys, label=label, linestyle="--" if tree == "main" else "-")
                for x, (_, v) in zip(xs, pts, strict=True):
                    ok = isinstance(v, float)
                    ax.plot(x, v if ok else timeout, "o", color=line.get_color(), fillstyle="full" if ok else "none")
        ax.set_xscale("log")
        ax.set_yscale("log")
        sizes = sorted({n for n, _, _, _ in rows})
        ax.set_xticks(sizes, [str(n) for n in sizes])
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_title(q)
        ax.set_xlabel("components n")
        ax.set_ylabel("seconds (process)")
        ax.axhline(timeout, color="grey", linewidth=0.5)
        ax.legend(fontsize=6)
    for ax in [a for r in axes for a in r][len(queries) :]:
        ax.set_visible(False)
    fig.tight_layout()
    fig.savefig(out)


def _cell(v: object) -> str:
    return f"{v:.1f}" if isinstance(v, float) else str(v)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", default="25,50,100,200,400")
    ap.add_argument("--depths", default="3,6,12,24")
    ap.add_argument("--variant", default="budget", choices=("budget", "power", "ram", "missing"))
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--seed", type=int, default=24)
    ap.add_argument("--no-enhsp", action="store_true")
    ap.add_argument("--quick", action="store_true", help="n = 12, 25 and d = 4 only (a smoke test)")
    ap.add_argument("--queries", default=",".join(QUERIES), help="the columns to run (comma-separated)")
    ap.add_argument("--trees", default="", help="NAME=DIR,... source trees to compare (default: this one)")
    ap.add_argument("--plot", type=Path, help="write a log-log plot of time against n here (matplotlib)")
    args = ap.parse_args(argv)
    shown = sys.argv[1:] if argv is None else argv
    sizes = [12, 25] if args.quick else [int(x) for x in args.sizes.split(",")]
    depths = [4] if args.quick else [int(x) for x in args.depths.split(",")]
    wanted = [q.strip() for q in args.queries.split(",")]
    queries = [q for q in QUERIES if q in wanted and not (args.no_enhsp and q.startswith("ENHSP"))]
    trees: list[tuple[str, Path | None]] = [
        (name, Path(path).resolve()) for name, _, path in (t.partition("=") for t in args.trees.split(",") if t)
    ] or [("", None)]
    rows: list[tuple[int, int, str, dict]] = []
    for d in depths:
        for n in sizes:
            if n < d or d < 3:
                continue
            for i, (name, tree) in enumerate(trees):
                mine = tuple(q for q in queries if i == 0 or not q.startswith("ENHSP"))  # ENHSP once
                with tempfile.TemporaryDirectory() as tmp:
                    row = measure(n, d, args.variant, args.timeout, args.seed, bool(mine), Path(tmp), tree, mine)
                row["load"] = os.getloadavg()[0]
                rows.append((n, d, name, row))
                print(
                    f"  n={n} d={d} {name}: " + ", ".join(f"{k} {_cell(v)}" for k, v in row.items()),
                    file=sys.stderr,
                    flush=True,
                )
    print(f"`python benchmarks/catalog_scale.py {' '.join(shown)}` — seconds per process, variant {args.variant}\n")
    print("| n | d | tree | components | " + " | ".join(queries) + " | load (1 min) |")
    print("|---:|---:|---|---:|" + "---:|" * len(queries) + "---:|")
    for n, d, name, row in rows:
        cells = " | ".join(_cell(row.get(q, "")) for q in queries)
        print(f"| {n} | {d} | {name} | {row['components']} | {cells} | {row['load']:.1f} |")
    print("\nFitted exponent k of time ∝ n^k per depth (least squares on log-log; timeouts left out):\n")
    print("| d | tree | " + " | ".join(queries) + " |")
    print("|---:|---|" + "---:|" * len(queries))
    for d in sorted({d for _, d, _, _ in rows}):
        for name, _ in trees:
            cells = []
            for q in queries:
                pts = [
                    (float(n), v)
                    for n, dd, t, row in rows
                    if dd == d and t == name
                    for v in [row.get(q)]
                    if isinstance(v, float)
                ]
                k = fit_exponent(pts)
                cells.append("—" if k is None else f"{k:.2f}")
            print(f"| {d} | {name} | " + " | ".join(cells) + " |")
    if args.plot is not None:
        plot(rows, queries, args.plot, args.timeout)
    wrong = [(n, d, t, q) for n, d, t, row in rows for q, v in row.items() if v == "WRONG"]
    if wrong:
        print(f"\nWRONG answers: {wrong}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
