"""Warm re-solving against cold solving, event by event, in one run (issue 16).

    python benchmarks/warm_bench.py [--runs 3] [--sizes 50,200,400] [--depth 24] [--sar-only]

A lifelong run changes one value at a time: a sensed value, a price the world charges, the
goal.  Each sequence below is a list of such problems on one model; every problem is solved
twice in this process, side by side — cold (``solve(inst)``: encode, new solver) and warm
(``solve(inst, warm=w)`` with one :class:`~catc.queries.solve.WarmStart` for the whole
sequence) — and the two answers must agree (status and length of the composition; every SAT
answer is replayed by the validator inside ``solve``).  Loading and checking the model is
not timed (the runtime does it for both).  Medians over ``--runs`` (each run starts with a
fresh WarmStart).

Sequences:

* search and rescue (examples/search-and-rescue/mission.cat without its metric): the range
  to base, the budget and the light change; the runtime assumes sensed resources from the
  start, and so does this run (``WarmStart(["range-to-base", "budget", "ambient"])``).
* generated catalogs (benchmarks/catalogs.py, ``ram`` variant: feasible from ram 12 up,
  and the relaxation cannot tell): ram and cpu change and the goal moves one level down.
  Here nothing is assumed in advance: the first change of ram, then of cpu, encodes afresh
  (marked ``re-encode``); the steady state is every other event.

The table gives each event's cold and warm time and their ratio; the summary line per
sequence the median ratio of the steady-state events and the largest (an event the relaxed
reachability refutes before anything is encoded, marked ``relaxation``, takes the same path
both ways and is left out of it).
"""

from __future__ import annotations

import argparse
import re
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT / "compiler"), str(ROOT / "benchmarks")]

SAR = ROOT / "examples" / "search-and-rescue"


def sar_sequence() -> tuple[list[tuple[str, object]], list[str]]:
    from catc.api import loads

    domain = (SAR / "domain.cat").read_text()
    base = (SAR / "mission.cat").read_text().replace("(:metric maximize budget)", "")

    def problem(**init: str) -> object:
        text = base
        for resource, value in init.items():
            text = re.sub(rf"\(= {resource} [^)]*\)", f"(= {resource} {value})", text)
        return loads({"domain.cat": domain, "p.cat": text}, "p.cat").instance

    events = [
        ("start", {}),
        ("range-to-base 14", {"range-to-base": "14"}),
        ("range-to-base 6", {"range-to-base": "6"}),
        ("budget 500 (UNSAT, relaxation)", {"range-to-base": "6", "budget": "500"}),
        ("budget 24000", {"range-to-base": "6", "budget": "24000"}),
        ("ambient dark", {"range-to-base": "6", "budget": "24000", "ambient": "dark"}),
        ("range-to-base 12", {"range-to-base": "12", "budget": "24000", "ambient": "dark"}),
        ("ambient bright", {"range-to-base": "12", "budget": "24000"}),
        ("budget 22000", {"range-to-base": "12", "budget": "22000"}),
    ]
    return [(name, problem(**init)) for name, init in events], ["range-to-base", "budget", "ambient"]


def catalog_sequence(n: int, d: int) -> tuple[list[tuple[str, object]], list[str]]:
    from catalogs import catalog

    from catc.api import loads

    text, _ = catalog(n, d, "ram")

    def problem(ram: int, cpu: int | None = None, goal: str | None = None) -> object:
        t = text.replace("(= ram 10)", f"(= ram {ram})")
        if cpu is not None:
            t = re.sub(r"\(= cpu \d+\)", f"(= cpu {cpu})", t)
        if goal is not None:
            t = t.replace(f"(:goal cap{d})", f"(:goal {goal})")
        return loads({"c.cat": t}, "c.cat").instance

    cpu = 4 * n
    events = [
        ("ram 12", problem(12)),
        ("ram 13 (re-encode)", problem(13)),
        ("ram 10 (UNSAT)", problem(10)),
        ("ram 14", problem(14)),
        (f"cpu {cpu - 3} (re-encode)", problem(14, cpu - 3)),
        (f"goal cap{d - 1}", problem(14, cpu - 3, f"cap{d - 1}")),
        (f"goal cap{d}", problem(14, cpu - 3)),
        ("ram 20", problem(20, cpu - 3)),
        ("ram 11 (UNSAT)", problem(11, cpu - 3)),
        (f"cpu {cpu - 5}", problem(12, cpu - 5)),
        (f"cpu {cpu - 2}", problem(12, cpu - 2)),
    ]
    return events, []


def run(events: list[tuple[str, object]], assumed: list[str], runs: int) -> list[tuple[str, float, float, str]]:
    from catc.queries.solve import WarmStart, solve

    cold: dict[str, list[float]] = {name: [] for name, _ in events}
    warm: dict[str, list[float]] = {name: [] for name, _ in events}
    answers: dict[str, str] = {}
    for _ in range(runs):
        state = WarmStart(assumed)
        for name, inst in events:
            t = time.perf_counter()
            c = solve(inst)  # type: ignore[arg-type]
            cold[name].append(time.perf_counter() - t)
            t = time.perf_counter()
            w = solve(inst, warm=state)  # type: ignore[arg-type]
            warm[name].append(time.perf_counter() - t)
            said = f"{c.status.value}" + (f" {len(c.plan)}" if c.plan is not None else "")
            again = f"{w.status.value}" + (f" {len(w.plan)}" if w.plan is not None else "")
            if said != again:
                raise SystemExit(f"{name}: cold answered {said}, warm {again}")
            answers[name] = said
    return [(name, statistics.median(cold[name]), statistics.median(warm[name]), answers[name]) for name, _ in events]


def report(title: str, rows: list[tuple[str, float, float, str]]) -> tuple[float, float]:
    print(f"\n{title}\n")
    print("| event | answer | cold (s) | warm (s) | warm / cold |")
    print("|---|---|---:|---:|---:|")
    for name, c, w, answer in rows:
        print(f"| {name} | {answer} | {c:.3f} | {w:.3f} | {w / c:.2f} |")
    steady = [w / c for name, c, w, _ in rows[1:] if "re-encode" not in name and "relaxation" not in name]
    med, worst = statistics.median(steady), max(steady)
    print(f"\nsteady state (after the first event; re-encodes and relaxation proofs left out): median {med:.2f}, "
          f"largest {worst:.2f}")  # fmt: skip
    return med, worst


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--sizes", default="50,200,400")
    ap.add_argument("--depth", type=int, default=24)
    ap.add_argument("--sar-only", action="store_true")
    args = ap.parse_args(argv)
    print("command: python benchmarks/warm_bench.py " + " ".join(argv if argv is not None else sys.argv[1:]))
    events, assumed = sar_sequence()
    report("search and rescue (mission, no metric)", run(events, assumed, args.runs))
    if not args.sar_only:
        for n in (int(x) for x in args.sizes.split(",")):
            events, assumed = catalog_sequence(n, args.depth)
            report(f"generated catalog, ram variant, n={n}, d={args.depth}", run(events, assumed, args.runs))
    return 0


if __name__ == "__main__":
    sys.exit(main())
