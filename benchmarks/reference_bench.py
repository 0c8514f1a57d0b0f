"""`catc optimize` and `catc solve` against hand-written Z3 scripts answering the same
question, as whole processes (the target: every query ≤ 1.3× such a script).

    python benchmarks/reference_bench.py [--runs N] [--no-compile]

Pairs (catc command line vs the script in benchmarks/reference/):

* ``catc optimize examples/gpu-allocation/max-confidence.cat`` vs ``gpu_z3.py``
* ``catc optimize examples/navigation/farthest.cat`` vs ``navigation_z3.py``
* ``catc solve examples/detection/person.cat`` vs ``detection_z3.py``

plus ``python -c 'import z3'`` as the floor of any of them.  catc is run as
``python -m catc ...``, which enters :func:`catc.interfaces.entry.main` exactly as the
installed ``catc`` console script does (the fast route: no click import for these command
lines).  Every command runs once untimed (warm caches), then all of them run interleaved,
``--runs`` rounds; the table gives each one's median and interquartile range.  Every answer
is checked against the example's ``expect.toml``: catc's ``--json`` optimum (or status,
steps and components for solve) and the script's printed optimum (or composition).
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
import tomllib
from fractions import Fraction
from pathlib import Path

from solve_bench import compile_catc  # benchmarks/ is on sys.path when run as a script

from catc.bench.machine import cpu_text
from catc.bench.stats import quartiles

ROOT = Path(__file__).resolve().parent.parent
CATC = [sys.executable, "-m", "catc"]
PY = sys.executable

#: (question, catc query, example, reference script)
PAIRS = [
    ("optimize gpu-allocation/max-confidence", "optimize", "examples/gpu-allocation/max-confidence.cat", "gpu_z3.py"),
    ("optimize navigation/farthest", "optimize", "examples/navigation/farthest.cat", "navigation_z3.py"),
    ("solve detection/person", "solve", "examples/detection/person.cat", "detection_z3.py"),
]
FLOOR = "python -c 'import z3'"


def expectation(example: str) -> dict:
    path = ROOT / example
    for case in tomllib.loads((path.parent / "expect.toml").read_text())["case"]:
        if case["file"] == path.name:
            return case
    raise SystemExit(f"no case for {example} in its expect.toml")


def check_catc(label: str, out: str, case: dict) -> None:
    doc = json.loads(out)
    steps = doc["steps"]
    used = {m["morphism"] for step in steps for m in step}
    if "optimum" in case:
        got = [Fraction(o["value"]) for o in doc["objectives"]]
        want = [Fraction(v) for v in case["optimum"]]
        ok = doc["status"] == "opt" and got == want
    else:
        ok = doc["status"] == case["status"]
    ok = ok and ("steps" not in case or len(steps) == case["steps"])
    ok = ok and ("uses" not in case or used == set(case["uses"]))
    if not ok:
        raise SystemExit(f"catc's answer to {label} does not match expect.toml:\n{out}")


def check_script(label: str, out: str, case: dict) -> None:
    lines = out.splitlines()
    if "optimum" in case:
        found = [line.split()[1:] for line in lines if line.startswith("optimum ")]
        ok = bool(found) and [Fraction(v) for v in found[0]] == [Fraction(v) for v in case["optimum"]]
    else:  # a composition printed one step a line: "t name name ..."
        used = {name for line in lines if line[:1].isdigit() for name in line.split()[1:]}
        ok = "unsat" not in lines and used == set(case.get("uses", used))
    if not ok:
        raise SystemExit(f"the script's answer to {label} does not match expect.toml:\n{out}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=21)
    ap.add_argument(
        "--no-compile",
        action="store_true",
        help="do not byte-compile catc first (by default it is, as `pip install .` does)",
    )
    args = ap.parse_args()
    if not args.no_compile:
        compile_catc()
    print(
        f"command: python benchmarks/reference_bench.py --runs {args.runs}"
        + (" --no-compile" if args.no_compile else "")
    )
    print(f"machine: {cpu_text()}\n")

    commands: dict[str, list[str]] = {}
    for label, query, example, script in PAIRS:
        case = expectation(example)
        catc_cmd = CATC + [query, example, "--json"]
        script_cmd = [PY, f"benchmarks/reference/{script}"]
        # the untimed first run: warms the caches and checks both answers
        for cmd, check in ((catc_cmd, check_catc), (script_cmd, check_script)):
            proc = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
            check(label, proc.stdout, case)
        commands[f"catc {label}"] = catc_cmd
        commands[f"script {label}"] = script_cmd
    commands[FLOOR] = [PY, "-c", "import z3"]
    subprocess.run(commands[FLOOR], cwd=ROOT, check=True)

    times: dict[str, list[float]] = {key: [] for key in commands}
    for _ in range(args.runs):
        for key, cmd in commands.items():
            start = time.perf_counter()
            subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=ROOT, check=True)
            times[key].append(time.perf_counter() - start)

    print(f"All run as processes, interleaved, {args.runs} runs each, bytecode compiled; every answer")
    print("checked against expect.toml.\n")
    print("| question | catc (s, median) | IQR | hand-written (s, median) | IQR | catc / hand-written |")
    print("|---|---:|---|---:|---|---:|")
    worst = 0.0
    for label, *_ in PAIRS:
        c, c_lo, c_hi = quartiles(times[f"catc {label}"])
        s, s_lo, s_hi = quartiles(times[f"script {label}"])
        worst = max(worst, c / s)
        print(f"| {label} | {c:.3f} | {c_lo:.3f}–{c_hi:.3f} | {s:.3f} | {s_lo:.3f}–{s_hi:.3f} | {c / s:.2f}× |")
    f, f_lo, f_hi = quartiles(times[FLOOR])
    print(f"| floor: `{FLOOR}` | | | {f:.3f} | {f_lo:.3f}–{f_hi:.3f} | |")
    print(f"\nLargest catc / hand-written: {worst:.2f}× (target ≤ 1.3×: {'met' if worst <= 1.3 else 'not met'}).")
    print(f"Median of the floor: {statistics.median(times[FLOOR]):.3f} s.")


if __name__ == "__main__":
    main()
