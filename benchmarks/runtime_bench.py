"""Benchmark: what one event costs the runtime (catrt), per decision kind.

Runs the search-and-rescue mission (examples/search-and-rescue/mission-events.jsonl) and a
stream of sensed RAM values on the detection example through catrt's Python API, in-process
(process start excluded), and prints, per event, the decision, the solver calls and the
seconds: the decision's own phases (validate, optimize/recompose, diagnose, relax) and the
whole step (apply, check, decide, commit, ground, write the generation).  Then, per decision
kind, the median.  A kept composition needs no solver call: its cost is the validator's replay.

    python benchmarks/runtime_bench.py [--runs 3] [--stream 40]
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT), str(ROOT / "compiler"), str(ROOT / "runtime")]

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


def main() -> None:
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
