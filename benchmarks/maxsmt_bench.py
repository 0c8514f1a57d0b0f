"""Churn as MaxSMT (soft-constraint groups) against churn as an arithmetic sum, side by side
in one run (issue 16, "optimisation proofs").

    python benchmarks/maxsmt_bench.py [--runs 3] [--timeout 60] [--sizes 25,50,100] [--depths 3,6]
                                      [--quick]

Each recomposition runs in this process on the loaded model (process start excluded) with
``Tactics(maxsmt_churn=...)`` (:class:`catc.queries.optimize.Tactics`) on and off, interleaved, ``--runs`` rounds; the table
gives each median and the ratio MaxSMT / sum.  Two groups of rows:

* search-and-rescue ``cheaper-camera.cat``, both priorities, with the counting proof of
  optimality (:mod:`catc.smt.counting`) as shipped and switched off — off, the optimiser itself
  must prove the optimum, which is what the encoding of churn changes;
* generated catalogs (``benchmarks/catalogs.py``'s ``price`` variant made feasible: the budget
  covers the gate), where the deployed provider of the level above the gate has been retired
  (it now needs more CPU than there is), so a recomposition must swap it for another provider:
  minimal churn 2 (one removed, one added; weights 1).  Stability first (churn, then CPU left).

Both encodings must give the same optimum; the script stops on any disagreement and checks the
catalogs' churn against the 2 derived above and SAR's against examples/search-and-rescue's
expect.toml (0 stability-first, 4 objective-first).
"""

from __future__ import annotations

import argparse
import re
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT / "compiler"), str(ROOT / "benchmarks")]

from catalogs import catalog  # noqa: E402


def retired_catalog(n: int, d: int, seed: int = 16) -> str:
    """A feasible catalog whose deployed provider above the gate can no longer run."""
    text, _ = catalog(n, d, "price", seed)
    price = re.search(r"\(>= budget (\d+)\)", text)
    assert price is not None
    text = re.sub(r"\(= budget \d+\)", f"(= budget {int(price.group(1)) + 1})", text)
    level = max(1, d // 2) + 1
    cpu = 4 * n
    name = f"p{level}-0"
    text = text.replace(
        f"(:morphism {name} :kind software :uses 1\n    :precondition (and",
        f"(:morphism {name} :kind software :uses 1\n    :precondition (and (>= cpu {cpu + 1})",
    )
    return text


def cases(
    sizes: list[int], depths: list[int], timeout: float, quick: bool = False
) -> list[tuple[str, Callable[[bool], object], object]]:
    """(label, run(maxsmt), expected churn) for every row."""
    from catc import ir
    from catc.api import load, loads
    from catc.queries.optimize import Tactics
    from catc.queries.recompose import recompose

    sar = ROOT / "examples" / "search-and-rescue"
    cheaper = load(sar / "cheaper-camera.cat", sar / "domain.cat").instance
    out: list[tuple[str, Callable[[bool], object], object]] = []
    for priority, churn in (("stability", 0), ("objective", 4)):

        def shipped(maxsmt: bool, p: str = priority) -> object:
            return recompose(cheaper, priority=p, timeout=timeout, tactics=Tactics(maxsmt_churn=maxsmt))

        def off(maxsmt: bool, p: str = priority) -> object:
            tactics = Tactics(maxsmt_churn=maxsmt, counting_proofs=False)
            return recompose(cheaper, priority=p, timeout=timeout, tactics=tactics)

        out.append((f"SAR {priority}-first", shipped, churn))

        if not quick:  # objective-first without the proof runs into the timeout
            out.append((f"SAR {priority}-first, no counting proof", off, churn))
    cpu_left = [ir.Objective(ir.Sense.MAXIMIZE, ir.ResourceRef("cpu", ir.REAL))]
    for d in depths:
        for n in sizes:
            if n < 2 * d:
                continue
            inst = loads({"catalog.cat": retired_catalog(n, d)}, "catalog.cat").instance

            def run(maxsmt: bool, i: object = inst) -> object:
                tactics = Tactics(maxsmt_churn=maxsmt, counting_proofs=False)
                return recompose(i, priority="stability", objectives=cpu_left, timeout=timeout, tactics=tactics)  # type: ignore[arg-type]

            out.append((f"catalog n={n} d={d}, no counting proof", run, 2))
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--sizes", default="25,50,100")
    ap.add_argument("--depths", default="3,6")
    ap.add_argument("--quick", action="store_true", help="SAR as shipped and one small catalog (a smoke test)")
    args = ap.parse_args(argv)
    if args.quick:
        args.sizes, args.depths = "12", "3"
    sizes, depths = [int(x) for x in args.sizes.split(",")], [int(x) for x in args.depths.split(",")]
    rows = cases(sizes, depths, args.timeout, args.quick)
    times: dict[tuple[str, bool], list[float]] = {}
    answers: dict[tuple[str, bool], str] = {}
    for _ in range(args.runs):
        for label, run, churn in rows:
            for maxsmt in (False, True):
                start = time.perf_counter()
                rec = run(maxsmt)
                wall = time.perf_counter() - start
                status = rec.status.value  # type: ignore[attr-defined]
                got = f"{status} churn {rec.churn}"  # type: ignore[attr-defined]
                if status == "opt" and rec.churn != churn:  # type: ignore[attr-defined]
                    raise SystemExit(f"{label}: churn {rec.churn}, expected {churn}")  # type: ignore[attr-defined]
                if status not in ("opt", "subopt"):
                    raise SystemExit(f"{label}: {status}")
                times.setdefault((label, maxsmt), []).append(wall if status == "opt" else float("inf"))
                answers[(label, maxsmt)] = got
        for label, _, _ in rows:
            a, b = answers[(label, False)], answers[(label, True)]
            if "opt churn" in a and "opt churn" in b and a != b and "subopt" not in a + b:
                raise SystemExit(f"{label}: the encodings disagree: {a} / {b}")
    cmd = "python benchmarks/maxsmt_bench.py " + " ".join(sys.argv[1:] if argv is None else argv)
    print(f"`{cmd.strip()}` — median of {args.runs}, seconds in process; inf = not proven in {args.timeout:g} s\n")
    print("| recomposition | churn as a sum | churn as MaxSMT | ratio | answer |")
    print("|---|---|---|---|---|")
    for label, _, _ in rows:
        a = statistics.median(times[(label, False)])
        b = statistics.median(times[(label, True)])
        ratio = f"{b / a:.2f}×" if a != float("inf") and b != float("inf") else "—"
        print(f"| {label} | {a:.3f} | {b:.3f} | {ratio} | {answers[(label, True)]} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
