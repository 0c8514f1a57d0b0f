"""The planning corpus (issue 27): task families of growing plan length, each with its
shortest plan's length counted by hand, run by catc beside ENHSP (and optionally a second
planner), every plan checked by unified-planning's validator; ``catc bench --corpus planning``
and ``benchmarks/planning_corpus.py`` (a thin wrapper) print its table.

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
* rover-k (numeric, IPC 2023 rover's actions on a line of k + 1 waypoints, soil and rock at
  the far end, energy 40): 2k + 4 + ⌈(16k − 32)/20⌉ (:func:`rover`).
* hydropower-T-u (numeric, IPC 2023 hydropower's actions, T hours on a demand curve of our
  own, profit 8u): T − 1 + 2u (:func:`hydropower`).
* unsolvable tasks: blocks-cycle-n (a cyclic goal: relaxed reachability cannot refute it, the
  reachable states can), counters-tight-n (max_int = n − 2: n strictly increasing values do not
  fit; the relaxation cannot tell), farmland-short-n (n − 1 workers for n farms).

For each task (:func:`run`): unified-planning's reader and catc's import (timed), ``catc solve
--sequential --strategy search``, optionally the SMT search alone, ENHSP ``-planner opt-hrmax``
(A* with h^max: optimal, the like-for-like baseline) in its own process under the same timeout,
optionally a second planner (:func:`_second`); every plan replayed by unified-planning's
``SequentialPlanValidator`` on the original PDDL. :func:`markdown` writes the table, the
per-band medians (:func:`medians`) and the command. tests/test_planning_corpus.py checks the hand
counts of the small members by a breadth-first search of its own.
"""

from __future__ import annotations

import os
import re
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from catc.bench import corpus

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


ROVER = """(define (domain rover)
 (:requirements :typing :numeric-fluents)
 (:types rover waypoint store lander)
 (:predicates (at ?x - rover ?y - waypoint) (at_lander ?l - lander ?y - waypoint)
  (can_traverse ?r - rover ?x - waypoint ?y - waypoint) (visible ?x - waypoint ?y - waypoint)
  (in_sun ?w - waypoint) (store_of ?s - store ?r - rover) (empty ?s - store) (full ?s - store)
  (equipped_for_soil_analysis ?r - rover) (equipped_for_rock_analysis ?r - rover)
  (at_soil_sample ?w - waypoint) (at_rock_sample ?w - waypoint)
  (have_soil_analysis ?r - rover ?w - waypoint) (have_rock_analysis ?r - rover ?w - waypoint)
  (communicated_soil_data ?w - waypoint) (communicated_rock_data ?w - waypoint))
 (:functions (energy ?r - rover) (recharges))
 (:action navigate :parameters (?x - rover ?y - waypoint ?z - waypoint)
  :precondition (and (can_traverse ?x ?y ?z) (at ?x ?y) (visible ?y ?z) (>= (energy ?x) 8))
  :effect (and (decrease (energy ?x) 8) (not (at ?x ?y)) (at ?x ?z)))
 (:action recharge :parameters (?x - rover ?w - waypoint)
  :precondition (and (at ?x ?w) (in_sun ?w) (<= (energy ?x) 80))
  :effect (and (increase (energy ?x) 20) (increase (recharges) 1)))
 (:action sample_soil :parameters (?x - rover ?s - store ?p - waypoint)
  :precondition (and (at ?x ?p) (>= (energy ?x) 3) (at_soil_sample ?p) (equipped_for_soil_analysis ?x)
   (store_of ?s ?x) (empty ?s))
  :effect (and (not (empty ?s)) (full ?s) (have_soil_analysis ?x ?p) (not (at_soil_sample ?p))
   (decrease (energy ?x) 3)))
 (:action sample_rock :parameters (?x - rover ?s - store ?p - waypoint)
  :precondition (and (at ?x ?p) (>= (energy ?x) 5) (at_rock_sample ?p) (equipped_for_rock_analysis ?x)
   (store_of ?s ?x) (empty ?s))
  :effect (and (not (empty ?s)) (full ?s) (have_rock_analysis ?x ?p) (not (at_rock_sample ?p))
   (decrease (energy ?x) 5)))
 (:action drop :parameters (?x - rover ?y - store)
  :precondition (and (store_of ?y ?x) (full ?y))
  :effect (and (not (full ?y)) (empty ?y)))
 (:action communicate_soil_data :parameters (?r - rover ?l - lander ?p - waypoint ?x - waypoint ?y - waypoint)
  :precondition (and (at ?r ?x) (at_lander ?l ?y) (have_soil_analysis ?r ?p) (visible ?x ?y) (>= (energy ?r) 4))
  :effect (and (communicated_soil_data ?p) (decrease (energy ?r) 4)))
 (:action communicate_rock_data :parameters (?r - rover ?l - lander ?p - waypoint ?x - waypoint ?y - waypoint)
  :precondition (and (at ?r ?x) (at_lander ?l ?y) (have_rock_analysis ?r ?p) (visible ?x ?y) (>= (energy ?r) 4))
  :effect (and (communicated_rock_data ?p) (decrease (energy ?r) 4))))
"""


def rover(k: int, energy: int = 40) -> str:
    """IPC 2023 numeric rover's actions (IPC 2002 Rovers with energy: navigate 8, sample soil 3,
    rock 5, communicate 4, recharge +20 in the sun at energy ≤ 80; the cameras left out, and
    the ``available``/``channel_free`` pair that the IPC 2023 encoding deletes and adds again
    in one effect left out too: ENHSP does not apply PDDL's delete-before-add rule to it), one
    rover at w0 of a line w0 … wk (all in the sun), the lander at w0 seen from w1 only, soil
    and rock at wk, one store.

    Shortest plan, by hand: the rover must reach wk (k navigates) and then a waypoint the
    lander is seen from, w1 (k − 1 more); both samples, and a drop between them (the one store
    is full after the first sample, and only a drop empties it); both communications. That
    takes 16k + 8 energy (8 a navigate, 3 + 5 + 4 + 4), and only a recharge adds any, 20 each:
    r = ⌈(16k + 8 − energy)/20⌉ recharges at least (0 if negative). So 2k + 4 + r actions, and
    that many suffice: recharging whenever the next action costs more than is left (then
    energy < 8 ≤ 80, so the recharge may fire) recharges at most r times (after its last
    recharge less than 20 + that action's cost was left for the actions still to come)."""
    ws = [f"w{i}" for i in range(k + 1)]
    edges = " ".join(
        f"(can_traverse r0 w{i} w{i + 1}) (can_traverse r0 w{i + 1} w{i}) (visible w{i} w{i + 1}) (visible w{i + 1} w{i})"
        for i in range(k)
    )
    sun = " ".join(f"(in_sun {w})" for w in ws)
    return (
        f"(define (problem rover-{k}) (:domain rover)\n (:objects r0 - rover {' '.join(ws)} - waypoint s0 - store"
        f" l0 - lander)\n (:init (at r0 w0) (at_lander l0 w0) {edges} {sun} (store_of s0 r0) (empty s0)"
        f" (equipped_for_soil_analysis r0) (equipped_for_rock_analysis r0) (at_soil_sample w{k})"
        f" (at_rock_sample w{k}) (= (energy r0) {energy}) (= (recharges) 0))\n"
        f" (:goal (and (communicated_soil_data w{k}) (communicated_rock_data w{k}))))\n"
    )


def rover_optimal(k: int, energy: int = 40) -> int:
    return 2 * k + 4 + max(0, -((energy - 16 * k - 8) // 20))


HYDROPOWER = """(define (domain hydropower)
 (:requirements :typing :numeric-fluents)
 (:types time turnvalue)
 (:predicates (timenow ?t - time) (before ?t1 - time ?t2 - time) (demand ?t - time ?n - turnvalue))
 (:functions (funds) (stored_units) (stored_capacity) (value ?n - turnvalue))
 (:action advance_time :parameters (?t1 - time ?t2 - time)
  :precondition (and (timenow ?t1) (before ?t1 ?t2))
  :effect (and (timenow ?t2) (not (timenow ?t1))))
 (:action pump_water_up :parameters (?t1 - time ?n1 - turnvalue)
  :precondition (and (timenow ?t1) (>= (funds) (* 1.05 (value ?n1))) (>= (stored_capacity) 1) (demand ?t1 ?n1))
  :effect (and (increase (stored_units) 1) (decrease (stored_capacity) 1) (decrease (funds) (* 1.05 (value ?n1)))))
 (:action generate :parameters (?t1 - time ?n1 - turnvalue)
  :precondition (and (timenow ?t1) (>= (stored_units) 1) (demand ?t1 ?n1))
  :effect (and (decrease (stored_units) 1) (increase (stored_capacity) 1) (increase (funds) (value ?n1)))))
"""


def hydropower(times: int, units: int) -> str:
    """IPC 2023 hydropower's actions (Coles, Fox & Long 2013: pump water up at 1.05 times the
    hour's price, generate at the price, advance the clock along ``before``) on a demand curve
    of our own: price 1 at t0, 2 in between, 10 at the last hour t(T−1); capacity ``units``,
    funds 100, the goal funds ≥ 100 + 8·units.

    Shortest plan, by hand: 2·units + T − 1. Every generate spends a unit pumped before it
    (none stored at first), each pump costs at least 1.05, so a plan's profit is at most
    Σ over its generates of (price − 1.05): 8.95 each at the last hour, 0.95 elsewhere. A plan
    that never reaches the last hour (T − 1 advances, one hour each) needs ⌈8·units/0.95⌉ >
    8·units generates and as many pumps, longer; one that does needs ⌈8·units/8.95⌉ = units
    generates (units ≤ 9) and as many pumps: units pumps at t0, T − 1 advances, units generates
    at the last hour reach it."""
    ts = [f"t{i}" for i in range(times)]
    price = [1] + [2] * (times - 2) + [10]
    demand = " ".join(f"(demand t{i} n{p})" for i, p in enumerate(price))
    before = " ".join(f"(before t{i} t{i + 1})" for i in range(times - 1))
    return (
        f"(define (problem hydropower-{times}-{units}) (:domain hydropower)\n"
        f" (:objects n1 n2 n10 - turnvalue {' '.join(ts)} - time)\n"
        f" (:init (= (value n1) 1) (= (value n2) 2) (= (value n10) 10) {demand} (timenow t0) {before}"
        f" (= (stored_units) 0) (= (stored_capacity) {units}) (= (funds) 100))\n"
        f" (:goal (and (>= (funds) {100 + 8 * units}))))\n"
    )


def counters_tight(n: int) -> str:
    text = corpus.counters_problem(n)
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
    if wheel is None:
        raise RuntimeError("the planning corpus reads unified-planning's test PDDL: pip install 'catc-lang[up]'")
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
    for k in (2, 4, 6, 8, 10, 14, 16):
        out.append(Task(f"rover-{k}", "rover", ROVER, rover(k), rover_optimal(k)))
    for times, units in ((6, 2), (10, 3), (16, 4), (24, 4), (30, 5), (36, 6)):
        out.append(
            Task(
                f"hydropower-{times}-{units}", "hydropower", HYDROPOWER, hydropower(times, units), times - 1 + 2 * units
            )
        )
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


def _child_env() -> dict[str, str]:
    """This process's environment, with the folder holding this catc first on PYTHONPATH (so
    that the child imports the same tree whether catc is installed or on sys.path)."""
    env = dict(os.environ)
    root = str(Path(__file__).resolve().parents[2])
    env["PYTHONPATH"] = os.pathsep.join([root, *filter(None, [env.get("PYTHONPATH")])])
    return env


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
            [sys.executable, "-m", "catc.bench.planning", row.second_name, str(d), str(p)],
            capture_output=True,
            text=True,
            timeout=timeout,
            env=_child_env(),
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


def run(
    task: Task,
    work: Path,
    timeout: float,
    *,
    smt: bool,
    enhsp: bool,
    horizon: int,
    second: bool = False,
    catc: bool = True,
) -> Row:
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
    if catc:
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


def select(only: Sequence[str] = (), *, exact: bool = True) -> list[Task]:
    """The tasks named in ``only`` (a task's name or its family), every task when empty; with
    ``exact=False`` (``catc bench``'s ``--only``) a task whose name contains one of them too."""
    return [
        t
        for t in tasks()
        if not only or t.name in only or t.family in only or (not exact and any(o in t.name for o in only))
    ]


def progress(row: Row, smt: bool = False, second: bool = False) -> str:
    """One line on a finished task (the script prints it on stderr as each task ends)."""
    t = row.task
    return (
        f"{t.name}: catc {row.catc} {row.catc_len} {_t(row.catc_time)}s (cpu {_t(row.catc_cpu)}); ENHSP "
        f"{row.enhsp} {row.enhsp_len} {_t(row.enhsp_time)}s (cpu {_t(row.enhsp_cpu)})"
        + (f"; SMT {row.smt} {row.smt_len} {_t(row.smt_time)}s" if smt else "")
        + (f"; {row.second_name} {row.second} {row.second_len} {_t(row.second_time)}s" if second else "")
    )


def run_tasks(
    chosen: Sequence[Task],
    timeout: float,
    *,
    smt: bool = False,
    enhsp: bool = True,
    horizon: int = 200,
    second: bool = False,
    catc: bool = True,
    work: Path | None = None,
    log: Callable[[str], None] | None = None,
) -> list[Row]:
    """:func:`run` on each task in turn, its PDDL written into ``work`` (a temporary folder when
    None); ``log`` gets :func:`progress`'s line as each task ends."""
    import unified_planning.shortcuts as shortcuts

    shortcuts.get_environment().credits_stream = None
    rows = []
    with tempfile.TemporaryDirectory(prefix="catc-planning-") as tmp:
        folder = work if work is not None else Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        for t in chosen:
            row = run(t, folder, timeout, smt=smt, enhsp=enhsp, horizon=horizon, second=second, catc=catc)
            if log is not None:
                log(progress(row, smt, second))
            rows.append(row)
    return rows


def jsonable(rows: Sequence[Row]) -> list[dict[str, Any]]:
    """The rows for ``--save-json``: the task by name, family and hand count, the figures as measured."""
    out = []
    for r in rows:
        d: dict[str, Any] = {"task": r.task.name, "family": r.task.family, "hand_count": r.task.optimal}
        d |= {k: v for k, v in vars(r).items() if k != "task"}
        out.append(d)
    return out


def _child_main(argv: list[str]) -> int:
    return _second_child(*argv)


if __name__ == "__main__":  # the second planner's child process (:func:`_second`)
    raise SystemExit(_child_main(sys.argv[1:]))
