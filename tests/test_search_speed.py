"""The forward search's fast paths (issue 27) against the plain algorithms they replace, written
out here as references: the incremental h^max layers (morphisms re-tested and re-applied only
where what they read changed, constant shifts applied per resource), h_add by Dijkstra's order
with precondition counters, the counting bound's simplex on whole-number rows, and the classical
fast path's compiled successors and layers. Each must give the same values on every state the
search can reach in small corpus tasks (and, for the simplex, on seeded random programs): the
search's answers and plans then cannot move."""

from __future__ import annotations

import importlib.util
import random
import sys
from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("unified_planning")

from unified_planning.io import PDDLReader
from unified_planning.shortcuts import get_environment

from catc.frontend.up_import import up_to_instance
from catc.semantics.search import _Atoms, _Counting, _Dual, _inline_statics, _Strips, _Task
from catc.semantics.search.common import _FAR
from catc.semantics.search.terms import _join, _lo_add, _point

ROOT = Path(__file__).resolve().parents[1]


def _corpus() -> Any:
    spec = importlib.util.spec_from_file_location("planning_corpus", ROOT / "benchmarks" / "planning_corpus.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("planning_corpus", mod)
    spec.loader.exec_module(mod)
    return mod


def _instance(tmp_path: Path, name: str) -> Any:
    (task,) = [t for t in _corpus().tasks() if t.name == name]
    (tmp_path / "d.pddl").write_text(task.domain)
    (tmp_path / "p.pddl").write_text(task.problem)
    get_environment().credits_stream = None
    return up_to_instance(PDDLReader().parse_problem(str(tmp_path / "d.pddl"), str(tmp_path / "p.pddl")))[0]


def _states(task: Any, limit: int) -> list[Any]:
    """Up to ``limit`` reachable states, breadth first."""
    seen = {task.init: None}
    todo = [task.init]
    while todo and len(seen) < limit:
        nxt = []
        for s in todo:
            for _, t in task.successors(s):
                if t not in seen and len(seen) < limit:
                    seen[t] = None
                    nxt.append(t)
        todo = nxt
    return list(seen)


# ---------------------------------------------------------------- references: the plain algorithms


def _ref_layer(task: _Task, rt: tuple[Any, ...], fired: set[int], first: list[int] | None, layer: int) -> Any:
    """Every morphism tested and applied, each effect on its own (the code before issue 27)."""
    changed = False
    new = list(rt)
    for a_i, a in enumerate(task.actions):
        if a_i in fired or not all(f(rt)[0] for f in a.rpre):
            continue
        if first is not None and first[a_i] < 0:
            first[a_i] = layer
        if a.constant:
            fired.add(a_i)
        posts = []
        for i, mode, terms in a.reffects:
            if mode == "assign":
                post = terms[0][1](rt)
            else:
                post = rt[i]
                for sign, f in terms:
                    d = f(rt)
                    if sign < 0:
                        d = (None if d[1] is None else -d[1], None if d[0] is None else -d[0])
                    post = (_lo_add(post[0], d[0]), _lo_add(post[1], d[1]))
            posts.append((i, post))
        for i, d in a.shifts:
            posts.append((i, (_lo_add(rt[i][0], d), _lo_add(rt[i][1], d))))
        for i, raw in posts:
            kind = task.kinds[i]
            post = task._cut(i, raw) if kind == "number" else raw
            if post is None:
                continue
            joined = _join(new[i], post, kind)
            if joined != new[i]:
                new[i] = joined
                changed = True
    return new if changed else None


def _ref_dead(task: _Task, r: list[Any]) -> bool:
    fired: set[int] = set()
    while True:
        rt = tuple(r)
        if all(f(rt)[0] for f in task.rgoal):
            return False
        new = _ref_layer(task, rt, fired, None, 0)
        if new is None:
            return True
        for i, kind in enumerate(task.kinds):
            if kind == "number" and new[i] != rt[i]:
                lo = None if new[i][0] != rt[i][0] else new[i][0]
                hi = None if new[i][1] != rt[i][1] else new[i][1]
                new[i] = task._cut(i, (lo, hi))
        r = new


def _ref_hmax(task: _Task, s: tuple[Any, ...], cap: int, first: list[int] | None) -> int | None:
    r: list[Any] = [_point(v, k) for v, k in zip(s, task.kinds)]
    fired: set[int] = set()
    for layer in range(cap):
        rt = tuple(r)
        if all(f(rt)[0] for f in task.rgoal):
            return layer
        new = _ref_layer(task, rt, fired, first, layer)
        if new is None:
            return None
        r = new
    return None if _ref_dead(task, r) else cap


def _ref_hadd(atoms: _Atoms, s: tuple[Any, ...]) -> int:
    """The fixpoint by sweeps over all morphisms until nothing changes, in Fractions."""
    cost: list[Any] = [_FAR] * len(atoms.kind)
    values = []
    for terms, k, _strict in atoms.linear:
        v: Any = k
        for i, w in terms:
            v += w * s[i]
        values.append(v)
    for atom, (what, j) in enumerate(atoms.kind):
        if what == "linear" and (values[j] > 0 or (values[j] == 0 and not atoms.linear[j][2])):
            cost[atom] = 0
    for atom, test in atoms.tests:
        try:
            if test(s):
                cost[atom] = 0
        except ArithmeticError:
            pass
    rates = list(atoms.rates)
    for a_i in atoms.varying:
        rates[a_i] = atoms._rates_at(a_i, s)
    changed = True
    while changed:
        changed = False
        for a_i, pre in enumerate(atoms.pre):
            c = 1 + sum(cost[q] for q in pre)
            if c >= _FAR:
                continue
            for q in atoms.adds[a_i]:
                if c < cost[q]:
                    cost[q], changed = c, True
            for q, j, rate in rates[a_i]:
                need = -values[j]
                reps = need // rate + 1 if atoms.linear[j][2] else -(-need // rate)
                r = c - 1 + max(int(reps), 1)
                if r < cost[q]:
                    cost[q], changed = r, True
    return int(min(sum(cost[q] for q in atoms.goal), _FAR))


def _ref_dual(matrix: list[list[Fraction]], n: int) -> Any:
    """The simplex on Fraction rows (the code before issue 27), with its kept basis."""
    m = len(matrix)
    rows = [list(row) + [Fraction(int(i == k)) for k in range(m)] + [Fraction(1)] for i, row in enumerate(matrix)]
    basis = [n + i for i in range(m)]

    def solve(r: list[Fraction], pivots: int) -> Fraction | None:
        cost = list(r) + [Fraction(0)] * m
        z = [-c for c in cost] + [Fraction(0)]
        for i, b in enumerate(basis):
            if cost[b]:
                z = [x + cost[b] * y for x, y in zip(z, rows[i])]
        for _ in range(pivots):
            j = next((j for j in range(n + m) if z[j] < 0), None)
            if j is None:
                break
            best = None
            for i, row in enumerate(rows):
                if row[j] > 0:
                    key = (row[-1] / row[j], basis[i], i)
                    if best is None or key < best:
                        best = key
            if best is None:
                return None
            i = best[2]
            prow = [x / rows[i][j] for x in rows[i]]
            rows[i] = prow
            for k, row in enumerate(rows):
                if k != i and row[j]:
                    rows[k] = [x - row[j] * y for x, y in zip(row, prow)]
            z = [x - z[j] * y for x, y in zip(z, prow)]
            basis[i] = j
        return z[-1]

    return solve


# ---------------------------------------------------------------- the comparisons


def _layers_equal(task: _Task, s: tuple[Any, ...], depth: int) -> None:
    """The layers themselves, one by one, both ways (not only the layer the goal holds in)."""
    r: list[Any] = [_point(v, k) for v, k in zip(s, task.kinds)]
    fired: set[int] = set()
    ref_fired: set[int] = set()
    enabled = [0] * len(task.actions)
    dirty: set[int] | None = None
    shifts: dict[int, list[Any]] = {}
    for layer in range(depth):
        rt = tuple(r)
        step = task._layer(rt, fired, None, layer, enabled, dirty, shifts)
        want = _ref_layer(task, rt, ref_fired, None, layer)
        assert (step is None) == (want is None), (s, layer)
        if step is None:
            return
        assert step[0] == want, (s, layer)
        assert step[1] == {i for i in range(len(rt)) if want[i] != rt[i]}
        r, dirty = step


def _bounded_shifts() -> Any:
    """x in [0, 10] moved by +2, +5 and −3, y = y + x (an effect that reads another number),
    z := x + y (an assignment of a term): the shifts meet the bounds exactly (d = H − lo at
    x = 5), and effects that are not constant shifts are re-applied when what they read moves."""
    from unified_planning.shortcuts import GE, LE, Fluent, InstantaneousAction, IntType, Plus, Problem

    x, y, z = Fluent("x", IntType(0, 10)), Fluent("y", IntType(0, 60)), Fluent("z", IntType(0, 80))
    p = Problem("shifts")
    for f, v in ((x, 0), (y, 0), (z, 0)):
        p.add_fluent(f, default_initial_value=v)
    for name, d in (("up2", 2), ("up5", 5)):
        a = InstantaneousAction(name)
        a.add_precondition(LE(x(), 10 - d))
        a.add_increase_effect(x(), d)
        p.add_action(a)
    down = InstantaneousAction("down3")
    down.add_precondition(GE(x(), 3))
    down.add_decrease_effect(x(), 3)
    p.add_action(down)
    gather = InstantaneousAction("gather")
    gather.add_precondition(LE(y(), 50))
    gather.add_increase_effect(y(), x())
    p.add_action(gather)
    total = InstantaneousAction("total")
    total.add_precondition(GE(y(), 4))
    total.add_effect(z(), Plus(x(), y()))
    p.add_action(total)
    p.add_goal(GE(z(), 40))
    return up_to_instance(p)[0]


def test_the_incremental_layers_equal_the_plain_ones_on_a_task_with_bounds_and_terms():
    inst = _inline_statics(_bounded_shifts())
    task = _Task(inst)
    assert sorted(d for a in task.actions for _, d in a.shifts) == [-3, 2, 5]
    assert any(a.reffects and a.ereads for a in task.actions)
    states = _states(task, 200)
    assert len(states) > 20
    for s in states:
        _layers_equal(task, s, 8)
        for cap in (1, 3, 30):
            assert task.hmax(s, cap) == _ref_hmax(task, s, cap, None)


NUMERIC = ["rover-4", "hydropower-6-2", "hydropower-10-3", "farmland-5", "counters-5", "sailing-far-4"]


@pytest.mark.parametrize("name", NUMERIC)
def test_the_fast_heuristics_equal_the_plain_ones_on_reachable_states(tmp_path, name):
    inst = _inline_statics(_instance(tmp_path, name))
    task = _Task(inst)
    atoms = _Atoms(task, inst)
    task.counting = _Counting.build(task, atoms, inst)
    states = _states(task, 150)
    assert len(states) > 20
    dead_or_capped = 0
    for s in states:
        for cap in (1, 2, 4, 60):
            first: list[int] = [-1] * len(task.actions)
            ref_first: list[int] = [-1] * len(task.actions)
            got, want = task._hmax(s, cap, first), _ref_hmax(task, s, cap, ref_first)
            assert got == want and first == ref_first, (s, cap)
            dead_or_capped += want is None or want == cap
        assert atoms.hadd(s) == _ref_hadd(atoms, s), s
        _layers_equal(task, s, 6)
    assert dead_or_capped  # the cap and the widened relaxation were exercised


def test_the_shifts_per_resource_meet_bounds_as_the_plain_layer_does(tmp_path):
    """hydropower's stored units and capacity are bounded (inferred): shifts cut at the bounds,
    some of them empty, on the relaxed states of several layers."""
    inst = _inline_statics(_instance(tmp_path, "hydropower-6-2"))
    task = _Task(inst)
    assert any(a.shifts for a in task.actions)
    assert any(lo is not None or hi is not None for lo, hi in task.bounds)
    for s in _states(task, 60):
        for cap in range(1, 12):
            assert task.hmax(s, cap) == _ref_hmax(task, s, cap, None)


def test_the_whole_number_simplex_equals_the_fraction_one():
    rng = random.Random(27)
    for _ in range(60):
        rows, cols = rng.randint(1, 6), rng.randint(1, 6)
        matrix = [[Fraction(rng.randint(-4, 4), rng.randint(1, 3)) for _ in range(cols)] for _ in range(rows)]
        fast, ref = _Dual(matrix, cols), _ref_dual(matrix, cols)
        for _ in range(5):  # warm starts: the kept bases must stay the same too
            r = [Fraction(rng.randint(-5, 5), rng.randint(1, 4)) for _ in range(cols)]
            pivots = rng.choice([1, 2, 200])
            assert fast.solve(r, pivots) == ref(r, pivots)


@pytest.mark.parametrize("name", ["gripper-4", "ferry-4", "blocks-4", "blocks-cycle-3"])
def test_the_compiled_classical_path_equals_its_loops(tmp_path, name):
    inst = _instance(tmp_path, name)
    fast = _Strips(inst)
    plain = _Strips(inst)
    plain._succ = plain._apply = None  # the loops over the mask tuples
    assert fast._succ is not None
    states = _states(plain, 400)
    assert len(states) > 20
    for s in states:
        assert fast.successors(s) == plain.successors(s)
        for cap in (1, 3, 50):
            assert fast.h(s, cap) == plain.h(s, cap)
