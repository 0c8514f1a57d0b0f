"""Generated catalogs for the lifelong queries at scale (issue 16): solve, diagnose and relax
of infeasible variants with cores known by construction, against ENHSP, with a growth table,
a log-log plot and the fitted exponent.

    python benchmarks/catalogs.py [--sizes 25,50,100,200,400] [--depths 3,6,12,24]
                                  [--variants price,ram] [--seed 16] [--timeout 60]
                                  [--no-enhsp] [--plot docs/img/catalogs.png] [--quick]

A catalog of ``n`` components builds a chain of ``d`` capabilities ``cap1 … capd`` (the goal is
``capd``); every level has ``⌊0.75 n / d⌋`` interchangeable providers (each needs the level
below and some CPU), and a quarter of the components are distractors (a chain of their own
that never reaches the goal).  The problem deploys one provider per level.  Halfway up the
chain, the providers need something only special components give:

* ``price`` — a gate ``g`` that needs ``(>= budget P)``; the budget only decreases and starts
  below ``P``.  Infeasible at any horizon; the relaxation sees it.  Core relative to the
  deployed composition: ``{init/budget, pre/g/1}``; least relaxation ``budget + (P - B)``.
* ``ram`` — two modules ``a`` and ``b`` that each need ``(>= ram 6)`` and use 6 of it, with
  ``ram`` 10 (no bounds).  Each alone can run, not both: the relaxation cannot see it (``ram``
  may be anywhere in [−∞, 10]).  Core: ``{init/ram, pre/a/1, eff/a/2, pre/b/1, eff/b/2}``;
  least relaxation ``ram + 2``.

Those cores are the only ones (derived by hand in the docstring of :func:`catalog`), so the
script checks that diagnose finds exactly them and relax exactly those amounts.  Every query
runs in this process on the loaded model (process start excluded); ENHSP (``sat-hadd`` on the
exported PDDL) as a process, as in docs/benchmarks.md's other tables.
"""

from __future__ import annotations

import argparse
import math
import random
import sys
import tempfile
import time
from collections.abc import Callable
from fractions import Fraction
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT / "compiler")]

VARIANTS = ("price", "ram")


def catalog(n: int, d: int, variant: str, seed: int = 16) -> tuple[str, dict]:
    """The catalog's text (domain and problem in one file) and what it must answer.

    Why the cores are unique: relative to the deployed composition every deployed component
    must fire and no other may.  ``price``: ``g`` fires only with ``budget ≥ P`` but the budget
    starts at ``B < P`` and only decreases — so {init/budget, pre/g/1} is infeasible; without
    the initial value the budget is free, without the precondition ``g`` fires, and everything
    else of the composition is feasible (the chain is satisfiable step by step: CPU is
    plentiful), so it is the only core.  ``ram``: ``a`` and ``b`` both fire; whichever fires
    second finds ``ram = 4 < 6`` (they cannot share a step: both touch ``ram``).  Without
    init/ram, ram is free; without either precondition that module goes second; without
    either effect that module leaves ram at 10.  Nothing else touches ram."""
    if variant not in VARIANTS:
        raise ValueError(f"variant {variant!r}: one of {', '.join(VARIANTS)}")
    rng = random.Random(f"{seed}/{n}/{d}/{variant}")
    per_level = max(1, (3 * n) // (4 * d))
    distractors = max(1, n - per_level * d)
    gate_level = max(1, d // 2)
    cpu = 4 * n
    lines = [
        f"(define (domain catalog-{variant}-{n}-{d})",
        "  (:requirements :numeric :recomposition)",
        "  (:resources (cpu real :bounds (0 *))"
        + (" (budget real :bounds (0 *))" if variant == "price" else " (ram real)")
        + "".join(f" (cap{i} bool)" for i in range(1, d + 1))
        + "".join(f" (junk{i} bool)" for i in range(distractors))
        + " (gate bool))",
    ]
    deployed: list[str] = []
    for level in range(1, d + 1):
        for j in range(per_level):
            name = f"p{level}-{j}"
            need = [f"cap{level - 1}"] if level > 1 else []
            if level == gate_level + 1:
                need.append("gate")
            w = rng.choice((1, 2, 3))
            need.append(f"(>= cpu {w})")
            lines.append(
                f"  (:morphism {name} :kind software :uses 1\n"
                f"    :precondition (and {' '.join(need)})\n"
                f"    :effect (and (assign cap{level} true) (decrease cpu {w})))"
            )
            if j == 0:
                deployed.append(name)
    for i in range(distractors):
        need = f"junk{i - 1}" if i > 0 else "(>= cpu 1)"
        lines.append(
            f"  (:morphism x{i} :kind software :uses 1 :precondition {need}\n"
            f"    :effect (and (assign junk{i} true) (decrease cpu 1)))"
        )
    price, budget = Fraction(rng.randrange(2000, 30000)), Fraction(rng.randrange(100, 1000))
    if variant == "price":
        lines.append(
            f"  (:morphism g :kind hardware :uses 1 :precondition (>= budget {price})\n"
            f"    :effect (and (decrease budget {price}) (assign gate true)))"
        )
        deployed.append("g")
        core = ["init/budget", "pre/g/1"]
        relax = {"init/budget": price - budget}
    else:
        for m in ("a", "b"):
            lines.append(
                f"  (:morphism {m} :kind software :uses 1 :precondition (>= ram 6)\n"
                f"    :effect (and (assign {m}-done true) (decrease ram 6)))"
            )
        lines[2] = lines[2].replace(" (gate bool))", " (gate bool) (a-done bool) (b-done bool))")
        lines.append("  (:morphism open-gate :kind software :uses 1 :precondition (and a-done b-done)")
        lines.append("    :effect (assign gate true))")
        deployed += ["a", "b", "open-gate"]
        core = ["init/ram", "pre/a/1", "eff/a/2", "pre/b/1", "eff/b/2"]
        relax = {"init/ram": Fraction(2)}
    lines.append(")")
    horizon = d + 4
    lines.append(
        f"(define (problem p) (:domain catalog-{variant}-{n}-{d})\n"
        f"  (:init (= cpu {cpu}) {f'(= budget {budget})' if variant == 'price' else '(= ram 10)'})\n"
        f"  (:goal cap{d})\n  (:horizon {horizon})\n  (:deployed {' '.join(deployed)}))"
    )
    return "\n".join(lines) + "\n", {"core": sorted(core), "relax": relax, "components": per_level * d + distractors}


# ---------------------------------------------------------------- running


def _timed(run: Callable[[], object]) -> tuple[float, object]:
    start = time.perf_counter()
    out = run()
    return time.perf_counter() - start, out


def measure(text: str, expect: dict, timeout: float, enhsp: bool, workdir: Path) -> dict[str, object]:
    """Each query on one loaded model: its wall time, or 'timeout'; ENHSP as a process."""
    from catc.api import loads
    from catc.queries.diagnose import diagnose
    from catc.queries.relax import relax
    from catc.queries.solve import solve

    inst = loads({"catalog.cat": text}, "catalog.cat").instance
    row: dict[str, object] = {}
    for name, run in (
        ("solve", lambda: solve(inst, strategy="single", timeout=timeout)),
        ("solve (no presolve)", lambda: solve(inst, strategy="single", timeout=timeout, presolve=False)),
        ("diagnose", lambda: diagnose(inst, timeout=timeout)),
        ("diagnose (no presolve)", lambda: diagnose(inst, timeout=timeout, presolve=False)),
        ("relax", lambda: relax(inst, timeout=timeout)),
    ):
        wall, res = _timed(run)
        row[name] = _judge(name, res, expect, wall)
    if enhsp:
        row["ENHSP"] = _enhsp(inst, workdir, timeout)
    return row


def _judge(name: str, res: object, expect: dict, wall: float) -> object:
    status = getattr(res, "status", None)
    value = getattr(status, "value", status)
    if name.startswith("solve"):
        ok = value == "unsat"
    elif name.startswith("diagnose"):
        cores = getattr(res, "cores", [])
        ok = value == "unsat" and bool(cores) and sorted(cores[0]) == expect["core"]
    else:
        got = {r.label: r.delta for r in getattr(res, "relaxations", [])}
        ok = value == "relaxed" and got == expect["relax"] and getattr(res, "proven", True)
    if value in ("unknown", None) or (not ok and value in ("subopt",)):
        return "timeout"
    if not ok:
        raise SystemExit(f"{name}: wrong answer {value} {res!r} (expected {expect})")
    return wall


def _enhsp(inst: object, workdir: Path, timeout: float) -> object:
    try:
        from catc.targets.enhsp import run_enhsp
        from catc.targets.pddl import export_pddl
    except ImportError:  # pragma: no cover - the baselines extra
        return "n/a"
    export = export_pddl(inst)  # type: ignore[arg-type]
    dom, prob = workdir / "domain.pddl", workdir / "problem.pddl"
    dom.write_text(export.domain)
    prob.write_text(export.problem)
    try:
        res = run_enhsp(dom, prob, planner="sat-hadd", timeout=timeout)
    except Exception as exc:  # no Java or no jar: say so in the table
        return f"n/a ({type(exc).__name__})"
    if res.status == "timeout":
        return "timeout"
    if res.status not in ("unsat", "unsolvable"):
        raise SystemExit(f"ENHSP: expected unsolvable, got {res.status}")
    return res.wall


# ---------------------------------------------------------------- the report


def fit_exponent(points: list[tuple[float, float]]) -> float | None:
    """The slope of log(time) against log(n), least squares (None with fewer than 2 points)."""
    pts = [(math.log(x), math.log(y)) for x, y in points if y > 0]
    if len(pts) < 2:
        return None
    mx = sum(x for x, _ in pts) / len(pts)
    my = sum(y for _, y in pts) / len(pts)
    sxx = sum((x - mx) ** 2 for x, _ in pts)
    return None if sxx == 0 else sum((x - mx) * (y - my) for x, y in pts) / sxx


def _cell(v: object) -> str:
    return f"{v:.3f}" if isinstance(v, float) else str(v)


def report(rows: list[tuple[str, int, int, int, dict]], tools: list[str], argv: list[str]) -> None:
    print("### Generated catalogs: infeasible variants, cores and relaxations known by construction\n")
    print(f"`python benchmarks/catalogs.py {' '.join(argv)}` — seconds in process (ENHSP: a process).\n")
    print("| variant | n | d | components | " + " | ".join(tools) + " | diagnose ÷ solve (no presolve) |")
    print("|---|---:|---:|---:|" + "---:|" * len(tools) + "---:|")
    for variant, n, d, comps, row in rows:
        ratio = row.get("diagnose"), row.get("solve (no presolve)")
        r = f"{ratio[0] / ratio[1]:.2f}" if all(isinstance(x, float) for x in ratio) else "—"
        print(f"| {variant} | {n} | {d} | {comps} | " + " | ".join(_cell(row.get(t, "")) for t in tools) + f" | {r} |")
    print("\nFitted exponent k of time ∝ n^k (least squares on log-log, per variant and depth; timeouts left out):\n")
    print("| variant | d | " + " | ".join(tools) + " |")
    print("|---|---:|" + "---:|" * len(tools))
    for variant in sorted({r[0] for r in rows}):
        for d in sorted({r[2] for r in rows if r[0] == variant}):
            cells = []
            for t in tools:
                pts = [
                    (float(n), v)
                    for var, n, dd, _, row in rows
                    if var == variant and dd == d
                    for v in [row.get(t)]
                    if isinstance(v, float)
                ]
                k = fit_exponent(pts)
                cells.append("—" if k is None else f"{k:.2f}")
            print(f"| {variant} | {d} | " + " | ".join(cells) + " |")
    print()


def plot(rows: list[tuple[str, int, int, int, dict]], tools: list[str], path: Path) -> None:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print(f"(no plot: matplotlib is not installed — pip install 'catc-lang[plots]'; wanted {path})")
        return
    variants = sorted({r[0] for r in rows})
    fig, axes = plt.subplots(1, len(variants), figsize=(6 * len(variants), 4.5), squeeze=False)
    for ax, variant in zip(axes[0], variants, strict=True):
        depth = max(r[2] for r in rows if r[0] == variant)
        for t in tools:
            pts = sorted(
                (n, row[t])
                for var, n, d, _, row in rows
                if var == variant and d == depth and isinstance(row.get(t), float)
            )
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label=t)
        ax.set_xscale("log")
        ax.set_yscale("log")
        from matplotlib.ticker import NullFormatter, ScalarFormatter

        sizes = sorted({r[1] for r in rows if r[0] == variant})
        ax.set_xticks(sizes)
        ax.xaxis.set_major_formatter(ScalarFormatter())
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_xlabel("components n")
        ax.set_ylabel("seconds")
        ax.set_title(f"{variant} variant, chain depth {depth}")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    print(f"(plot written to {path})")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", default="25,50,100,200,400")
    ap.add_argument("--depths", default="3,6,12,24")
    ap.add_argument("--variants", default=",".join(VARIANTS))
    ap.add_argument("--seed", type=int, default=16)
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--no-enhsp", action="store_true")
    ap.add_argument("--plot", type=Path, default=None)
    ap.add_argument("--quick", action="store_true", help="n = 12, 25 and d = 3 only (a smoke test)")
    args = ap.parse_args(argv)
    argv = sys.argv[1:] if argv is None else argv
    sizes = [12, 25] if args.quick else [int(x) for x in args.sizes.split(",")]
    depths = [3] if args.quick else [int(x) for x in args.depths.split(",")]
    tools = ["solve", "solve (no presolve)", "diagnose", "diagnose (no presolve)", "relax"]
    tools += [] if args.no_enhsp else ["ENHSP"]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for variant in args.variants.split(","):
            for d in depths:
                for n in sizes:
                    if n < d:
                        continue
                    text, expect = catalog(n, d, variant, args.seed)
                    row = measure(text, expect, args.timeout, not args.no_enhsp, Path(tmp))
                    rows.append((variant, n, d, expect["components"], row))
                    print(
                        f"  {variant} n={n} d={d}: " + ", ".join(f"{k} {_cell(v)}" for k, v in row.items()),
                        file=sys.stderr,
                        flush=True,
                    )
    report(rows, tools, argv)
    if args.plot is not None:
        plot(rows, tools, args.plot)
    return 0


if __name__ == "__main__":
    sys.exit(main())
