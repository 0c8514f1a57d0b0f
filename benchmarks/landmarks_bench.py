"""The forward search's A* with and without the counting-plus-landmarks bound
(:mod:`catc.semantics.search.landmarks`), side by side on tasks of benchmarks/planning_corpus.py.

    python benchmarks/landmarks_bench.py [--timeout 60] [--only NAME ...]

For each task: the PDDL imported once (unified-planning, as planning_corpus.py does), then
:func:`catc.semantics.search.search` (greedy search taking turns with A*, as ``catc solve
--strategy search``) run twice in this process, without the bound and with it: CPU seconds,
states expanded, the plan's length and whether it is proven shortest, and the heuristic's
value at the initial state (A*'s h: the largest of h^max, the achiever bound, the counting
bound and, with it, the landmark bound). Every plan is replayed by UP's validator."""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

DEFAULT = [
    "rover-10",
    "rover-14",
    "rover-16",
    "hydropower-16-4",
    "hydropower-24-4",
    "hydropower-30-5",
    "hydropower-36-6",
    "gripper-12",
    "farmland-10",
    "sailing-far-19",
    "counters-10",
]


def _h0(inst, horizon: int, landmarks: bool) -> str:
    """A*'s heuristic at the initial state, as :func:`catc.semantics.search.search` builds it
    ("strips": a classical task, searched on bitmasks without the numeric bounds)."""
    import catc.semantics.search.landmarks as lm
    from catc.semantics import search as se

    try:
        se._Strips(inst)
        return "strips"
    except se._Unsupported:
        pass
    folded = se._inline_statics(inst)
    task = se._Task(folded)
    atoms = se._Atoms(task, folded)
    task.counting = se._Counting.build(task, atoms, folded)
    task.landmarks = lm.LandmarkCounting.build(task, atoms, folded) if landmarks else None
    return str(task.h(task.init, horizon + 1))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--horizon", type=int, default=200)
    ap.add_argument("--only", action="append", default=[])
    args = ap.parse_args(argv)
    import planning_corpus as pc  # type: ignore[import-not-found]
    from unified_planning.io import PDDLReader

    from catc.frontend.up_import import up_to_instance
    from catc.semantics import search as se

    names = args.only or DEFAULT
    tasks = [t for t in pc.tasks() if t.name in names]
    print(
        "| task | optimum | h₀ without | h₀ with | plan without (proven) | plan with (proven) | cpu s without | cpu s with | expanded without | expanded with | valid |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as work:
        for t in tasks:
            d, p = Path(work) / f"{t.name}-domain.pddl", Path(work) / f"{t.name}.pddl"
            d.write_text(t.domain)
            p.write_text(t.problem)
            up_problem = PDDLReader().parse_problem(str(d), str(p))
            inst, report = up_to_instance(up_problem, timeout=args.timeout)
            cells: dict[str, list[str]] = {"h": [], "plan": [], "cpu": [], "exp": []}
            valid = []
            for enabled in (False, True):
                cells["h"].append(_h0(inst, args.horizon, enabled))
                c0 = time.process_time()
                r = se.search(inst, args.horizon, deadline=time.monotonic() + args.timeout, landmarks=enabled)
                cells["cpu"].append(f"{time.process_time() - c0:.1f}")
                cells["exp"].append(str(r.expanded))
                if r.plan is None:
                    cells["plan"].append(r.status.value)
                    continue
                cells["plan"].append(f"{len(r.plan.steps)} ({'yes' if r.shortest else 'NO'})")
                steps = pc._pddl_steps(r.plan, report)
                valid.append(pc.corpus.up_validates(up_problem, steps))
            h, plan, cpu, exp = cells["h"], cells["plan"], cells["cpu"], cells["exp"]
            ok = "-" if not valid else "yes" if all(valid) else "NO"
            print(
                f"| {t.name} | {t.optimal} | {h[0]} | {h[1]} | {plan[0]} | {plan[1]} | {cpu[0]} | {cpu[1]} | {exp[0]} | {exp[1]} | {ok} |",
                flush=True,
            )
    print(
        f"\n    python benchmarks/landmarks_bench.py --timeout {args.timeout:g}"
        + "".join(f" --only {n}" for n in args.only)
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
