"""The counting-plus-landmarks bound of A* (:mod:`catc.semantics.search.landmarks`): never above the
true distance to the goal (breadth first over the explicit state graph, an independent count)
on random small tasks and on hydropower, and the hydropower optimum (T − 1 + 2·units, argued
by hand in benchmarks/planning_corpus.py) at the start where h^max and the counting bound
alone see only their parts."""

from __future__ import annotations

from collections import deque
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from catc.api import loads
from catc.semantics.search import _Atoms, _Counting, _inline_statics, _Task
from catc.semantics.search.landmarks import LandmarkCounting


def _parts(inst: Any) -> tuple[_Task, LandmarkCounting]:
    inst = _inline_statics(inst)
    task = _Task(inst)
    atoms = _Atoms(task, inst)
    task.counting = _Counting.build(task, atoms, inst)
    return task, LandmarkCounting(task, atoms, inst)


def _distances(task: _Task, limit: int = 20_000) -> tuple[set[Any], dict[Any, int]]:
    """Every reachable state and, for those that can reach the goal, their distance to it
    (breadth first backwards over the explicit graph)."""
    succ: dict[Any, list[Any]] = {}
    seen, todo = {task.init}, [task.init]
    while todo:
        s = todo.pop()
        succ[s] = [t for _, t in task.successors(s)]
        for t in succ[s]:
            if t not in seen:
                seen.add(t)
                todo.append(t)
        assert len(seen) <= limit
    pred: dict[Any, list[Any]] = {s: [] for s in seen}
    for s, ts in succ.items():
        for t in ts:
            pred[t].append(s)
    dist = {s: 0 for s in seen if task.is_goal(s)}
    queue = deque(dist)
    while queue:
        t = queue.popleft()
        for s in pred[t]:
            if s not in dist:
                dist[s] = dist[t] + 1
                queue.append(s)
    return seen, dist


def _check(task: _Task, lm: LandmarkCounting) -> None:
    seen, dist = _distances(task)
    for s in seen:
        h = lm.h(s)
        if h is None:
            assert s not in dist, (s, dist[s])  # a dead end it proves is one
        elif s in dist:
            assert h <= dist[s], (s, h, dist[s])


# ---------------------------------------------------------------- random small tasks

_BOOLS = ["b0", "b1", "b2", "b3"]


def _literal(draw: Any, bools: list[str]) -> str:
    b = draw(st.sampled_from(bools))
    return b if draw(st.booleans()) else f"(not {b})"


@st.composite
def _tasks(draw: Any) -> str:
    nb = draw(st.integers(2, 4))
    bools = _BOOLS[:nb]
    hi = draw(st.integers(2, 4))
    morphisms = []
    for k in range(draw(st.integers(2, 6))):
        pre = [_literal(draw, bools) for _ in range(draw(st.integers(0, 2)))]
        if draw(st.booleans()):
            pre.append(f"({draw(st.sampled_from(['>=', '<=']))} x {draw(st.integers(0, hi))})")
        eff = []
        for b in draw(st.lists(st.sampled_from(bools), max_size=2, unique=True)):
            eff.append(f"(assign {b} {draw(st.sampled_from(['true', 'false']))})")
        if draw(st.booleans()) or not eff:
            eff.append(f"({draw(st.sampled_from(['increase', 'decrease']))} x {draw(st.integers(1, 2))})")
        p = f":precondition (and {' '.join(pre)}) " if pre else ""
        morphisms.append(f"  (:morphism m{k} {p}:effect (and {' '.join(eff)}))")
    goal = [_literal(draw, bools) for _ in range(draw(st.integers(1, 2)))]
    if draw(st.booleans()):
        goal.append(f"(>= x {draw(st.integers(1, hi))})")
    init = [b for b in bools if draw(st.booleans())]
    x0 = draw(st.integers(0, hi))
    resources = " ".join(f"({b} bool)" for b in bools)
    return (
        "(define (domain d) (:requirements :numeric)\n"
        f"  (:resources {resources} (x int :bounds (0 {hi})))\n" + "\n".join(morphisms) + ")\n"
        f"(define (problem p) (:domain d) (:init {' '.join(init)} (= x {x0})) (:goal (and {' '.join(goal)}))"
        " (:horizon 12))\n"
    )


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_tasks())
def test_the_bound_never_exceeds_the_true_distance_on_random_tasks(text):
    task, lm = _parts(loads({"d.cat": text}, "d.cat").instance)
    _check(task, lm)


def test_a_random_task_by_hand():
    """b0 is needed by the only morphism making the goal b1 true and is made true only by m0,
    which needs x ≥ 2 (two increments from 0): four steps (inc, inc, m0, m1), and the bound
    sees the landmarks b0 (m0) and b1 (m1) plus the counting of x: two increments."""
    text = """
(define (domain d) (:requirements :numeric)
  (:resources (b0 bool) (b1 bool) (x int :bounds (0 3)))
  (:morphism inc :precondition (<= x 2) :effect (increase x 1))
  (:morphism m0 :precondition (>= x 2) :effect (assign b0 true))
  (:morphism m1 :precondition b0 :effect (assign b1 true)))
(define (problem p) (:domain d) (:init (= x 0)) (:goal b1) (:horizon 12))
"""
    task, lm = _parts(loads({"d.cat": text}, "d.cat").instance)
    _, dist = _distances(task)
    assert dist[task.init] == 4
    h = lm.h(task.init)
    assert h is not None and 2 <= h <= 4
    _check(task, lm)


# ---------------------------------------------------------------- hydropower


def _hydropower(tmp_path: Any, times: int, units: int) -> Any:
    pytest.importorskip("unified_planning")
    from test_search import _corpus_script, _read

    from catc.frontend.up_import import up_to_instance

    mod = _corpus_script()
    (tmp_path / "d.pddl").write_text(mod.HYDROPOWER)
    (tmp_path / "p.pddl").write_text(mod.hydropower(times, units))
    return up_to_instance(_read(tmp_path / "d.pddl", tmp_path / "p.pddl"))[0]


@pytest.mark.parametrize(("times", "units"), [(4, 1), (6, 2)])
def test_hydropower_start_is_the_hand_count(tmp_path, times, units):
    """T − 1 + 2·units (the generator's hand argument): the clock's advances (the relevance
    row of the last hour, in the case that reaches it) plus the pumps and generates (the
    counting rows); without the last hour every trade earns 0.95 at most, far more trades."""
    inst = _hydropower(tmp_path, times, units)
    task, lm = _parts(inst)
    assert lm.h(task.init) == times - 1 + 2 * units
    assert (task.h(task.init, 100) or 0) < times - 1 + 2 * units  # the other bounds see less
    # so A* takes it (search() builds it the same way), and its start is the optimum
    folded = _inline_statics(inst)
    task = _Task(folded)
    atoms = _Atoms(task, folded)
    task.counting = _Counting.build(task, atoms, folded)
    task.landmarks = LandmarkCounting.build(task, atoms, folded)
    assert task.landmarks is not None and task.h(task.init, 100) == times - 1 + 2 * units


def test_without_numeric_goals_a_star_does_not_take_it():
    text = """
(define (domain d) (:requirements :numeric)
  (:resources (b0 bool) (b1 bool) (x int :bounds (0 3)))
  (:morphism inc :precondition (<= x 2) :effect (increase x 1))
  (:morphism m0 :precondition (>= x 2) :effect (assign b0 true))
  (:morphism m1 :precondition b0 :effect (assign b1 true)))
(define (problem p) (:domain d) (:init (= x 0)) (:goal b1) (:horizon 12))
"""
    inst = _inline_statics(loads({"d.cat": text}, "d.cat").instance)
    task = _Task(inst)
    assert LandmarkCounting.build(task, _Atoms(task, inst), inst) is None


def test_hydropower_states_near_the_start_are_bounded_by_their_distance(tmp_path):
    """Every state within 3 steps of the start of hydropower-4-1, its bound against its
    distance to the goal found breadth first from it (forward, at most 12 steps)."""
    task, lm = _parts(_hydropower(tmp_path, 4, 1))
    near = {task.init}
    frontier = [task.init]
    for _ in range(3):
        frontier = [t for s in frontier for _, t in task.successors(s) if t not in near]
        near |= set(frontier)
    for s in near:
        dist: int | None = None
        level, seen = [s], {s}
        for d in range(13):
            if any(task.is_goal(x) for x in level):
                dist = d
                break
            nxt = []
            for x in level:
                for _, t in task.successors(x):
                    if t not in seen:
                        seen.add(t)
                        nxt.append(t)
            level = nxt
        h = lm.h(s)
        if dist is not None:
            assert h is not None and h <= dist, (s, h, dist)
