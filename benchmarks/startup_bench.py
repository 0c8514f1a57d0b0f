"""Every query as a whole process against a hand-written Z3 script, side by side in one run
(the target: each ≤ 1.2× its yardstick; docs/benchmarks.md, "Start-up of every query").

    python benchmarks/startup_bench.py [--runs N] [--no-compile] [--against OTHER-CHECKOUT] [--only TEXT]

Each row is one ``catc`` command line, run as ``python -m catc ...`` (which enters
:func:`catc.interfaces.entry.main` as the installed ``catc`` script does), and its yardstick:

* the hand-written script of benchmarks/reference/ answering the same question, where there
  is one (solve on detection, optimize on gpu-allocation and navigation, diagnose and relax
  on lifelong/budget-cut, recompose on lifelong/cheaper-camera, pareto on pareto-design;
  tests/test_reference_scripts.py checks the last two answer as catc does);
* otherwise the least a hand-written Z3 script does at all — ``import z3``, make a solver,
  one ``check()`` — so the ratio is an upper bound of what catc adds to *any* Z3 script
  (a script answering the same question does more than that).

``catc check`` needs no solver and so is measured against the same floor.  All commands
run once untimed (warm caches; every exit code is checked), then interleaved, ``--runs``
rounds.  Wall time (a monotonic clock around the child) and CPU time (the child's user +
system, from ``os.wait4``) are given as medians; the ratio is the median of the per-round
ratios, so a drift of the machine's speed during the run moves both sides of a round alike.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from solve_bench import compile_catc  # benchmarks/ is on sys.path when run as a script

from catc.bench.machine import cpu_text

ROOT = Path(__file__).resolve().parent.parent
PY = sys.executable
CATC = [PY, "-m", "catc"]
FLOOR = "import z3; z3.Solver().check()"

#: (row, catc arguments, expected exit code, hand-written script or None for the floor)
ROWS: list[tuple[str, list[str], int, str | None]] = [
    ("solve detection/person", ["solve", "examples/detection/person.cat", "--json"], 0, "detection_z3.py"),
    (
        "optimize gpu-allocation/max-confidence",
        ["optimize", "examples/gpu-allocation/max-confidence.cat", "--json"],
        0,
        "gpu_z3.py",
    ),
    ("optimize navigation/farthest", ["optimize", "examples/navigation/farthest.cat", "--json"], 0, "navigation_z3.py"),
    (
        "diagnose lifelong/budget-cut",
        ["diagnose", "examples/lifelong/budget-cut.cat", "--json"],
        0,
        "budget_cut_diagnose_z3.py",
    ),
    ("relax lifelong/budget-cut", ["relax", "examples/lifelong/budget-cut.cat", "--json"], 0, "budget_cut_relax_z3.py"),
    (
        "recompose lifelong/cheaper-camera",
        ["recompose", "examples/lifelong/cheaper-camera.cat", "--json"],
        0,
        "cheaper_camera_recompose_z3.py",
    ),
    (
        "pareto pareto-design/design",
        ["pareto", "examples/pareto-design/design.cat", "--json"],
        0,
        "pareto_design_z3.py",
    ),
    ("validate detection/person PLAN", ["validate", "examples/detection/person.cat", "PLAN", "--json"], 0, None),
    ("check detection/person", ["check", "examples/detection/person.cat"], 0, None),
]


def timed(cmd: list[str], env: dict[str, str] | None = None) -> tuple[float, float, int]:
    """Wall seconds, CPU seconds (user + system) and exit code of one run of ``cmd``."""
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=ROOT, env=env)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    proc.returncode = os.waitstatus_to_exitcode(status)
    return wall, usage.ru_utime + usage.ru_stime, proc.returncode


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=21)
    ap.add_argument("--no-compile", action="store_true", help="do not byte-compile catc first")
    ap.add_argument(
        "--against",
        metavar="TREE",
        help="also run each catc command from this other checkout (e.g. the main branch's), interleaved in the "
        "same rounds; it is byte-compiled into a private folder (PYTHONPYCACHEPREFIX), its checkout is not written",
    )
    ap.add_argument(
        "--only",
        metavar="TEXT",
        help="only the rows whose label contains TEXT (e.g. recompose): fewer processes a round on a busy machine",
    )
    args = ap.parse_args()
    rows = [row for row in ROWS if args.only is None or args.only in row[0]]
    if not rows:
        raise SystemExit(f"no row's label contains {args.only!r}")
    if not args.no_compile:
        compile_catc()  # this tree; the other one below, into a folder of its own
    print(
        f"command: python benchmarks/startup_bench.py --runs {args.runs}"
        + (" --no-compile" if args.no_compile else "")
        + (f" --against {args.against}" if args.against else "")
        + (f" --only {args.only}" if args.only else "")
    )
    print(f"machine: {cpu_text()}\n")

    with tempfile.TemporaryDirectory() as tmp:
        # each tree its own cache folder (filled by the untimed first run): two trees sharing
        # one would replace each other's standard-library entries, whose keys differ
        trees = {"catc": ROOT, **({"other": Path(args.against).resolve()} if args.against else {})}
        envs = {
            side: {
                **os.environ,
                "CATC_CACHE": str(Path(tmp) / f"cache-{side}"),
                "PYTHONPATH": os.pathsep.join(str(tree / p) for p in ("compiler", "runtime", ".")),
            }
            for side, tree in trees.items()
        }
        if args.against:  # whatever --no-compile says of this tree: its folder is new each run
            # compiled as this tree is, else every module whose source is newer than its
            # __pycache__ entry would be compiled again in each run (PYTHONDONTWRITEBYTECODE)
            # and counted against it; the bytecode goes to a private folder, not its checkout.
            # Every module it imports (z3, the standard library's) is read from that folder
            # then, so the untimed first run may write there
            envs["other"]["PYTHONPYCACHEPREFIX"] = str(Path(tmp) / "pycache-other")
            envs["other"].pop("PYTHONDONTWRITEBYTECODE", None)
            subprocess.run(
                [PY, "-m", "compileall", "-q", "compiler/catc", "catgrammar", "stdlib_domains"],
                cwd=trees["other"],
                env=envs["other"],
                check=False,
                stdout=subprocess.DEVNULL,
            )
        plan = Path(tmp) / "plan.json"
        solved = subprocess.run(
            CATC + ["solve", "examples/detection/person.cat", "--json"],
            capture_output=True,
            text=True,
            cwd=ROOT,
            env=envs["catc"],
        )
        json.loads(solved.stdout)  # a catc.plan/1-compatible answer, or this fails
        plan.write_text(solved.stdout)

        commands: dict[str, tuple[list[str], dict[str, str] | None]] = {}
        for label, words, expected, script in rows:
            catc_cmd = CATC + [str(plan) if w == "PLAN" else w for w in words]
            yard = [PY, f"benchmarks/reference/{script}"] if script else [PY, "-c", FLOOR]
            runs = [(side, catc_cmd, expected, envs[side]) for side in trees] + [("yard", yard, 0, None)]
            for side, cmd, want, env in runs:
                code = subprocess.run(cmd, capture_output=True, cwd=ROOT, env=env).returncode
                if code != want:
                    raise SystemExit(f"{' '.join(cmd)} ({side}) exited {code}, not {want}")
                commands[f"{side} {label}"] = (cmd, env)

        # the floor is one command: run it once a round, shared by the rows that use it
        unique: dict[tuple[str, ...], str] = {}
        for key, (cmd, env) in commands.items():
            unique.setdefault((*cmd, str(sorted(env.items())) if env else ""), key)
        wall: dict[str, list[float]] = {key: [] for key in unique.values()}
        cpu: dict[str, list[float]] = {key: [] for key in unique.values()}
        for _ in range(args.runs):
            for key in unique.values():
                cmd, env = commands[key]
                w, c, _ = timed(cmd, env)
                wall[key].append(w)
                cpu[key].append(c)

    def series(key: str, table: dict[str, list[float]]) -> list[float]:
        cmd, env = commands[key]
        return table[unique[(*cmd, str(sorted(env.items())) if env else "")]]

    other = f" Beside this tree's catc, the catc of {args.against} (other)." if args.against else ""
    print(f"Whole processes, interleaved, {args.runs} rounds, bytecode compiled.  Yardstick: the")
    print(f"hand-written script of benchmarks/reference/, or (*) the floor `python -c '{FLOOR}'`.{other}\n")
    extra_head, extra_rule = (" other wall ratio | other CPU ratio |", "---:|---:|") if args.against else ("", "")
    print(
        "| query | catc wall (s) | yardstick wall (s) | wall ratio | catc CPU (s) | yardstick CPU (s) | CPU ratio |"
        + extra_head
    )
    print("|---|---:|---:|---:|---:|---:|---:|" + extra_rule)

    def ratios(side: str, label: str) -> tuple[float, float]:
        cw, yw = series(f"{side} {label}", wall), series(f"yard {label}", wall)
        cc, yc = series(f"{side} {label}", cpu), series(f"yard {label}", cpu)
        return (
            statistics.median(a / b for a, b in zip(cw, yw)),
            statistics.median(a / b for a, b in zip(cc, yc) if b > 0),
        )

    worst = 0.0
    for label, _, _, script in rows:
        cw, yw = series(f"catc {label}", wall), series(f"yard {label}", wall)
        cc, yc = series(f"catc {label}", cpu), series(f"yard {label}", cpu)
        wr, cr = ratios("catc", label)
        if script:  # the floor rows are upper bounds, not the target's comparison
            worst = max(worst, wr)
        star = "" if script else " (*)"
        extra = " {:.2f}× | {:.2f}× |".format(*ratios("other", label)) if args.against else ""
        print(
            f"| {label}{star} | {statistics.median(cw):.3f} | {statistics.median(yw):.3f} | {wr:.2f}× "
            f"| {statistics.median(cc):.3f} | {statistics.median(yc):.3f} | {cr:.2f}× |" + extra
        )
    print(
        f"\nLargest wall ratio against a hand-written script: {worst:.2f}× "
        f"(target ≤ 1.2×: {'met' if worst <= 1.2 else 'not met'})."
    )


if __name__ == "__main__":
    main()
