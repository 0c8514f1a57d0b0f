"""Mutation testing of the validator and the encoder with mutmut 3 (issue 15, item 4).

A scheduled script, not part of the test suite.  mutmut 3 copies the code it mutates into
``mutants/`` and imports it from there, and it finds the code only under ``./``, ``src/``
or ``source/``; catc lives under ``compiler/``.  So this script builds a staging copy of
the repository with ``compiler/catc`` and ``catgrammar`` under ``src/`` and a
``[tool.mutmut]`` section naming the file to mutate and the tests to run, runs ``mutmut
run`` there, and prints the score and every surviving mutant as a diff.

    python benchmarks/mutation.py [--target validate|encoder] [--stage DIR] [--max-children 2]

``--target validate`` mutates compiler/catc/semantics/validate.py against the validator's
tests; ``--target encoder`` mutates compiler/catc/smt/encoder.py against the encoder's.
Each test selection is the fast, relevant part of the suite (see ``TARGETS``); mutmut
runs, for each mutant, only the tests that reach the mutated function.  Needs ``pip
install mutmut`` (3.x).
"""

from __future__ import annotations

import argparse
import fnmatch
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: target → (file to mutate, relative to compiler/; the tests that judge it)
TARGETS: dict[str, tuple[str, list[str]]] = {
    "validate": (
        "catc/semantics/validate.py",
        [
            "tests/test_validate.py",
            "tests/test_validate_mutants.py",
            "tests/test_solve_property.py",
            "tests/test_generated_models.py",
        ],
    ),
    # the validator's expression evaluator (part of validate.py until it was split out)
    "evaluate": (
        "catc/semantics/evaluate.py",
        ["tests/test_validate.py", "tests/test_validate_mutants.py", "tests/test_solve_property.py"],
    ),
    "encoder": (
        "catc/smt/encoder.py",
        # the brute-force search, the z3 binary and cvc5, and the whole pipeline on generated
        # models (tests/test_golden_answers.py would add 40 s a mutant)
        ["tests/test_solve_property.py", "tests/test_differential.py", "tests/test_generated_models.py"],
    ),
}


def stage(target: str, where: Path) -> Path:
    """A copy of the repository laid out as mutmut 3 expects, configured for ``target``."""
    source, tests = TARGETS[target]
    if where.exists():
        shutil.rmtree(where)
    where.mkdir(parents=True)
    shutil.copytree(ROOT / "compiler" / "catc", where / "src" / "catc")
    shutil.copytree(ROOT / "catgrammar", where / "src" / "catgrammar")
    for name in ("tests", "examples", "stdlib_domains", "benchmarks"):
        shutil.copytree(ROOT / name, where / name, ignore=shutil.ignore_patterns("__pycache__", "node_modules"))
    tests = [t for t in tests if (ROOT / t).exists()]
    pyproject = (ROOT / "pyproject.toml").read_text()
    pyproject += (
        "\n[tool.mutmut]\n"
        'source_paths = ["src/catc"]\n'
        f'only_mutate = ["src/{source}"]\n'
        f"pytest_add_cli_args_test_selection = {tests!r}\n"
        'pytest_add_cli_args = ["-p", "no:cacheprovider", "-x", "-q"]\n'
        'also_copy = ["src/catgrammar", "examples", "stdlib_domains", "benchmarks"]\n'
    ).replace("'", '"')
    (where / "pyproject.toml").write_text(pyproject)
    return where


def run_mutmut(where: Path, max_children: int, mutants: list[str] | None = None) -> str:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    # the staged copy only: mutmut puts mutants/src first; the runtime is not under test
    env["PYTHONPATH"] = str(where / "src")
    cmd = [sys.executable, "-m", "mutmut", "run", "--max-children", str(max_children), *(mutants or [])]
    proc = subprocess.run(cmd, cwd=where, env=env, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"mutmut run failed ({proc.returncode}):\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    results = subprocess.run(
        [sys.executable, "-m", "mutmut", "results", "--all", "true"], cwd=where, env=env, capture_output=True, text=True
    )
    return results.stdout


def survivors_diffs(where: Path, names: list[str]) -> list[str]:
    env = {**os.environ, "PYTHONPATH": str(where / "src")}
    out = []
    for name in names:
        show = subprocess.run(
            [sys.executable, "-m", "mutmut", "show", name], cwd=where, env=env, capture_output=True, text=True
        )
        out.append(show.stdout.strip())
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--target", choices=sorted(TARGETS), default="validate")
    ap.add_argument("--stage", help="the staging folder (default: a new temporary one)")
    ap.add_argument("--max-children", type=int, default=2, help="mutants tested at once")
    ap.add_argument(
        "--mutants",
        nargs="+",
        help="test only these mutants (names as `mutmut results` prints them, or fnmatch patterns)",
    )
    args = ap.parse_args()
    where = Path(args.stage) if args.stage else Path(tempfile.mkdtemp(prefix="catc-mutation-"))
    t0 = time.perf_counter()
    results = run_mutmut(stage(args.target, where), args.max_children, args.mutants)
    status = dict(re.findall(r"^\s*(\S+): (\w[\w ]*)$", results, re.M))
    if args.mutants:  # the others were not run
        status = {name: s for name, s in status.items() if any(fnmatch.fnmatch(name, m) for m in args.mutants)}
    counts: dict[str, int] = {}
    for s in status.values():
        counts[s] = counts.get(s, 0) + 1
    killed, survived = counts.get("killed", 0), counts.get("survived", 0)
    judged = killed + survived + counts.get("timeout", 0)
    source, tests = TARGETS[args.target]
    print(f"command: python benchmarks/mutation.py --target {args.target} --max-children {args.max_children}")
    print(f"mutated: compiler/{source}; tests: {' '.join(tests)}; {time.perf_counter() - t0:.0f} s")
    print()
    print("| mutants | killed | timeout | survived | no tests | score |")
    print("|---:|---:|---:|---:|---:|---:|")
    score = (killed + counts.get("timeout", 0)) / judged if judged else 0.0
    print(
        f"| {len(status)} | {killed} | {counts.get('timeout', 0)} | {survived} | "
        f"{counts.get('no tests', 0)} | {score:.1%} |"
    )
    names = sorted(n for n, s in status.items() if s in ("survived", "no tests"))
    if names:
        print("\nSurviving mutants:\n")
        for diff in survivors_diffs(where, names):
            print(diff + "\n")
    other = {s: n for s, n in counts.items() if s not in ("killed", "survived", "timeout", "no tests")}
    if other:
        print(f"other outcomes: {other}")


if __name__ == "__main__":
    main()
