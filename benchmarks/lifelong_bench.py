"""The lifelong queries on the search-and-rescue model, before and after issue 16, side by side
in one run, and the budget cut's UNSAT proof against ENHSP's.

    python benchmarks/lifelong_bench.py [--runs 5] [--timeout 300] [--no-enhsp]

In process (process start excluded; each query on the loaded model, median of ``--runs``):
every query with the issue's machinery and without it — ``presolve=False`` (no relaxed
reachability) for solve and diagnose, ``counting=False`` for relax, and for recompose the
counting proof of optimality switched off (``Tactics(counting_proofs=False)``).  As
processes (wall, median): ``catc solve`` on the budget cut against ENHSP ``sat-hadd`` on the
exported PDDL, interleaved.  Answers are checked against examples/search-and-rescue/expect.toml.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from fractions import Fraction
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SAR = ROOT / "examples" / "search-and-rescue"


def cases(timeout: float) -> list[tuple[str, Callable[[bool], object], Callable[[object], str]]]:
    from catc.api import load
    from catc.queries.diagnose import diagnose
    from catc.queries.optimize import Tactics
    from catc.queries.recompose import recompose
    from catc.queries.relax import relax
    from catc.queries.solve import solve

    cut = load(SAR / "domain.cat", SAR / "budget-cut.cat").instance
    cheaper = load(SAR / "domain.cat", SAR / "cheaper-camera.cat").instance

    def rec(priority: str) -> Callable[[bool], object]:
        def run(new: bool) -> object:
            return recompose(cheaper, priority=priority, timeout=timeout, tactics=Tactics(counting_proofs=new))

        return run

    return [
        ("solve, budget cut (UNSAT)", lambda new: solve(cut, presolve=new, timeout=timeout), _solve),
        ("diagnose, budget cut", lambda new: diagnose(cut, presolve=new, timeout=timeout), _diagnose),
        ("relax, budget cut", lambda new: relax(cut, counting=new, timeout=timeout), _relax),
        ("recompose stability-first, cheaper camera", rec("stability"), _recompose),
        ("recompose objective-first, cheaper camera", rec("objective"), _recompose),
    ]


def _solve(r: object) -> str:
    return f"{r.status.value}{' (final)' if r.final else ''}"  # type: ignore[attr-defined]


def _diagnose(r: object) -> str:
    cores = r.cores  # type: ignore[attr-defined]
    assert not cores or sorted(cores[0]) == ["init/budget", "pre/mount-lidar/1"], cores
    return f"core of {len(cores[0])} of {r.total}" if cores else r.status.value  # type: ignore[attr-defined]


def _relax(r: object) -> str:
    got = {x.label: x.delta for x in r.relaxations}  # type: ignore[attr-defined]
    assert not got or got == {"init/budget": Fraction(19860)}, got
    return f"{r.status.value}, {'proven' if r.proven else 'NOT proven'}"  # type: ignore[attr-defined]


def _recompose(r: object) -> str:
    return f"{r.status.value}, churn {r.churn}"  # type: ignore[attr-defined]


def timed(run: Callable[[], object], runs: int) -> tuple[float, object]:
    walls, out = [], None
    for _ in range(runs):
        start = time.perf_counter()
        out = run()
        walls.append(time.perf_counter() - start)
    return statistics.median(walls), out


def in_process(runs: int, timeout: float, skip: list[str]) -> None:
    print("| query (search-and-rescue) | before issue 16 (s) | answer | now (s) | answer | ratio |")
    print("|---|---:|---|---:|---|---:|")
    for name, run, show in cases(timeout):
        if any(word in name for word in skip):
            continue
        old_runs = 1 if "objective" in name or "relax" in name else runs  # the slow ones: once
        before, old = timed(lambda run=run: run(False), old_runs)
        now, new = timed(lambda run=run: run(True), 1 if "objective" in name else runs)
        print(f"| {name} | {before:.3f} | {show(old)} | {now:.3f} | {show(new)} | {before / now:.1f}× |", flush=True)
    print()


def against_enhsp(runs: int) -> None:
    from catc.api import load
    from catc.bench.problems import GRID_SAR
    from catc.targets.enhsp import run_enhsp
    from catc.targets.pddl import export_pddl

    export = export_pddl(load(SAR / "domain.cat", SAR / "budget-cut.cat").instance, grid=GRID_SAR)
    with tempfile.TemporaryDirectory() as tmp:
        dom, prob = Path(tmp) / "domain.pddl", Path(tmp) / "problem.pddl"
        dom.write_text(export.domain)
        prob.write_text(export.problem)
        catc_cmd = [sys.executable, "-m", "catc", "solve", str(SAR / "domain.cat"), str(SAR / "budget-cut.cat")]
        ours, theirs, answer = [], [], None
        for _ in range(runs):  # interleaved
            start = time.perf_counter()
            proc = subprocess.run(catc_cmd, capture_output=True, text=True)
            ours.append(time.perf_counter() - start)
            assert proc.returncode == 1, proc.stdout  # UNSAT
            res = run_enhsp(dom, prob, planner="sat-hadd", timeout=300)
            theirs.append(res.wall)
            answer = res.status
    a, b = statistics.median(ours), statistics.median(theirs)
    print(f"ENHSP on the PDDL export with catc bench's grid ({', '.join(f'{k}={v}' for k, v in GRID_SAR.items())}).\n")
    print("| budget cut, UNSAT proof (wall, process) | catc solve (s) | ENHSP sat-hadd (s) | ratio |")
    print("|---|---:|---:|---:|")
    print(f"| search-and-rescue/budget-cut.cat | {a:.3f} | {b:.3f} ({answer}) | {a / b:.2f}× |")
    print()


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--timeout", type=float, default=300.0)
    ap.add_argument("--no-enhsp", action="store_true")
    ap.add_argument("--skip", action="append", default=[], help="skip the queries whose name contains this")
    args = ap.parse_args()
    print(f"`python benchmarks/lifelong_bench.py {' '.join(sys.argv[1:])}`\n")
    in_process(args.runs, args.timeout, args.skip)
    if not args.no_enhsp:
        against_enhsp(args.runs)
    return 0


if __name__ == "__main__":
    sys.exit(main())
