"""unified-planning's own example problems through catc's UP engine (issue 14).

    python benchmarks/up_examples.py [--timeout 30] [--markdown]

Every problem of ``unified_planning.test.examples.get_example_problems()`` goes to
``OneshotPlanner(name="catc")``. A problem outside catc's declared ``ProblemKind`` is refused by
kind (``engine.supports(kind)`` is false; the reasons are catc's import report); the others
are solved with ``--timeout`` seconds each, and every plan is checked by UP's own
``sequential_plan_validator``. The table gives each problem's answer, its time, the plan's
length, the validator's verdict, and the metric's value beside the optimum the example records.
A problem that runs out of time counts as ``timeout``, not as a failure; a failure is a
crash, a plan UP's validator rejects, an unsolvable answer to a problem with a recorded valid
plan, or an optimum claimed that differs from the recorded one. Needs the ``up`` extra.
"""

from __future__ import annotations

import argparse
import sys
import time
from fractions import Fraction
from typing import Any

TEMPORAL = ("CONTINUOUS_TIME", "DISCRETE_TIME")


def _row(name: str, ex: Any, timeout: float) -> tuple[str, list[str]]:
    from unified_planning.engines import PlanGenerationResultStatus as Status
    from unified_planning.engines import ValidationResultStatus
    from unified_planning.shortcuts import OneshotPlanner, PlanValidator

    from catc.frontend.up_import import refusals

    p = ex.problem
    temporal = "yes" if any(f in p.kind.features for f in TEMPORAL) else "no"
    with OneshotPlanner(name="catc") as planner:
        if not planner.supports(p.kind):
            why = ", ".join(f for f, _ in refusals(p.kind))
            return "refused", [name, temporal, "refused by kind", "", "", "", why]
        t0 = time.perf_counter()
        try:
            r = planner.solve(p, timeout=timeout)
        except Exception as exc:  # reported, counted as a failure
            return "failed", [name, temporal, f"crash: {exc!r}", "", "", "", ""]
        seconds = f"{time.perf_counter() - t0:.2f}"
    if r.status is Status.TIMEOUT:
        return "timeout", [name, temporal, "timeout", seconds, "", "", ""]
    if r.plan is None:
        return "failed", [name, temporal, r.status.name, seconds, "", "", "the example records a valid plan"]
    with PlanValidator(name="sequential_plan_validator") as v:
        check = v.validate(p, r.plan)
    valid = check.status is ValidationResultStatus.VALID
    value = ""
    verdict = "solved" if valid else "failed"
    if check.metric_evaluations:
        got = Fraction(str(next(iter(check.metric_evaluations.values()))))
        value = str(got)
        if ex.optimum is not None:
            value += f" (recorded optimum {ex.optimum})"
            if r.status is Status.SOLVED_OPTIMALLY and got != Fraction(str(ex.optimum)):
                verdict = "failed"
    return verdict, [
        name,
        temporal,
        r.status.name,
        seconds,
        str(len(r.plan.actions)),
        "valid" if valid else "INVALID",
        value,
    ]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--timeout", type=float, default=30.0, help="seconds per problem (default 30)")
    ap.add_argument("--markdown", action="store_true", help="a Markdown table (as in docs/interop.md)")
    args = ap.parse_args(argv)
    from unified_planning.shortcuts import get_environment
    from unified_planning.test.examples import get_example_problems

    env = get_environment()
    env.credits_stream = None
    if "catc" not in env.factory.engines:
        env.factory.add_engine("catc", "catc.interfaces.up_engine", "CatcEngine")
    counts: dict[str, int] = {"solved": 0, "refused": 0, "timeout": 0, "failed": 0}
    head = ["problem", "temporal", "answer", "seconds", "actions", "UP validator", "metric / why refused"]
    rows = []
    for name, ex in get_example_problems().items():
        verdict, row = _row(name, ex, args.timeout)
        counts[verdict] += 1
        rows.append(row)
    if args.markdown:
        print("| " + " | ".join(head) + " |")
        print("|" + "---|" * len(head))
        for row in rows:
            print("| " + " | ".join(row) + " |")
    else:
        widths = [max(len(r[i]) for r in [head, *rows]) for i in range(len(head))]
        for row in [head, *rows]:
            print("  ".join(c.ljust(w) for c, w in zip(row, widths, strict=True)).rstrip())
    print()
    print(", ".join(f"{k} {v}" for k, v in counts.items()) + f" (of {len(rows)})")
    return 1 if counts["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
