"""The SMT route's step encodings on the planning corpus (issue 27): sequential steps, ∀-step
parallel steps (catc's non-interference rules) and ∃-step parallel steps (R²∃: a fixed order
within a step, each precondition read on the state the step's earlier activations left).

    python benchmarks/step_encodings.py [--timeout 20] [--only NAME ...]

For each task of ``benchmarks/planning_corpus.py`` (its generators; ``--only`` picks some):
``solve(strategy="incremental")`` in each mode under the same timeout, printing the status,
the horizon reached (horizons checked), the plan length (∃-step: its linearisation, one
activation per step), the wall time, and whether UP's sequential plan validator accepts the
plan on the original PDDL (∀-step plans linearised in the step's order: catc's
non-interference makes any order run alike; UP's semantics may still differ, so a ∀-step
"no" is reported, not hidden). Prints a markdown table and the command.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "compiler"), str(ROOT / "runtime"), str(ROOT), str(ROOT / "benchmarks")]

MODES = ("sequential", "forall", "exists")
DEFAULT_ONLY = (
    "gripper-2",
    "gripper-4",
    "ferry-2",
    "blocks-3",
    "blocks-4",
    "counters-4",
    "counters-5",
    "counters-6",
    "farmland-4",
    "farmland-5",
    "sailing-far-2",
    "sailing-far-4",
    "blocks-cycle-3",
    "counters-tight-3",
    "farmland-short-4",
)


def run_mode(inst, report, up_problem, mode: str, timeout: float, horizon: int) -> dict:
    from planning_corpus import _pddl_steps

    from catc.bench import corpus
    from catc.queries.solve import solve

    t0 = time.perf_counter()
    r = solve(
        inst,
        horizon=horizon,
        sequential=mode != "forall",
        exists_step=mode == "exists",
        strategy="incremental",
        timeout=timeout,
    )
    wall = time.perf_counter() - t0
    out = {"status": r.status.value + (" (final)" if r.final else ""), "h": r.horizons_tried, "wall": wall}
    if r.plan is not None:
        steps = _pddl_steps(r.plan, report)
        out["len"] = len(steps)
        out["steps"] = len(r.plan) if mode != "exists" else r.horizons_tried - 1
        out["valid"] = corpus.up_validates(up_problem, steps)
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--timeout", type=float, default=20.0)
    ap.add_argument("--horizon", type=int, default=200)
    ap.add_argument("--only", nargs="*", default=list(DEFAULT_ONLY))
    args = ap.parse_args(argv)
    from planning_corpus import tasks
    from unified_planning.io import PDDLReader
    from unified_planning.shortcuts import get_environment

    from catc.frontend.up_import import up_to_instance

    get_environment().credits_stream = None
    chosen = [t for t in tasks() if not args.only or t.name in args.only]
    print("| task | optimal | " + " | ".join(f"{m}: status, horizons, length, s, UP" for m in MODES) + " |")
    print("|---|---|" + "---|" * len(MODES))
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for task in chosen:
            d, p = work / f"{task.name}-domain.pddl", work / f"{task.name}.pddl"
            d.write_text(task.domain)
            p.write_text(task.problem)
            up_problem = PDDLReader().parse_problem(str(d), str(p))
            inst, report = up_to_instance(up_problem, timeout=args.timeout)
            cells = []
            for mode in MODES:
                o = run_mode(inst, report, up_problem, mode, args.timeout, args.horizon)
                valid = "-" if "valid" not in o else ("yes" if o["valid"] else "NO")
                length = o.get("len", "-")
                cells.append(f"{o['status']}, {o['h']}, {length}, {o['wall']:.2f}, {valid}")
            opt = "unsolvable" if task.optimal is None else str(task.optimal)
            print(f"| {task.name} | {opt} | " + " | ".join(cells) + " |", flush=True)
    print()
    print(
        f"`python benchmarks/step_encodings.py --timeout {args.timeout:g}" + (" --only ..." if args.only else "") + "`"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
