"""Planning tasks of growing plan length, catc beside ENHSP, every plan checked by UP's validator.

    python benchmarks/planning_corpus.py [--timeout 60] [--only NAME ...] [--smt] [--no-enhsp]

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

Not here (yet): IPC 2023 rover and hydropower (no generator on this machine; not written).

For each task: ``catc import pddl`` (timed), ``catc solve --sequential --strategy search`` (forward
greedy search on a numeric h_add for a first plan, then A* with numeric h^max below its length:
a shortest plan proven, or the greedy plan marked not proven shortest when the time runs out;
exact; the SMT search where it does not apply), optionally the SMT search
alone (``--smt``), ENHSP ``-planner opt-hrmax`` (A* with h^max: optimal, the like-for-like
baseline) in its own process under the same timeout; both plans replayed by unified-planning's
``SequentialPlanValidator`` on the original PDDL. Prints a markdown table and the command.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT / "compiler"), str(ROOT / "runtime"), str(ROOT)]

from catc.bench import corpus  # noqa: E402

# ---------------------------------------------------------------- generators

GRIPPER = """(define (domain gripper-strips)
 (:predicates (room ?r) (ball ?b) (gripper ?g) (at-robby ?r) (at ?b ?r) (free ?g) (carry ?o ?g))
 (:action move :parameters (?from ?to)
  :precondition (and (room ?from) (room ?to) (at-robby ?from))
  :effect (and (at-robby ?to) (not (at-robby ?from))))
 (:action pick :parameters (?obj ?room ?gripper)
  :precondition (and (ball ?obj) (room ?room) (gripper ?gripper) (at ?obj ?room) (at-robby ?room) (free ?gripper))
  :effect (and (carry ?obj ?gripper) (not (at ?obj ?room)) (not (free ?gripper))))
 (:action drop :parameters (?obj ?room ?gripper)
  :precondition (and (ball ?obj) (room ?room) (gripper ?gripper) (carry ?obj ?gripper) (at-robby ?room))
  :effect (and (at ?obj ?room) (free ?gripper) (not (carry ?obj ?gripper)))))
"""


def gripper(n: int) -> str:
    balls = " ".join(f"ball{i}" for i in range(n))
    init = " ".join(f"(ball ball{i}) (at ball{i} rooma)" for i in range(n))
    goal = " ".join(f"(at ball{i} roomb)" for i in range(n))
    return (
        f"(define (problem gripper-{n}) (:domain gripper-strips)\n (:objects rooma roomb left right {balls})\n"
        f" (:init (room rooma) (room roomb) (gripper left) (gripper right) (at-robby rooma) (free left)"
        f" (free right) {init})\n (:goal (and {goal})))\n"
    )


FERRY = """(define (domain ferry)
 (:requirements :strips)
 (:predicates (not-eq ?x ?y) (car ?c) (place ?p) (at-ferry ?l) (at ?c ?l) (empty-ferry) (on ?c))
 (:action sail :parameters (?from ?to)
  :precondition (and (place ?from) (place ?to) (not-eq ?from ?to) (at-ferry ?from))
  :effect (and (at-ferry ?to) (not (at-ferry ?from))))
 (:action board :parameters (?car ?loc)
  :precondition (and (car ?car) (place ?loc) (at ?car ?loc) (at-ferry ?loc) (empty-ferry))
  :effect (and (on ?car) (not (at ?car ?loc)) (not (empty-ferry))))
 (:action debark :parameters (?car ?loc)
  :precondition (and (car ?car) (place ?loc) (on ?car) (at-ferry ?loc))
  :effect (and (at ?car ?loc) (empty-ferry) (not (on ?car)))))
"""


def ferry(n: int) -> str:
    cars = " ".join(f"c{i}" for i in range(n))
    init = " ".join(f"(car c{i}) (at c{i} l0)" for i in range(n))
    goal = " ".join(f"(at c{i} l1)" for i in range(n))
    return (
        f"(define (problem ferry-{n}) (:domain ferry)\n (:objects l0 l1 {cars})\n"
        f" (:init (place l0) (place l1) (not-eq l0 l1) (not-eq l1 l0) (empty-ferry) (at-ferry l0) {init})\n"
        f" (:goal (and {goal})))\n"
    )


BLOCKS = """(define (domain blocks)
 (:requirements :strips)
 (:predicates (on ?x ?y) (ontable ?x) (clear ?x) (handempty) (holding ?x))
 (:action pick-up :parameters (?x)
  :precondition (and (clear ?x) (ontable ?x) (handempty))
  :effect (and (not (ontable ?x)) (not (clear ?x)) (not (handempty)) (holding ?x)))
 (:action put-down :parameters (?x)
  :precondition (holding ?x)
  :effect (and (not (holding ?x)) (clear ?x) (handempty) (ontable ?x)))
 (:action stack :parameters (?x ?y)
  :precondition (and (holding ?x) (clear ?y))
  :effect (and (not (holding ?x)) (not (clear ?y)) (clear ?x) (handempty) (on ?x ?y)))
 (:action unstack :parameters (?x ?y)
  :precondition (and (on ?x ?y) (clear ?x) (handempty))
  :effect (and (holding ?x) (clear ?y) (not (clear ?x)) (not (handempty)) (not (on ?x ?y)))))
"""


def blocks(n: int, cycle: bool = False) -> str:
    bs = [f"b{i}" for i in range(n)]
    init = " ".join(f"(on b{i} b{i + 1})" for i in range(n - 1)) + f" (ontable b{n - 1}) (clear b0) (handempty)"
    if cycle:  # b0 on b1 on b2 on b0: no state has it
        goal = "(on b0 b1) (on b1 b2) (on b2 b0)"
    else:  # the tower reversed
        goal = " ".join(f"(on b{i + 1} b{i})" for i in range(n - 1)) + " (ontable b0)"
    return (
        f"(define (problem blocks-{n}) (:domain blocks)\n (:objects {' '.join(bs)})\n (:init {init})\n"
        f" (:goal (and {goal})))\n"
    )


FARMLAND = """(define (domain farmland)
 (:requirements :typing :equality :numeric-fluents)
 (:types farm)
 (:predicates (adj ?f1 ?f2 - farm))
 (:functions (x ?f - farm) (cost))
 (:action move-fast :parameters (?f1 ?f2 - farm)
  :precondition (and (not (= ?f1 ?f2)) (adj ?f1 ?f2) (>= (x ?f1) 4))
  :effect (and (decrease (x ?f1) 4) (increase (x ?f2) 2) (increase (cost) 1)))
 (:action move-slow :parameters (?f1 ?f2 - farm)
  :precondition (and (not (= ?f1 ?f2)) (adj ?f1 ?f2) (>= (x ?f1) 1))
  :effect (and (decrease (x ?f1) 1) (increase (x ?f2) 1) (increase (cost) 1))))
"""


def farmland(n: int, workers: int) -> str:
    """IPC 2023 farmland's actions (move-fast loses two of four workers, move-slow moves one)
    on a line of n farms, every worker on f0, every farm to hold one at the end. With n workers
    no move-fast can be part of a plan (the total never grows and would fall below n), so farm
    j's worker crosses j edges one move-slow each: n(n − 1)/2, and that suffices. With n − 1
    workers there is no plan."""
    fs = [f"f{i}" for i in range(n)]
    adj = " ".join(f"(adj f{i} f{i + 1}) (adj f{i + 1} f{i})" for i in range(n - 1))
    init = " ".join(f"(= (x {f}) {workers if f == 'f0' else 0})" for f in fs)
    goal = " ".join(f"(>= (x {f}) 1)" for f in fs)
    return (
        f"(define (problem farmland-{n}-{workers}) (:domain farmland)\n (:objects {' '.join(fs)} - farm)\n"
        f" (:init {adj} {init} (= (cost) 0))\n (:goal (and {goal})))\n"
    )


def sailing_far(q: int) -> str:
    """UP's sailing domain (IPC 2023), one boat at the origin, persons at d = 3q and 3q − 6.
    In u = x + y, v = y − x no move raises u + v by more than 3 (north-east, north-west: +3;
    the others 0 or less), saving the first needs u ≥ 3q and v ≥ 3q: 2q moves at least, and q
    north-east then q north-west reach u = v = 3q, inside both persons' windows [d, d + 25];
    one save each: 2q + 2."""
    return (
        corpus.sailing_problem(2)
        .replace("(= (d p0) -10)", f"(= (d p0) {3 * q})")
        .replace("(= (d p1) -17)", f"(= (d p1) {3 * q - 6})")
    )


def counters_tight(n: int) -> str:
    text = corpus.counters_problem(n)
    import re

    return re.sub(r"\(=\s*\(max_int\)\s*[0-9.]+\)", f"(= (max_int) {n - 2})", text)


@dataclass
class Task:
    name: str
    family: str
    domain: str  # text, or a path
    problem: str
    optimal: int | None  # the hand count (None: unsolvable)


def tasks() -> list[Task]:
    wheel = corpus.wheel_dir()
    assert wheel is not None
    counters_domain = (wheel / "counters" / "domain.pddl").read_text()
    out = []
    for n in (2, 4, 6, 8, 10, 12, 16):
        out.append(Task(f"gripper-{n}", "gripper", GRIPPER, gripper(n), 6 * ((n + 1) // 2) - 1))
    for n in (2, 4, 6, 8, 10, 12):
        out.append(Task(f"ferry-{n}", "ferry", FERRY, ferry(n), 4 * n - 1))
    for n in (3, 4, 5, 6, 8, 10):
        out.append(Task(f"blocks-{n}", "blocks", BLOCKS, blocks(n), 2 * n))
    for n in (4, 5, 6, 7, 8, 10):
        out.append(Task(f"counters-{n}", "counters", counters_domain, corpus.counters_problem(n), n * (n - 1) // 2))
    for n in (4, 5, 6, 7, 8, 10):
        out.append(Task(f"farmland-{n}", "farmland", FARMLAND, farmland(n, n), n * (n - 1) // 2))
    sailing_domain = (wheel / "sailing" / "domain.pddl").read_text()
    for q in (2, 4, 7, 10, 14, 19, 24):
        out.append(Task(f"sailing-far-{q}", "sailing", sailing_domain, sailing_far(q), 2 * q + 2))
    for n in (3, 4, 5, 6):
        out.append(Task(f"blocks-cycle-{n}", "unsolvable", BLOCKS, blocks(n, cycle=True), None))
    for n in (4, 6, 8):
        out.append(Task(f"farmland-short-{n}", "unsolvable", FARMLAND, farmland(n, n - 1), None))
    for n in (3, 4, 5):
        out.append(Task(f"counters-tight-{n}", "unsolvable", counters_domain, counters_tight(n), None))
    return out


# ---------------------------------------------------------------- running


@dataclass
class Row:
    task: Task
    imported: float | None = None
    catc: str = "-"
    catc_len: int | None = None
    catc_time: float | None = None
    catc_cpu: float | None = None
    catc_valid: bool | None = None
    catc_shortest: bool | None = None  # proven shortest (A*), or the greedy plan when the time ran out
    catc_first: float | None = None  # seconds until the first plan (the greedy search's)
    smt: str = "-"
    smt_len: int | None = None
    smt_time: float | None = None
    second: str = "-"  # the second planner: pyperplan A*/LM-cut (classical), TAMER (numeric)
    second_name: str = ""
    second_len: int | None = None
    second_time: float | None = None
    second_valid: bool | None = None
    enhsp: str = "-"
    enhsp_len: int | None = None
    enhsp_time: float | None = None
    enhsp_cpu: float | None = None
    enhsp_valid: bool | None = None
    notes: list[str] = field(default_factory=list)


def _pddl_steps(plan, report) -> list[str]:
    out = []
    for step in plan.steps:
        for a in step:
            ai = report.actions[a.morphism]
            args = " ".join(str(p) for p in ai.actual_parameters)
            out.append(f"({ai.action.name}{' ' + args if args else ''})")
    return out


def _second_child(engine: str, domain: str, problem: str) -> int:
    """In a child process (so that the timeout can end it): ``engine`` on the PDDL; prints the
    status and the plan's actions, one a line."""
    import unified_planning.shortcuts as shortcuts
    from unified_planning.io import PDDLReader

    shortcuts.get_environment().credits_stream = None
    problem_up = PDDLReader().parse_problem(domain, problem)
    params = {"search": "astar", "heuristic": "lmcut"} if engine == "pyperplan" else {}
    with shortcuts.OneshotPlanner(name=engine, params=params) as planner:
        r = planner.solve(problem_up)
    print(r.status.name)
    if r.plan is not None:
        for a in r.plan.actions:
            args = " ".join(str(p) for p in a.actual_parameters)
            print(f"({a.action.name}{' ' + args if args else ''})")
    return 0


def _second(row: Row, up_problem, d: Path, p: Path, timeout: float) -> None:
    """The second planner: pyperplan (A* with LM-cut: optimal) on classical tasks, TAMER on
    numeric ones, in its own process; its plan replayed by UP's validator."""
    import subprocess

    kind = up_problem.kind
    numeric = bool(kind.has_numeric_fluents() or kind.has_int_fluents() or kind.has_real_fluents())
    row.second_name = "tamer" if numeric else "pyperplan"
    t0 = time.perf_counter()
    try:
        out = subprocess.run(
            [sys.executable, __file__, "--child", row.second_name, str(d), str(p)],
            capture_output=True,
            text=True,
            timeout=timeout,
        )
    except subprocess.TimeoutExpired:
        row.second, row.second_time = "timeout", time.perf_counter() - t0
        return
    row.second_time = time.perf_counter() - t0
    lines = out.stdout.splitlines()
    if out.returncode != 0 or not lines:
        row.second = "error"
        return
    status = lines[0]
    row.second = {"SOLVED_SATISFICING": "sat", "SOLVED_OPTIMALLY": "sat (optimal)"}.get(
        status, "unsat" if "UNSOLVABLE" in status else status.lower()
    )
    if row.second.startswith("sat"):
        steps = lines[1:]
        row.second_len, row.second_valid = len(steps), corpus.up_validates(up_problem, steps)


def run(task: Task, work: Path, timeout: float, *, smt: bool, enhsp: bool, horizon: int, second: bool = False) -> Row:
    from unified_planning.io import PDDLReader

    from catc.frontend.up_import import up_to_instance
    from catc.queries.solve import SolveStatus, solve

    row = Row(task)
    d, p = work / f"{task.name}-domain.pddl", work / f"{task.name}.pddl"
    d.write_text(task.domain)
    p.write_text(task.problem)
    t0 = time.perf_counter()
    up_problem = PDDLReader().parse_problem(str(d), str(p))
    inst, report = up_to_instance(up_problem, timeout=timeout)
    row.imported = time.perf_counter() - t0
    t0, c0 = time.perf_counter(), time.process_time()
    r = solve(inst, horizon=horizon, sequential=True, strategy="search", timeout=timeout)
    row.catc_time, row.catc_cpu = time.perf_counter() - t0, time.process_time() - c0
    row.catc = r.status.value + (" (final)" if r.status is SolveStatus.UNSAT and r.final else "")
    row.catc_first = r.timings.get("first_plan")
    if r.plan is not None:
        row.catc_shortest = r.shortest
        steps = _pddl_steps(r.plan, report)
        row.catc_len, row.catc_valid = len(steps), corpus.up_validates(up_problem, steps)
    if smt:
        t0 = time.perf_counter()
        s = solve(inst, horizon=horizon, sequential=True, timeout=timeout)
        row.smt_time = time.perf_counter() - t0
        row.smt = s.status.value
        row.smt_len = None if s.plan is None else sum(len(x) for x in s.plan.steps)
    if second:
        _second(row, up_problem, d, p, timeout)
    if enhsp:
        from catc.targets.enhsp import run_enhsp

        c0 = _children_cpu()
        en = run_enhsp(d, p, planner="opt-hrmax", timeout=timeout)
        row.enhsp, row.enhsp_time, row.enhsp_cpu = en.status, en.wall, _children_cpu() - c0
        if en.status == "sat":
            steps = corpus._steps(en.output)
            row.enhsp_len, row.enhsp_valid = len(steps), corpus.up_validates(up_problem, steps)
    return row


def _children_cpu() -> float:
    """CPU seconds of the finished child processes (ENHSP's JVM, all its threads)."""
    import resource

    u = resource.getrusage(resource.RUSAGE_CHILDREN)
    return u.ru_utime + u.ru_stime


def _t(x: float | None) -> str:
    return "-" if x is None else f"{x:.1f}"


def _v(x: bool | None) -> str:
    return "-" if x is None else ("yes" if x else "NO")


def markdown(rows: list[Row], command: str, smt: bool, second: bool = False) -> str:
    head = (
        "| task | hand count | catc (search) | len | proven shortest | first plan s | wall s | cpu s | valid "
        "| ENHSP opt-hrmax | len | wall s | cpu s | valid |"
    )
    rule = "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    if smt:
        head += " catc SMT | len | s |"
        rule += "---|---|---|"
    if second:
        head += " second planner | len | wall s | valid |"
        rule += "---|---|---|---|"
    lines = [head, rule]
    for r in rows:
        t = r.task
        line = (
            f"| {t.name} | {t.optimal if t.optimal is not None else 'unsolvable'} | {r.catc} | {r.catc_len or '-'} | "
            f"{_v(r.catc_shortest)} | {_t(r.catc_first)} | "
            f"{_t(r.catc_time)} | {_t(r.catc_cpu)} | {_v(r.catc_valid)} | {r.enhsp} | {r.enhsp_len or '-'} | "
            f"{_t(r.enhsp_time)} | {_t(r.enhsp_cpu)} | {_v(r.enhsp_valid)} |"
        )
        if smt:
            line += f" {r.smt} | {r.smt_len if r.smt_len is not None else '-'} | {_t(r.smt_time)} |"
        if second:
            line += (
                f" {r.second_name} {r.second} | {r.second_len if r.second_len is not None else '-'} | "
                f"{_t(r.second_time)} | {_v(r.second_valid)} |"
            )
        lines.append(line)
    lines += ["", *medians(rows), "", f"    {command}"]
    return "\n".join(lines)


def medians(rows: list[Row], timeout: float | None = None) -> list[str]:
    """Median wall seconds per plan length (the hand count, in bands of 10), solvable tasks:
    a run without an answer counts as the time it was given (its wall time), so a median is
    never flattered by leaving failures out."""
    from statistics import median

    bands: dict[str, list[Row]] = {}
    for r in rows:
        n = r.task.optimal
        if n is None:
            continue
        lo = 10 * ((n - 1) // 10) + 1 if n > 0 else 0
        bands.setdefault(f"{lo}–{lo + 9}", []).append(r)
    out = [
        "| plan length | tasks | catc plans (proven shortest) | catc median wall s | catc median cpu s "
        "| ENHSP plans | ENHSP median wall s | ENHSP median cpu s | catc / ENHSP wall | catc / ENHSP cpu |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]

    def med(xs: list[float | None]) -> float | None:
        ys = [x for x in xs if x is not None]
        return median(ys) if ys else None

    def ratio(a: float | None, b: float | None) -> str:
        return "-" if a is None or not b else f"{a / b:.2f}"

    for band, rs in sorted(bands.items(), key=lambda kv: int(kv[0].split("–")[0])):
        cw, cc = med([r.catc_time for r in rs]), med([r.catc_cpu for r in rs])
        ew, ec = med([r.enhsp_time for r in rs]), med([r.enhsp_cpu for r in rs])
        plans = sum(r.catc_len is not None for r in rs)
        proven = sum(bool(r.catc_shortest) for r in rs)
        out.append(
            f"| {band} | {len(rs)} | {plans} ({proven}) | {_t(cw)} | {_t(cc)} | "
            f"{sum(r.enhsp_len is not None for r in rs)} | {_t(ew)} | {_t(ec)} | {ratio(cw, ew)} | {ratio(cc, ec)} |"
        )
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--horizon", type=int, default=200)
    ap.add_argument("--only", action="append", default=[])
    ap.add_argument("--smt", action="store_true", help="also the SMT search alone (slow past ~12 actions)")
    ap.add_argument("--no-enhsp", action="store_true")
    ap.add_argument(
        "--second", action="store_true", help="also pyperplan A*/LM-cut (classical) or TAMER (numeric), if installed"
    )
    ap.add_argument("--child", nargs=3, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        return _second_child(*args.child)
    import unified_planning.shortcuts as shortcuts

    shortcuts.get_environment().credits_stream = None
    chosen = [t for t in tasks() if not args.only or t.name in args.only or t.family in args.only]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for t in chosen:
            row = run(
                t,
                Path(tmp),
                args.timeout,
                smt=args.smt,
                enhsp=not args.no_enhsp,
                horizon=args.horizon,
                second=args.second,
            )
            print(
                f"{t.name}: catc {row.catc} {row.catc_len} {_t(row.catc_time)}s (cpu {_t(row.catc_cpu)}); ENHSP "
                f"{row.enhsp} {row.enhsp_len} {_t(row.enhsp_time)}s (cpu {_t(row.enhsp_cpu)})"
                + (f"; SMT {row.smt} {row.smt_len} {_t(row.smt_time)}s" if args.smt else "")
                + (f"; {row.second_name} {row.second} {row.second_len} {_t(row.second_time)}s" if args.second else ""),
                file=sys.stderr,
                flush=True,
            )
            rows.append(row)
    print(
        markdown(rows, "python benchmarks/planning_corpus.py " + " ".join(argv or sys.argv[1:]), args.smt, args.second)
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
