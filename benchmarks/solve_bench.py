"""Benchmarks of `catc solve` (issue 3), printed as Markdown tables with the command.

    python benchmarks/solve_bench.py [--runs N] [--quick]

1. Every example end to end (process start to exit), with the share of encoding time.
2. Detection end to end against the hand-written Z3 script benchmarks/reference/detection_z3.py,
   both as processes, interleaved in one run (median and interquartile range).
3. Scaling on synthetic catalogs of 25/50/100/200 components × horizons 5/10/20: wall time
   and peak memory of the process, for both strategies (incremental deepening and one
   encoding with idle steps).
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
import tomllib
from pathlib import Path

from catc.bench.machine import cpu_text as machine  # shared with catc bench
from catc.bench.stats import quartiles

ROOT = Path(__file__).resolve().parent.parent
CATC = [sys.executable, "-m", "catc"]


def peak_rss(cmd: list[str]) -> tuple[float, float, int]:
    """Wall seconds and this process's own peak RSS (MB), via wait4."""
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=ROOT)
    _, status, usage = os.wait4(proc.pid, 0)
    return time.perf_counter() - start, usage.ru_maxrss / 1024, os.waitstatus_to_exitcode(status)


# ---------------------------------------------------------------- 1. examples


def example_cases():
    for expect in sorted((ROOT / "examples").glob("*/expect.toml")):
        for case in tomllib.loads(expect.read_text())["case"]:
            path = (expect.parent / case["file"]).relative_to(ROOT)
            yield str(path), case.get("problem")


def bench_examples(runs: int) -> None:
    print("### Every example end to end\n")
    print("| example | answer | end to end (s) | Z3 start (s) | encode (s) | solve (s) | encode share |")
    print("|---|---|---:|---:|---:|---:|---:|")
    worst = 0.0
    for path, problem in example_cases():
        cmd = CATC + ["solve", path, "--json"] + (["--problem", problem] if problem else [])
        walls, starts, enc, sol = [], [], [], []
        status = "?"
        for _ in range(runs):
            start = time.perf_counter()
            out = subprocess.run(cmd, capture_output=True, cwd=ROOT)
            walls.append(time.perf_counter() - start)
            doc = json.loads(out.stdout)
            status = doc["status"].upper()
            starts.append(doc["timings"]["start"])
            enc.append(doc["timings"]["encode"])
            sol.append(doc["timings"]["solve"])
        w, z, e, s = (statistics.median(xs) for xs in (walls, starts, enc, sol))
        worst = max(worst, e / w)
        name = path.removeprefix("examples/") + (f" ({problem})" if problem else "")
        print(f"| {name} | {status} | {w:.3f} | {z:.4f} | {e:.4f} | {s:.4f} | {100 * e / w:.1f}% |")
    print(f"\nLargest encoding share: {100 * worst:.1f}% (target ≤ 10%).\n")


# ---------------------------------------------------------------- 2. reference


def bench_reference(runs: int) -> None:
    print("### Detection against a hand-written Z3 script (both as processes, interleaved)\n")
    script = "benchmarks/reference/detection_z3.py"
    cases = {
        "catc solve": CATC + ["solve", "examples/detection/person.cat"],
        "hand-written Z3 script": [sys.executable, script],
        # the floor of any click-based command line doing the script's work: click is a core
        # dependency (the guide's list), so its import is part of every catc run
        "the script, importing click first": [sys.executable, "-c", f"import click, runpy; runpy.run_path({script!r})"],
        "python -c 'import z3'": [sys.executable, "-c", "import z3"],
        "python -c 'import z3, click'": [sys.executable, "-c", "import z3, click"],
    }
    times: dict[str, list[float]] = {label: [] for label in cases}
    for _ in range(runs):
        for label, cmd in cases.items():
            start = time.perf_counter()
            subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=ROOT)
            times[label].append(time.perf_counter() - start)
    print("| process | median (s) | IQR (s) |")
    print("|---|---:|---|")
    for label, xs in times.items():
        m, lo, hi = quartiles(xs)
        print(f"| {label} | {m:.3f} | {lo:.3f}–{hi:.3f} |")
    med = {label: statistics.median(xs) for label, xs in times.items()}
    ratio = med["catc solve"] / med["hand-written Z3 script"]
    floor = med["the script, importing click first"] / med["hand-written Z3 script"]
    print(
        f"\ncatc / hand-written: {ratio:.2f}× (target ≤ 1.3×; under 1 s: {med['catc solve'] < 1}); "
        f"the same script importing click: {floor:.2f}×; catc / that: {med['catc solve'] / med['the script, importing click first']:.2f}×.\n"
    )


# ---------------------------------------------------------------- 3. scaling


def synthetic(components: int, horizon: int, depth: int = 4) -> str:
    """A catalog where a chain of `depth` capabilities must be built from many alternative
    components competing for RAM, with a topic θ per activation and distractors."""
    lines = [
        f"(define (domain synthetic-{components})",
        "  (:requirements :numeric :sets :free-parameters)",
        "  (:sorts topic - symbol)",
        "  (:constants " + " ".join(f"t{i}" for i in range(4)) + " - topic)",
        "  (:resources (ram real :bounds (0 *)) (topics (set topic)) "
        + " ".join(f"(cap{i} bool)" for i in range(depth + 1))
        + ")",
    ]
    for i in range(components):
        level = i % depth
        need = f"cap{level}" if level > 0 else "true"
        lines.append(
            f"  (:morphism c{i} :uses 1 :parameters ((out topic) (mem real :bounds (0.5 {2 + i % 3})))\n"
            f"    :precondition (and {need} (>= ram mem) (>= ram {1 + (i * 7) % 5}))\n"
            f"    :effect (and (decrease ram mem) (add topics out) (assign cap{level + 1} true)))"
        )
    lines.append(")")
    lines.append(
        f"(define (problem synthetic-{components}-{horizon}) (:domain synthetic-{components})"
        f" (:init (= ram {8 + components // 10})) (:goal (and cap{depth} (member t3 topics))) (:horizon {horizon}))"
    )
    return "\n".join(lines) + "\n"


def bench_scaling(runs: int, sizes: list[int], horizons: list[int]) -> None:
    print("### Scaling: synthetic catalogs (chain of 4 capabilities, RAM competition, topic θ)\n")
    print("| components | horizon | incremental (s) | peak MB | single encoding (s) | peak MB | answer |")
    print("|---:|---:|---:|---:|---:|---:|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for n in sizes:
            for k in horizons:
                path = Path(tmp) / f"s{n}-{k}.cat"
                path.write_text(synthetic(n, k))
                row = []
                answer = "?"
                for strategy in ("incremental", "single"):
                    walls, peaks = [], []
                    for _ in range(runs):
                        wall, peak, code = peak_rss(CATC + ["solve", str(path), "--strategy", strategy])
                        walls.append(wall)
                        peaks.append(peak)
                        answer = {0: "SAT", 1: "UNSAT", 3: "UNKNOWN"}.get(code, f"exit {code}")
                    row += [f"{statistics.median(walls):.2f}", f"{max(peaks):.0f}"]
                print(f"| {n} | {k} | {row[0]} | {row[1]} | {row[2]} | {row[3]} | {answer} |")
    print()


# ---------------------------------------------------------------- 4. queries


def _median_wall(cmd: list[str], runs: int) -> tuple[float, int]:
    walls, code = [], 0
    for _ in range(runs):
        start = time.perf_counter()
        proc = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=ROOT)
        walls.append(time.perf_counter() - start)
        code = proc.returncode
    return statistics.median(walls), code


def bench_queries(runs: int) -> None:
    print("### Lifelong queries end to end (process start to exit)\n")
    print("| query | example | median (s) | exit |")
    print("|---|---|---:|---:|")
    for query, path, extra in (
        ("diagnose", "examples/lifelong/budget-cut.cat", []),
        ("relax", "examples/lifelong/budget-cut.cat", []),
        ("relax --discrete", "examples/lifelong/budget-cut.cat", []),
        ("recompose (stability first)", "examples/lifelong/cheaper-camera.cat", []),
        ("recompose --priority objective", "examples/lifelong/cheaper-camera.cat", []),
        ("diagnose", "examples/search-and-rescue/budget-cut.cat", []),
        ("recompose (stability first)", "examples/search-and-rescue/cheaper-camera.cat", []),
        ("synthesize", "examples/holes/talk.cat", []),
        ("pareto", "examples/pareto-design/design.cat", []),
    ):
        words = query.split(" (")[0].split()
        wall, code = _median_wall(CATC + words[:1] + [path] + words[1:] + extra, runs)
        print(f"| {query} | {path.removeprefix('examples/')} | {wall:.3f} | {code} |")
    print()
    print("### Optimize against plain solve on the same problem\n")
    print("In-process time (`timings.total` of `--json`: encode + solve + validate) and wall time of the")
    print("process; `optimize` deepens then proves (default), `single` is `--strategy single`.\n")
    print(
        "| example | solve (s) | optimize (s) | ratio | single (s) | ratio | wall: solve / optimize (s) | wall ratio |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for path in (
        "examples/gpu-allocation/max-confidence.cat",
        "examples/gpu-allocation/retask.cat",
        "examples/navigation/farthest.cat",
        "examples/search-and-rescue/event2-out-of-range.cat",
        "examples/semantics/soft.cat",
    ):
        problem = ["--problem", "fastest-with-reserve"] if path.endswith("soft.cat") else []
        runs_of: dict[str, tuple[list[float], list[float]]] = {k: ([], []) for k in ("solve", "optimize", "single")}
        for _ in range(runs):
            for key, cmd in (
                ("solve", ["solve"]),
                ("optimize", ["optimize"]),
                ("single", ["optimize", "--strategy", "single"]),
            ):
                start = time.perf_counter()
                out = subprocess.run(CATC + cmd + [path, "--json"] + problem, capture_output=True, cwd=ROOT).stdout
                runs_of[key][1].append(time.perf_counter() - start)
                runs_of[key][0].append(json.loads(out)["timings"]["total"])
        med = {k: (statistics.median(v[0]), statistics.median(v[1])) for k, v in runs_of.items()}
        s_in, s_wall = med["solve"]
        o_in, o_wall = med["optimize"]
        g_in = med["single"][0]
        print(
            f"| {path.removeprefix('examples/')} | {s_in:.3f} | {o_in:.3f} | {o_in / s_in:.2f}× | {g_in:.3f} | "
            f"{g_in / s_in:.2f}× | {s_wall:.3f} / {o_wall:.3f} | {o_wall / s_wall:.2f}× |"
        )
    print()


def bench_refutation(runs: int) -> None:
    """The check `catc optimize --strategy deepen` uses as a proof — "a composition of at most
    24 steps better than 10 m?" on search-and-rescue event II, unsat — on Z3's default
    configuration and on Z3 configured for QF_LRA (what catc uses), in this process."""
    import z3

    from catc import ir
    from catc.frontend.workspace import load_instance
    from catc.queries.optimum import _encode_whole, _objective_terms
    from catgrammar.diagnostics import Diagnostics

    _, inst = load_instance(None, str(ROOT / "examples/search-and-rescue/event2-out-of-range.cat"), Diagnostics())
    objectives = list(inst.problem.metric.objectives)
    k = inst.problem.horizon
    enc, backend = _encode_whole(inst, k, False, optimize=False)
    (term,) = _objective_terms(enc, backend, objectives, [], k)
    assert objectives[0].sense is ir.Sense.MAXIMIZE
    formula = backend.solver.assertions()  # this benchmark compares Z3 configurations: Z3's own objects
    term = backend.expr(term)
    print("### The refutation behind `optimize --strategy deepen` (event II, 24 steps, better than 10 m)\n")
    print("| Z3 configuration | answer | median (s) | IQR (s) |")
    print("|---|---|---:|---|")
    for label, make in (
        ("default (`z3.Solver()`)", z3.Solver),
        ("QF_LRA (`z3.SolverFor('QF_LRA')`)", lambda ctx: z3.SolverFor("QF_LRA", ctx=ctx)),
    ):
        walls, answer = [], None
        for _ in range(runs):
            solver = make(ctx=backend.ctx)
            solver.add(formula)
            solver.add(term > 10)
            start = time.perf_counter()
            answer = solver.check()
            walls.append(time.perf_counter() - start)
        m, lo, hi = quartiles(walls)
        print(f"| {label} | {answer} | {m:.3f} | {lo:.3f}–{hi:.3f} |")
    print()


def compile_catc() -> None:
    """Byte-compile catc, so that timings match an installed catc whatever
    PYTHONDONTWRITEBYTECODE says (as `pip install .` compiles it)."""
    subprocess.run(
        [sys.executable, "-m", "compileall", "-q", "compiler/catc", "catgrammar", "stdlib_domains"],
        cwd=ROOT,
        check=False,
    )


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--quick", action="store_true", help="fewer sizes and runs, for a smoke test")
    ap.add_argument("--only", choices=["examples", "reference", "scaling", "queries"])
    ap.add_argument(
        "--no-compile",
        action="store_true",
        help="do not byte-compile catc first (by default it is, as `pip install .` does)",
    )
    args = ap.parse_args()
    if not args.no_compile:
        compile_catc()
    sizes, horizons = ([25, 50], [5, 10]) if args.quick else ([25, 50, 100, 200], [5, 10, 20])
    print(
        f"command: python benchmarks/solve_bench.py --runs {args.runs}"
        + (" --quick" if args.quick else "")
        + (f" --only {args.only}" if args.only else "")
    )
    print(f"machine: {machine()}\n")
    if args.only in (None, "examples"):
        bench_examples(args.runs)
    if args.only in (None, "reference"):
        bench_reference(max(args.runs, 15))
    if args.only in (None, "queries"):
        bench_queries(args.runs)
        bench_refutation(args.runs)
    if args.only in (None, "scaling"):
        bench_scaling(max(1, args.runs // 3), sizes, horizons)


if __name__ == "__main__":
    main()
