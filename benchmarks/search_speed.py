"""The forward search's CPU seconds on chosen corpus tasks, two source trees side by side.

    python benchmarks/search_speed.py --before /work/main --after . [--only rover-10 ...] [--repeat 1]

Each (tree, task) runs in its own process, which loads the tree's own
``benchmarks/planning_corpus.py`` (so its ``catc``), imports the task's PDDL, and times
``solve(..., sequential=True, strategy="search")`` as ``planning_corpus.py`` does (process CPU
seconds, wall seconds); the plan is replayed by unified-planning's validator. The runs of the
two trees alternate task by task, so a change in the machine's load falls on both. Prints a
markdown table: per task the plan length (the hand count beside it), whether it was proven
shortest, whether it validated, and both trees' CPU seconds and their ratio.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import subprocess
import sys
import time
from pathlib import Path

DEFAULT = ["gripper-12", "farmland-10", "rover-10", "rover-14", "hydropower-24-4"]


def child(tree: str, name: str, timeout: float, horizon: int) -> dict[str, object]:
    spec = importlib.util.spec_from_file_location("planning_corpus", Path(tree) / "benchmarks" / "planning_corpus.py")
    assert spec is not None and spec.loader is not None
    pc = importlib.util.module_from_spec(spec)
    sys.modules["planning_corpus"] = pc
    spec.loader.exec_module(pc)
    import tempfile

    import unified_planning.shortcuts as shortcuts
    from unified_planning.io import PDDLReader

    from catc.bench import corpus
    from catc.frontend.up_import import up_to_instance
    from catc.queries.solve import solve

    shortcuts.get_environment().credits_stream = None
    (task,) = [t for t in pc.tasks() if t.name == name]
    with tempfile.TemporaryDirectory() as tmp:
        d, p = Path(tmp) / "domain.pddl", Path(tmp) / "problem.pddl"
        d.write_text(task.domain)
        p.write_text(task.problem)
        up_problem = PDDLReader().parse_problem(str(d), str(p))
    inst, report = up_to_instance(up_problem, timeout=timeout)
    t0, c0 = time.perf_counter(), time.process_time()
    r = solve(inst, horizon=horizon, sequential=True, strategy="search", timeout=timeout)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    out: dict[str, object] = {"status": r.status.value, "wall": wall, "cpu": cpu, "expected": task.optimal}
    import catc

    out["catc"] = str(Path(catc.__file__).parents[2])
    if r.plan is not None:
        steps = pc._pddl_steps(r.plan, report)
        out.update(length=len(steps), shortest=r.shortest, valid=corpus.up_validates(up_problem, steps))
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--before", help="the source tree measured first (e.g. /work/main)")
    ap.add_argument("--after", help="the source tree measured second")
    ap.add_argument("--only", action="append", default=[])
    ap.add_argument("--repeat", type=int, default=1, help="runs per tree and task; the least CPU time counts")
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--horizon", type=int, default=200)
    ap.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        print(json.dumps(child(args.child[0], args.child[1], args.timeout, args.horizon)))
        return 0
    if not args.before or not args.after:
        ap.error("--before and --after are required")
    trees = {"before": str(Path(args.before).resolve()), "after": str(Path(args.after).resolve())}
    lines = [
        "| task | hand count | before: length (shortest, valid) | before cpu s | after: length (shortest, valid) "
        "| after cpu s | before / after |",
        "|---|---|---|---|---|---|---|",
    ]
    for name in args.only or DEFAULT:
        best: dict[str, dict[str, object]] = {}
        for _ in range(args.repeat):
            for which, tree in trees.items():
                env_path = f"{tree}/compiler:{tree}/runtime:{tree}"
                proc = subprocess.run(
                    [sys.executable, __file__, "--child", tree, name, "--timeout", str(args.timeout)]
                    + ["--horizon", str(args.horizon)],
                    capture_output=True,
                    text=True,
                    env={**__import__("os").environ, "PYTHONPATH": env_path},
                )
                if proc.returncode != 0:
                    print(proc.stderr, file=sys.stderr)
                    raise SystemExit(f"{name} on {tree} failed")
                r = json.loads(proc.stdout.strip().splitlines()[-1])
                assert r["catc"] == tree, (r["catc"], tree)
                if which not in best or r["cpu"] < best[which]["cpu"]:
                    best[which] = r
                print(f"{name} {which}: {r}", file=sys.stderr, flush=True)
        b, a = best["before"], best["after"]

        def answer(r: dict[str, object]) -> str:
            if "length" not in r:
                return str(r["status"])
            return f"{r['length']} ({'yes' if r['shortest'] else 'no'}, {'yes' if r['valid'] else 'NO'})"

        ratio = float(b["cpu"]) / max(float(a["cpu"]), 1e-9)  # type: ignore[arg-type]
        lines.append(
            f"| {name} | {b['expected']} | {answer(b)} | {float(b['cpu']):.2f} | {answer(a)} | "  # type: ignore[arg-type]
            f"{float(a['cpu']):.2f} | {ratio:.1f}× |"  # type: ignore[arg-type]
        )
    print("\n".join(lines))
    print("\n    python benchmarks/search_speed.py " + " ".join(argv or sys.argv[1:]))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
