"""Benchmark: parse + check of generated domains with 200 / 2,000 / 20,000 morphisms.

Prints a Markdown table (median of N runs, in-process, after one warm-up) and the command
that produced it.  The generated domain mixes every kind of literal: numeric comparisons,
set membership, bools, θ parameters with bounds, increase/decrease/add/assign effects.

    python benchmarks/parse_check.py [--sizes 200 2000 20000] [--runs 5]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT), str(ROOT / "compiler")]

from catc.frontend.workspace import Workspace  # noqa: E402
from catc.interfaces.entry import configure_process  # noqa: E402
from catgrammar._lalr import Parser  # noqa: E402
from catgrammar.diagnostics import Diagnostics  # noqa: E402
from catgrammar.parser import _Builder, parse_source, read_source  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from solve_bench import machine  # noqa: E402


def generate(n: int) -> str:
    lines = [
        f"(define (domain synthetic-{n})",
        "  (:requirements :numeric :sets :free-parameters :recomposition)",
        "  (:sorts module topic - symbol)",
        "  (:constants " + " ".join(f"mod{i}" for i in range(max(1, n // 10))) + " - module",
        "              " + " ".join(f"top{i}" for i in range(max(1, n // 10))) + " - topic)",
        "  (:resources (ram real :bounds (0 *)) (budget real) (mounted (set module)) (topics (set topic))",
        "              " + " ".join(f"(flag{i} bool)" for i in range(max(1, n // 20))) + ")",
    ]
    flags = max(1, n // 20)
    mods = max(1, n // 10)
    for i in range(n):
        f_in, f_out = f"flag{i % flags}", f"flag{(i + 1) % flags}"
        mod = f"mod{i % mods}"
        lines.append(
            f"  (:morphism m{i}\n"
            f"    :kind software :churn {1 + i % 3} :uses 1\n"
            f"    :parameters ((req real :bounds (0.5 {2 + i % 5})) (out topic))\n"
            f"    :precondition (and (>= ram req) (member {mod} mounted) {f_in} (>= budget {i % 100}.5))\n"
            f"    :effect (and (decrease ram req) (add topics out) (assign {f_out} true) (decrease budget 1)))"
        )
    lines.append(")")
    return "\n".join(lines) + "\n"


def measure(text: str, runs: int) -> tuple[float, float, int]:
    parse_times, check_times = [], []
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "synthetic.cat"
        path.write_text(text)
        for _ in range(runs + 1):
            diags = Diagnostics()
            # the process's collector is set as the catc executable sets it (main below)
            t0 = time.perf_counter()
            src = read_source(str(path), diags)
            sf = parse_source(src, diags)
            t1 = time.perf_counter()
            ws = Workspace(diags)
            ws.files[str(path)] = sf
            (dom,) = sf.definitions
            ws.domains[dom.name.text] = [(dom, str(path))]
            result = ws.domain_ir(dom.name.text, str(path), None)
            t2 = time.perf_counter()
            assert result is not None and not diags.has_errors, [d.message for d in diags][:3]
            parse_times.append(t1 - t0)
            check_times.append(t2 - t1)
    return statistics.median(parse_times[1:]), statistics.median(check_times[1:]), len(text.splitlines())


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", type=int, nargs="+", default=[200, 2000, 20000])
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args()
    configure_process()  # as the catc executable does
    t0 = time.perf_counter()
    for _ in range(100):
        Parser(_Builder())  # every parse makes its own parser from the generated tables
    grammar_ms = (time.perf_counter() - t0) * 10

    print(f"command: python benchmarks/parse_check.py --sizes {' '.join(map(str, args.sizes))} --runs {args.runs}")
    print(f"machine: {machine()}; making a parser {grammar_ms:.2f} ms")
    print()
    print("| morphisms | lines | parse (s) | check (s) | total (s) | µs per morphism | growth vs previous |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    prev = None
    for n in args.sizes:
        p, c, lines = measure(generate(n), args.runs)
        total = p + c
        growth = f"{total / prev[1]:.1f}× for {n / prev[0]:.0f}× size" if prev else "—"
        print(f"| {n:,} | {lines:,} | {p:.3f} | {c:.3f} | {total:.3f} | {total / n * 1e6:.0f} | {growth} |")
        prev = (n, total)


if __name__ == "__main__":
    main()
