"""Pareto fronts: every non-dominated composition for two or more objectives (paper §V-A).

The guided improvement algorithm (Rayside et al., "The guided improvement algorithm for
exact, general-purpose, many-objective combinatorial optimization", 2009) needs nothing but
satisfiability checks, so it works for nonlinear objectives such as MMMU·(1 − WER):

1. find any composition not dominated by a front point found so far;
2. while some composition dominates it, move to that one;
3. it is Pareto-optimal: record it, and from then on require every answer to be strictly
   better than it in at least one objective.

Every recorded point is replayed by the independent validator, which recomputes its
objective values exactly.  ``max_points``/``timeout`` bound fronts that are infinite
(continuous θ) or large; the result says whether the front is complete.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from fractions import Fraction

from catc import ir
from catc.semantics.compositions import canonical_fresh
from catc.semantics.horizon import default_horizon
from catc.semantics.plan import Plan
from catc.semantics.validate import ValidationFailure
from catc.smt.backend import DEFAULT_BACKEND, Check, open_backend
from catc.smt.encoder import Encoder
from catc.smt.readback import read_plan
from catc.smt.terms import App, and_, better, or_


@dataclass
class ParetoPoint:
    values: tuple[Fraction, ...]
    plan: Plan
    states: tuple = ()


@dataclass
class ParetoResult:
    status: str  # "front" | "unsat" | "unknown"
    objectives: list[ir.Objective]
    points: list[ParetoPoint] = field(default_factory=list)
    complete: bool = True
    horizon: int = 0
    checks: int = 0
    timings: dict[str, float] = field(default_factory=dict)


def pareto(
    inst: ir.Instance,
    objectives: list[ir.Objective] | None = None,
    *,
    horizon: int | None = None,
    sequential: bool = False,
    max_points: int = 100,
    timeout: float | None = None,
) -> ParetoResult:
    from catc.semantics.validate import objective_value, validate

    if objectives is None:
        metric = inst.problem.metric
        objectives = list(metric.objectives) if metric else []
    if len(objectives) < 2:
        raise ValueError("a Pareto front needs at least two objectives")
    start = time.perf_counter()
    deadline = start + timeout if timeout else None
    k = default_horizon(inst) if horizon is None else horizon
    enc = Encoder(inst, k, sequential=sequential)
    enc.unroll(k)
    texts = [enc.objective(o.term, k) for o in objectives]
    solver = open_backend(DEFAULT_BACKEND)
    solver.add(*enc.script.take())
    terms = [solver.intern(t) for t in texts]
    result = ParetoResult("unknown", objectives, horizon=k)
    result.timings["encode"] = time.perf_counter() - start
    minimizing = [o.sense is ir.Sense.MINIMIZE for o in objectives]

    def as_good(values: tuple[Fraction, ...]) -> App:
        """At least as good as ``values`` in every objective."""
        return and_(*[better(t, v, m, strict=False) for t, v, m in zip(terms, values, minimizing)])

    def improving(values: tuple[Fraction, ...]) -> App:
        """Strictly better than ``values`` in some objective."""
        return or_(*[better(t, v, m) for t, v, m in zip(terms, values, minimizing)])

    def check() -> Check:
        if deadline is not None:
            solver.set_timeout(max(0.001, deadline - time.perf_counter()))
        result.checks += 1
        return solver.check()

    def values_now() -> tuple[Fraction, ...]:
        out = []
        for t in terms:
            v = solver.value(t)
            assert not isinstance(v, bool)
            out.append(v)
        return tuple(out)

    while len(result.points) < max_points:
        r = check()
        if r is Check.UNSAT:
            break
        if r is Check.UNKNOWN:
            result.complete = False
            break
        values = values_now()
        plan = read_plan(solver, enc, k)
        # Improve until nothing dominates it.
        while True:
            solver.push()
            solver.assert_term(as_good(values))  # a point that dominates this one
            solver.assert_term(improving(values))
            r = check()
            if r is Check.SAT:
                values = values_now()
                plan = read_plan(solver, enc, k)
                solver.pop()
                continue
            solver.pop()
            if r is Check.UNKNOWN:
                result.complete = False
            break
        if not result.complete:
            break
        report = validate(inst, plan, horizon=k, sequential=sequential)
        if not report.ok:
            raise ValidationFailure(
                "the independent validator rejected a Pareto point: "
                + "; ".join(v.message for v in report.violations[:5])
            )
        recomputed = tuple(objective_value(inst, plan, o.term, report.states[-1]) for o in objectives)
        if recomputed != values:
            raise ValidationFailure(f"Pareto point values {values} differ from the composition's {recomputed}")
        result.points.append(ParetoPoint(values, canonical_fresh(plan), report.states))
        # Every later answer must be strictly better than this point in some objective.
        solver.assert_term(improving(values))
    else:
        result.complete = False
    if result.points:
        result.status = "front"
    elif result.complete:
        result.status = "unsat"
    result.points.sort(key=lambda p: p.values)
    result.timings["total"] = time.perf_counter() - start
    return result


def dominates(a: tuple, b: tuple, objectives: list[ir.Objective]) -> bool:
    """a is at least as good as b everywhere and strictly better somewhere."""
    at_least, strictly = True, False
    for x, y, o in zip(a, b, objectives):
        good, strict = (x <= y, x < y) if o.sense is ir.Sense.MINIMIZE else (x >= y, x > y)
        at_least &= good
        strictly |= strict
    return at_least and strictly


# ---------------------------------------------------------------- pictures


def ascii_plot(result: ParetoResult, labels: list[str], width: int = 56, height: int = 14) -> str:
    """The front on the first two objectives, as text (no plotting library needed)."""
    xs = [float(p.values[0]) for p in result.points]
    ys = [float(p.values[1]) for p in result.points]
    if not xs:
        return ""
    x0, x1 = min(xs), max(xs)
    y0, y1 = min(ys), max(ys)
    grid = [[" "] * width for _ in range(height)]
    for n, (x, y) in enumerate(zip(xs, ys), 1):
        col = 0 if x1 == x0 else round((x - x0) / (x1 - x0) * (width - 1))
        row = 0 if y1 == y0 else round((y - y0) / (y1 - y0) * (height - 1))
        mark = str(n) if n < 10 else "*"
        grid[height - 1 - row][col] = mark if grid[height - 1 - row][col] == " " else "*"
    y_hi, y_lo = f"{y1:.4g}", f"{y0:.4g}"
    pad = max(len(y_hi), len(y_lo))
    lines = [f"{labels[1]} ↑"]
    for i, row in enumerate(grid):
        tick = y_hi if i == 0 else y_lo if i == height - 1 else ""
        lines.append(f"{tick.rjust(pad)} |{''.join(row)}")
    lines.append(" " * pad + " +" + "-" * width)
    left, right = f"{x0:.4g}", f"{x1:.4g}"
    lines.append(" " * (pad + 2) + left + " " * max(1, width - len(left) - len(right)) + right)
    lines.append(" " * (pad + 2) + f"{labels[0]} →   (digits: point numbers in the table; * several)")
    return "\n".join(lines)


def plot(result: ParetoResult, labels: list[str], path: str) -> None:
    """PNG or SVG via matplotlib (the optional 'plots' extra)."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise RuntimeError("--plot needs matplotlib: pip install 'catc-lang[plots]'") from exc
    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=120)
    xs = [float(p.values[0]) for p in result.points]
    ys = [float(p.values[1]) for p in result.points]
    extra = len(result.objectives) > 2
    colours = [float(p.values[2]) for p in result.points] if extra else None
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
    ax.set_title(f"Pareto front: {len(result.points)} non-dominated compositions")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
