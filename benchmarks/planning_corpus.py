"""Planning tasks of growing plan length, catc beside ENHSP, every plan checked by UP's validator.

    python benchmarks/planning_corpus.py [--timeout 60] [--only NAME ...] [--smt] [--no-enhsp] [--no-catc] [--second]

Families, written here by their textbook definitions (IPC encodings, sizes chosen for plan
lengths from ~5 to ~50; the optimal lengths argued by hand in each generator):

* gripper-n (classical, untyped IPC encoding): n balls from room a to room b with two grippers;
  optimal 6·⌈n/2⌉ − 1 for even n (pick, pick, move, drop, drop, move back per pair, no last move).
* ferry-n (classical, untyped IPC encoding, the one UP 1.3's grounder crashed on): n cars from
  l0 to l1 with a one-car ferry: board, sail, debark, sail back per car, 4n − 1.
* blocks-n (classical, 4-operator IPC encoding): reverse a tower of n blocks; every block moves
  once, two actions each: 2n.
* counters-n (numeric, IPC 2023 counters, UP's wheel domain): n counters from 0 ending strictly
  increasing: n(n − 1)/2 increments.
* farmland-n (numeric, IPC 2023 farmland's actions on a line of n farms, n workers on f0, one
  needed on every farm): n(n − 1)/2 move-slow steps (:func:`farmland`).
* sailing-far-q (numeric, UP's sailing domain, IPC 2023): persons 3q and 3q − 6 away, 2q + 2
  (:func:`sailing_far`).
* unsolvable tasks: blocks-cycle-n (a cyclic goal: relaxed reachability cannot refute it, the
  reachable states can), counters-tight-n (max_int = n − 2: n strictly increasing values do not
  fit; the relaxation cannot tell), farmland-short-n (n − 1 workers for n farms).

* rover-k (numeric, IPC 2023 rover's actions on a line of k + 1 waypoints, soil and rock at
  the far end, energy 40): 2k + 4 + ⌈(16k − 32)/20⌉ (:func:`rover`).
* hydropower-T-u (numeric, IPC 2023 hydropower's actions, T hours on a demand curve of our
  own, profit 8u): T − 1 + 2u (:func:`hydropower`).

For each task: ``catc import pddl`` (timed), ``catc solve --sequential --strategy search`` (forward
greedy search on a numeric h_add taking turns with A*, whose admissible heuristic is the largest
of numeric h^max, a goal-achiever bound and an operator-counting bound; once the greedy search
has a plan, A* goes on below its length: a shortest plan proven, or the greedy plan marked not
proven shortest when the time runs out; exact; the SMT search where it does not apply),
optionally the SMT search
alone (``--smt``), ENHSP ``-planner opt-hrmax`` (A* with h^max: optimal, the like-for-like
baseline) in its own process under the same timeout; both plans replayed by unified-planning's
``SequentialPlanValidator`` on the original PDDL. Prints a markdown table and the command.

The generators, the runner and the table live in :mod:`catc.bench.planning` (``catc bench
--corpus planning`` prints the same table); this script is their command line, as before.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT / "compiler"), str(ROOT / "runtime"), str(ROOT)]

# the names other scripts and tests read from this file (tasks, Task, the generators, _pddl_steps, corpus)
from catc.bench import corpus  # noqa: E402,F401
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
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
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
