"""Planning tasks of growing plan length, catc beside ENHSP, every plan checked by UP's validator.

    python benchmarks/planning_corpus.py [--timeout 60] [--only NAME ...] [--smt] [--no-enhsp] [--no-catc] [--second]

The families, their hand-counted shortest lengths, the runner and the table live in
:mod:`catc.bench.planning` (``catc bench --corpus planning`` prints the same table; ``--help``
shows its description); this script is their command line, as before.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT / "compiler"), str(ROOT / "runtime"), str(ROOT)]

# the names other scripts and tests read from this file (tasks, Task, the generators, _pddl_steps, corpus)
from catc.bench import corpus, planning  # noqa: E402,F401
from catc.bench.planning import (  # noqa: E402,F401
    BLOCKS,
    FARMLAND,
    FERRY,
    GRIPPER,
    HYDROPOWER,
    ROVER,
    Row,
    Task,
    _children_cpu,
    _pddl_steps,
    _second,
    _second_child,
    _t,
    _v,
    blocks,
    counters_tight,
    farmland,
    ferry,
    gripper,
    hydropower,
    markdown,
    medians,
    progress,
    rover,
    rover_optimal,
    run,
    run_tasks,
    sailing_far,
    select,
    tasks,
)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0] + "\n\n" + planning.__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--horizon", type=int, default=200)
    ap.add_argument("--only", action="append", default=[])
    ap.add_argument("--smt", action="store_true", help="also the SMT search alone (slow past ~12 actions)")
    ap.add_argument("--no-enhsp", action="store_true")
    ap.add_argument(
        "--no-catc", action="store_true", help="leave catc's search out (e.g. to run only the second planner)"
    )
    ap.add_argument(
        "--second", action="store_true", help="also pyperplan A*/LM-cut (classical) or TAMER (numeric), if installed"
    )
    ap.add_argument("--child", nargs=3, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        return _second_child(*args.child)
    rows = run_tasks(
        select(args.only),
        args.timeout,
        smt=args.smt,
        enhsp=not args.no_enhsp,
        horizon=args.horizon,
        second=args.second,
        catc=not args.no_catc,
        log=lambda line: print(line, file=sys.stderr, flush=True),
    )
    print(
        markdown(rows, "python benchmarks/planning_corpus.py " + " ".join(argv or sys.argv[1:]), args.smt, args.second)
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
