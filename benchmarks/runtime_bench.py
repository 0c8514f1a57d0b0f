"""Benchmark: what one event costs the runtime (catrt), per decision kind.

Runs the search-and-rescue mission (examples/search-and-rescue/mission-events.jsonl) and a
stream of sensed RAM values on the detection example through catrt's Python API, in-process
(process start excluded), and prints, per event, the decision, the solver calls and the
seconds: the decision's own phases (validate, optimize/recompose, diagnose, relax) and the
whole step (apply, check, decide, commit, ground, write the generation).  Then, per decision
kind, the median.  A kept composition needs no solver call: its cost is the validator's replay.

    python benchmarks/runtime_bench.py [--runs 3] [--stream 40]

``rate`` measures the event rate of a long stream, side by side against another checkout of
the code (``git worktree add /tmp/base main``) in one run, rounds alternating: 10,000 keep
events on the search-and-rescue mission (the range to base sensed within the comms range:
the deployed composition stays valid), and a burst of mixed events on the detection example
(kept, restorations asked for and approved, a value refused, a duplicate).  Each tree runs in
a child process of its own with only that tree on ``sys.path``.  It exits 1 — the
regression check — when the keep rate is less than ``--min-ratio`` times the other tree's,
or the burst rate less than ``--min-burst-ratio`` times:

    python benchmarks/runtime_bench.py rate --against /tmp/base [--keep 10000] [--base-keep 300]

``catalog`` runs a mission of five value events on a generated 400-component catalog
(benchmarks/catalog_gen.py, ``sat``: one recompose, four keeps) on both trees, the start
excluded, and prints each step's decision time and whole time side by side:

    python benchmarks/runtime_bench.py catalog --against /tmp/base [--n 400] [--d 6] [--rounds 2]

``--sar`` runs the search-and-rescue mission (mission-events.jsonl, each tree its own copy)
that way instead.

``question`` settles whether a step got slower by its question or by the optimizer: each
tree runs the mission up to IV-approved, takes the query its recompose hands to
``optimize`` (stability first: least churn, then the most budget), and answers it as asked
on that tree and with the initial values another tree's IV-dark restoration leaves (at
0970ded relax added watts to dollars: budget 21,020 and power 23, against budget 21,110
now) — every tree's optimizer on every question, with its seconds and Z3 checks:

    python benchmarks/runtime_bench.py question --against /tmp/rt4old /work/main [--rounds 2]
"""

from __future__ import annotations

import argparse
import contextlib
import json
import statistics
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TREE = Path(sys.argv[sys.argv.index("--tree") + 1]) if "--tree" in sys.argv else ROOT  # rate's child process
sys.path[:0] = [str(TREE), str(TREE / "compiler"), str(TREE / "runtime")]

from catrt.api import connect, init  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from solve_bench import machine  # noqa: E402

MISSION = ROOT / "examples" / "search-and-rescue"
DETECTION = ROOT / "examples" / "detection" / "person.cat"


def run_events(problem: Path, events: list[dict]) -> list[dict]:
    """Each outcome of a fresh runtime on ``problem``: the start, then ``events``."""
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        state = Path(tmp) / "st"
        init(state, str(problem))
        t = time.perf_counter()
        with connect(state) as rt:
            started = time.perf_counter() - t
            outcomes = [(o, started) for o in rt.started]
            for event in events:
                t = time.perf_counter()
                outcome = rt.submit(event)
                outcomes.append((outcome, time.perf_counter() - t))
        for outcome, wall in outcomes:
            d = outcome.decision
            rows.append({"event": outcome.event_id or outcome.where, "action": d.action if d else outcome.status,
                         "solver_calls": d.solver_calls if d else 0,
                         "decide": sum(d.timings.values()) if d else 0.0, "step": wall})  # fmt: skip
    return rows


def median_rows(runs: list[list[dict]]) -> list[dict]:
    out = []
    for i, row in enumerate(runs[0]):
        out.append({**row, "decide": statistics.median(r[i]["decide"] for r in runs),
                    "step": statistics.median(r[i]["step"] for r in runs)})  # fmt: skip
    return out


def table(title: str, rows: list[dict]) -> None:
    print(f"### {title}\n")
    print("| event | decision | solver calls | decision phases (s) | whole step (s) |")
    print("|---|---|---:|---:|---:|")
    for r in rows:
        print(f"| {r['event']} | {r['action']} | {r['solver_calls']} | {r['decide']:.3f} | {r['step']:.3f} |")
    print()


def by_kind(rows: list[dict]) -> None:
    kinds: dict[str, list[dict]] = {}
    for r in rows:
        kinds.setdefault(r["action"], []).append(r)
    print("### Per decision kind (medians over both workloads)\n")
    print("| decision | events | solver calls | whole step (s) |")
    print("|---|---:|---:|---:|")
    for kind, rs in sorted(kinds.items()):
        calls = statistics.median(r["solver_calls"] for r in rs)
        print(f"| {kind} | {len(rs)} | {calls:g} | {statistics.median(r['step'] for r in rs):.3f} |")
    print()


# ---------------------------------------------------------------- rate: long streams, two trees


def keep_events(n: int) -> list[dict]:
    """``n`` sensed ranges to base within the comms range (10): each keeps the composition."""
    return [{"id": f"k{i}", "set": {"range-to-base": f"{1 + i % 9}.{i % 10}"}} for i in range(n)]


def burst_events(n: int) -> list[dict]:
    """``n`` mixed events on detection: RAM values that keep or ask for a restoration, each
    request approved, a value refused, a duplicate id."""
    out: list[dict] = []
    request = 0
    while len(out) < n:
        i = len(out)
        out += [{"id": f"b{i}", "set": {"ram": "16"}}, {"id": f"b{i}", "set": {"ram": "12"}},  # a duplicate
                {"id": f"b{i}-bad", "set": {"ram": "lots"}}, {"id": f"b{i}-low", "set": {"ram": "1"}}]  # fmt: skip
        request += 1
        out += [{"id": f"b{i}-ok", "approve": f"r{request}"}, {"id": f"b{i}-up", "set": {"ram": "64"}}]
    return out[:n]


def rate_of(problem: Path, events: list[dict]) -> dict:
    """Events per second of one runtime's loop reading ``events`` from a file after its
    start, as ``catrt run --events FILE`` does (in-process; the model files written at the
    end included)."""
    import threading

    from catrt.loop import loop

    with tempfile.TemporaryDirectory() as tmp:
        state, feed = Path(tmp) / "st", Path(tmp) / "events.jsonl"
        init(state, str(problem))
        feed.write_text("".join(json.dumps(e) + "\n" for e in events), encoding="utf-8")
        actions: dict[str, int] = {}

        def count(o: object) -> None:
            d = getattr(o, "decision", None)
            kind = str(d.action) if d is not None else str(getattr(o, "status", "?"))
            actions[kind] = actions.get(kind, 0) + 1

        with connect(state, say=count) as rt:
            actions.clear()  # the start's
            t = time.perf_counter()
            loop(rt.runtime, str(feed), once=True, stop=threading.Event(), sensors=())
            rt.close()
            took = time.perf_counter() - t
    return {"events": len(events), "seconds": took, "rate": len(events) / took, "actions": actions}


def child(args: argparse.Namespace) -> None:
    keep = rate_of(MISSION / "mission.cat", keep_events(args.keep))
    burst = rate_of(DETECTION, burst_events(args.burst))
    print(json.dumps({"keep": keep, "burst": burst}))


def rate(args: argparse.Namespace) -> int:
    import subprocess

    trees = {"this tree": (ROOT, args.keep), "--against": (Path(args.against).resolve(), args.base_keep)}
    runs: dict[str, list[dict]] = {name: [] for name in trees}
    for _ in range(args.rounds):
        for name, (tree, keep) in trees.items():
            argv = [sys.executable, __file__, "child", "--tree", str(tree), "--keep", str(keep),
                    "--burst", str(args.burst)]  # fmt: skip
            done = subprocess.run(argv, capture_output=True, text=True, check=False, env={"PATH": "/usr/bin:/bin"})
            if done.returncode != 0:
                print(f"{name} ({tree}) failed:\n{done.stderr[-2000:]}", file=sys.stderr)
                return 2
            runs[name].append(json.loads(done.stdout.splitlines()[-1]))
    print(f"`python benchmarks/runtime_bench.py rate --against {args.against} --keep {args.keep} "
          f"--base-keep {args.base_keep} --burst {args.burst} --rounds {args.rounds}` on {machine()}\n")  # fmt: skip
    print("| tree | workload | events | decisions | events/s (median of rounds) | ms/event |")
    print("|---|---|---:|---|---:|---:|")
    best: dict[tuple[str, str], float] = {}
    for name, (tree, _) in trees.items():
        for workload in ("keep", "burst"):
            rs = [r[workload] for r in runs[name]]
            median = statistics.median(r["rate"] for r in rs)
            best[name, workload] = median
            actions = ", ".join(f"{k} {v}" for k, v in sorted(rs[0]["actions"].items()))
            print(f"| {name} ({tree.name}) | {workload} | {rs[0]['events']} | {actions} | {median:.1f} | "
                  f"{1000 / median:.2f} |")  # fmt: skip
    keep_ratio = best["this tree", "keep"] / best["--against", "keep"]
    burst_ratio = best["this tree", "burst"] / best["--against", "burst"]
    print(f"\nkeep: {keep_ratio:.1f}× the other tree's rate (at least {args.min_ratio:g}× required); "
          f"burst: {burst_ratio:.2f}× (at least {args.min_burst_ratio:g}× required)")  # fmt: skip
    if keep_ratio < args.min_ratio or burst_ratio < args.min_burst_ratio:
        sys.stdout.flush()
        print("REGRESSION: an event rate is below what is required", file=sys.stderr)
        return 1
    return 0


# ---------------------------------------------------------------- catalog: a large model, two trees

CATALOG_EVENTS = [{"id": "c1", "set": {"ram": "7"}}, {"id": "c2", "set": {"ram": "10"}},
                  {"id": "c3", "set": {"power": "90"}}, {"id": "c4", "set": {"ram": "8"}},
                  {"id": "c5", "set": {"power": "91"}}]  # fmt: skip


def catalog_child(args: argparse.Namespace) -> None:
    """Per step of a mission on a generated catalog (benchmarks/catalog_gen.py, the ``sat``
    problem): ram 10 → 7 breaks the deployed composition (it needs 8, the least is 7: a
    recompose), the rest keep it.  Prints the decision and the seconds per step as JSON."""
    if args.sar:  # the search-and-rescue mission instead, as the tree that runs has it (the language moved)
        folder = TREE / "examples" / "search-and-rescue"
        mission = [json.loads(line) for line in (folder / "mission-events.jsonl").read_text().splitlines()]
        print(json.dumps(run_events(folder / "mission.cat", mission)))
        return
    from catalog_gen import build, write

    with tempfile.TemporaryDirectory() as tmp:
        write(build(args.n, args.d), Path(tmp) / "cat")
        rows = run_events(Path(tmp) / "cat" / "sat.cat", CATALOG_EVENTS)
    print(json.dumps(rows))


def catalog(args: argparse.Namespace) -> int:
    """The steps of :func:`catalog_child` for this tree and ``--against``, rounds alternating."""
    import subprocess

    trees = {"this tree": ROOT, "--against": Path(args.against).resolve()}
    runs: dict[str, list[list[dict]]] = {name: [] for name in trees}
    for _ in range(args.rounds):
        for name, tree in trees.items():
            argv = [
                sys.executable,
                __file__,
                "catalog-child",
                "--tree",
                str(tree),
                "--n",
                str(args.n),
                "--d",
                str(args.d),
                *(["--sar"] if args.sar else []),
            ]
            done = subprocess.run(argv, capture_output=True, text=True, check=False, env={"PATH": "/usr/bin:/bin"})
            if done.returncode != 0:
                print(f"{name} ({tree}) failed:\n{done.stderr[-2000:]}", file=sys.stderr)
                return 2
            runs[name].append(json.loads(done.stdout.splitlines()[-1]))
    size = "--sar" if args.sar else f"--n {args.n} --d {args.d}"
    print(f"`python benchmarks/runtime_bench.py catalog --against {args.against} {size} "
          f"--rounds {args.rounds}` on {machine()}\n")  # fmt: skip
    print("| step | decision | decision phases (s), " + " / ".join(trees) + " | whole step (s), "
          + " / ".join(f"{n} ({t.name})" for n, t in trees.items()) + " |")  # fmt: skip
    print("|---|---|---:|---:|")
    mine, other = (median_rows(runs[n]) for n in trees)
    for a, b in zip(mine, other, strict=True):
        print(f"| {a['event']} | {a['action']} | {a['decide']:.3f} / {b['decide']:.3f} | "
              f"{a['step']:.3f} / {b['step']:.3f} |")  # fmt: skip
    return 0


# ---------------------------------------------------------------- question: IV-approved's query, swapped

#: IV-approved's question by the restoration before it: the initial values it changes.
QUESTIONS = {
    "budget 21110 (now)": {"budget": "21110"},
    "budget 21020, power 23 (0970ded)": {"budget": "21020", "power": "23"},
}


class _Taken(BaseException):
    """Raised by :func:`question_child`'s stand-in for ``optimize`` (past any ``except Exception``)."""


def question_child(args: argparse.Namespace) -> None:
    """The optimize call of IV-approved's recompose on this tree, then this tree's optimize
    on each of :data:`QUESTIONS` (``--rounds`` times): seconds, Z3 checks, values (JSON)."""
    from fractions import Fraction

    import catc.queries.recompose as rec
    import catc.smt.z3backend as z3b
    from catc import ir
    from catc.queries.optimize import optimize

    taken: list[tuple] = []

    def take(inst: object, order: object, **kw: object) -> object:
        taken.append((inst, order, kw))
        raise _Taken  # stop the step: only its question is wanted

    folder = TREE / "examples" / "search-and-rescue"
    mission = [json.loads(line) for line in (folder / "mission-events.jsonl").read_text().splitlines()]
    with tempfile.TemporaryDirectory() as tmp:
        state = Path(tmp) / "st"
        init(state, str(folder / "mission.cat"))
        with connect(state) as rt:
            for event in mission:
                if event["id"] == "IV-approved":
                    rec.optimize = take
                    with contextlib.suppress(_Taken):
                        rt.submit(event)
                    break
                rt.submit(event)
    rec.optimize = optimize
    inst, order, kw = taken[0]
    checks: list[str] = []
    check = z3b.Z3Backend.check

    def counted(self: object, *a: object, **k: object) -> object:
        checks.append(type(self.solver).__name__)  # type: ignore[attr-defined]
        return check(self, *a, **k)

    z3b.Z3Backend.check = counted
    out = []
    for name, values in QUESTIONS.items():
        start = dict(inst.problem.init)
        for r, v in values.items():
            iv = start[r]
            start[r] = type(iv)(iv.resource, type(iv.value)(Fraction(v), iv.value.sort), iv.label, iv.span)
        asked = ir.Instance(inst.domain, replace(inst.problem, init=start), inst.view)
        for _ in range(args.rounds):
            checks.clear()
            t = time.perf_counter()
            result = optimize(asked, order, **{k: v for k, v in kw.items() if k != "progress"})
            took = time.perf_counter() - t
            out.append({"question": name, "seconds": took, "checks": len(checks),
                        "optimize_checks": checks.count("Optimize"), "status": result.status.name,
                        "values": [str(v.value) for v in result.values]})  # fmt: skip
    print(json.dumps(out))


def question(args: argparse.Namespace) -> int:
    """:func:`question_child` on this tree and each ``--against`` tree, side by side."""
    import subprocess

    trees = {"this tree": ROOT} | {f"--against {t}": Path(t).resolve() for t in args.against}
    rows: dict[str, list[dict]] = {}
    for name, tree in trees.items():
        argv = [sys.executable, __file__, "question-child", "--tree", str(tree), "--rounds", str(args.rounds)]
        done = subprocess.run(argv, capture_output=True, text=True, check=False, env={"PATH": "/usr/bin:/bin"})
        if done.returncode != 0:
            print(f"{name} ({tree}) failed:\n{done.stderr[-2000:]}", file=sys.stderr)
            return 2
        rows[name] = json.loads(done.stdout.splitlines()[-1])
    print(f"`python benchmarks/runtime_bench.py question --against {' '.join(args.against)} "
          f"--rounds {args.rounds}` on {machine()}\n")  # fmt: skip
    print("| tree's optimizer | question (IV-dark's restoration) | answer (churn, budget) | seconds (median) "
          "| Z3 checks (of them Optimize) |")  # fmt: skip
    print("|---|---|---|---:|---:|")
    for name, tree in trees.items():
        for q in QUESTIONS:
            rs = [r for r in rows[name] if r["question"] == q]
            seconds = statistics.median(r["seconds"] for r in rs)
            print(f"| {name} ({tree.name}) | {q} | {rs[0]['status']} ({', '.join(rs[0]['values'])}) | "
                  f"{seconds:.2f} | {rs[0]['checks']} ({rs[0]['optimize_checks']}) |")  # fmt: skip
    return 0


def main() -> None:
    if sys.argv[1:2] in (["question"], ["question-child"]):
        ap = argparse.ArgumentParser(description="IV-approved's question on each tree's optimizer, and swapped")
        ap.add_argument("mode", choices=["question", "question-child"])
        ap.add_argument("--against", nargs="+", default=["/tmp/base"], help="other checkouts")
        ap.add_argument("--tree", default=str(ROOT), help="(child) the tree whose code runs")
        ap.add_argument("--rounds", type=int, default=2)
        args = ap.parse_args()
        if args.mode == "question-child":
            question_child(args)
            return
        sys.exit(question(args))
    if sys.argv[1:2] in (["catalog"], ["catalog-child"]):
        ap = argparse.ArgumentParser(description="a mission on a generated catalog, side by side against another tree")
        ap.add_argument("mode", choices=["catalog", "catalog-child"])
        ap.add_argument("--against", default="/tmp/base", help="another checkout (e.g. a worktree of main)")
        ap.add_argument("--tree", default=str(ROOT), help="(child) the tree whose code runs")
        ap.add_argument("--n", type=int, default=400, help="components")
        ap.add_argument("--d", type=int, default=6, help="levels")
        ap.add_argument("--rounds", type=int, default=2)
        ap.add_argument("--sar", action="store_true", help="the search-and-rescue mission instead of a catalog")
        args = ap.parse_args()
        if args.mode == "catalog-child":
            catalog_child(args)
            return
        sys.exit(catalog(args))
    if sys.argv[1:2] in (["rate"], ["child"]):
        ap = argparse.ArgumentParser(description="event rate, side by side against another tree")
        ap.add_argument("mode", choices=["rate", "child"])
        ap.add_argument("--against", default="/tmp/base", help="another checkout (e.g. a worktree of main)")
        ap.add_argument("--tree", default=str(ROOT), help="(child) the tree whose code runs")
        ap.add_argument("--keep", type=int, default=10000, help="keep events for this tree")
        ap.add_argument(
            "--base-keep", type=int, default=300, help="keep events for the other tree (its rate is steady)"
        )
        ap.add_argument("--burst", type=int, default=60, help="mixed events on detection")
        ap.add_argument("--rounds", type=int, default=2)
        ap.add_argument("--min-ratio", type=float, default=10.0, help="keep rate: at least this × the other tree's")
        ap.add_argument("--min-burst-ratio", type=float, default=1.0, help="burst rate: at least this × the other's")
        args = ap.parse_args()
        if args.mode == "child":
            child(args)
            return
        sys.exit(rate(args))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--stream", type=int, default=40, help="sensed RAM values on detection")
    args = ap.parse_args()
    print(f"`python benchmarks/runtime_bench.py --runs {args.runs} --stream {args.stream}` on {machine()}\n")
    mission = [json.loads(line) for line in (MISSION / "mission-events.jsonl").read_text().splitlines()]
    sar = median_rows([run_events(MISSION / "mission.cat", mission) for _ in range(args.runs)])
    table("Search-and-rescue mission (mission-events.jsonl)", sar)
    values = ["16", "8", "1", "4.5", "64", "3", "12", "4.5"]
    stream = [{"id": f"e{i}", "set": {"ram": values[i % len(values)]}} for i in range(args.stream)]
    det = median_rows([run_events(DETECTION, stream) for _ in range(args.runs)])
    table(f"Detection, {args.stream} sensed RAM values (first 8 shown)", det[:9])
    by_kind(sar + det)


if __name__ == "__main__":
    main()
