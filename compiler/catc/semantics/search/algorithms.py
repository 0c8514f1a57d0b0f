"""The searches: greedy best-first on h_add, A* on the admissible heuristic, the plan's
neighbourhood (:func:`_improve`), and :func:`search`, which runs them in turns."""

from __future__ import annotations

import heapq
import itertools
import time
from collections.abc import Callable, Generator
from typing import Any

from catc import ir
from catc.semantics.plan import Activation, Plan
from catc.semantics.search.atoms import _Atoms
from catc.semantics.search.common import _FAR, SearchResult, SearchStatus, State, _Unsupported
from catc.semantics.search.counting import _Counting
from catc.semantics.search.landmarks import LandmarkCounting
from catc.semantics.search.strips import _Strips
from catc.semantics.search.task import _inline_statics, _Task

#: The most states the greedy phase stores before it gives way to A* (with no deadline it
#: would otherwise run as long as the horizon allows; A* also prunes proven dead ends).
GREEDY_STATES = 200_000


def search(
    inst: ir.Instance,
    horizon: int,
    *,
    deadline: float | None = None,
    greedy: bool = True,
    prove: bool = True,
    landmarks: bool = True,
) -> SearchResult:
    """A composition of at most ``horizon`` steps, or a proof that there is none; ``deadline``
    is a ``time.monotonic()`` instant.

    With ``greedy`` a greedy best-first search guided by h_add looks for a composition (fast,
    not necessarily shortest) taking turns with A* (with ``prove``); if A* answers first, its
    answer is the answer; if the greedy search does, A* goes on below its composition's length,
    and when it finds none shorter the greedy one is proven shortest. When the time runs out
    first the greedy composition is the answer, ``shortest`` False.
    Without ``greedy``, A* alone (the shortest composition); without ``prove``, the greedy
    search alone (A* only when it found nothing). Without ``landmarks``, A*'s heuristic leaves
    out the counting-plus-landmarks bound (:mod:`catc.semantics.search.landmarks`; for measurements)."""
    task: Any
    try:
        task = _Strips(inst)
    except _Unsupported:
        try:
            inst = _inline_statics(inst)
            task = _Task(inst)
        except _Unsupported as why:
            return SearchResult(SearchStatus.UNSUPPORTED, reason=str(why))
    atoms = None if isinstance(task, _Strips) else _Atoms(task, inst)
    if atoms is not None:
        task.counting = _Counting.build(task, atoms, inst)
        task.landmarks = LandmarkCounting.build(task, atoms, inst) if landmarks else None
    t0 = time.monotonic()
    h0 = task.h(task.init, horizon + 1)
    if h0 is None:
        return SearchResult(SearchStatus.NONE, final=True, reason="a dead end from the initial state")
    if h0 > horizon:
        return SearchResult(SearchStatus.NONE, reason=f"no composition within {horizon} steps (h^max)")
    if not greedy:
        return _astar(task, horizon, deadline)
    hadd: Callable[[Any], Any] = task.hadd if atoms is None else atoms.hadd
    if atoms is not None and task.counting is not None:
        hadd = _counting_first(task.counting, atoms.hadd)
    if not prove:
        bound = [horizon]
        found = _greedy(task, hadd, horizon, deadline)
        return _after_greedy(task, found, _astar_run(task, horizon, deadline, bound), bound, deadline, t0, prove)
    # the greedy search and A* take turns (SLICE expansions each) until one of them answers:
    # A* on its own finds the shortest composition where the greedy search's order misleads
    # it (hydropower: h_add prefers selling at any hour); a greedy plan first lowers A*'s
    # bound to one below its length, so that A* only has to prove nothing shorter exists
    bound = [horizon]
    greedy_run, astar_run = _greedy_run(task, hadd, horizon, deadline), _astar_run(task, horizon, deadline, bound)
    while True:
        try:
            next(greedy_run)
        except StopIteration as done:
            return _after_greedy(task, done.value, astar_run, bound, deadline, t0, prove)
        try:
            next(astar_run)
        except StopIteration as done:  # A* answered first: the shortest composition, or a proof of none
            better: SearchResult = done.value
            if better.status is SearchStatus.PLAN:
                better.first_plan = time.monotonic() - t0
            return better


def _after_greedy(
    task: Any, found: SearchResult, astar_run: Run, bound: list[int], deadline: float | None, t0: float, prove: bool
) -> SearchResult:
    """The answer once the greedy search has answered (``found``): A* (``astar_run``, under
    ``bound``) to its end where the greedy search has no plan and no proof; the greedy plan,
    shortened through its neighbourhood, and with ``prove`` A* below its length."""
    if found.status is SearchStatus.NONE and found.final:
        return found  # every reachable state seen, none cut by the horizon
    if found.status is not SearchStatus.PLAN:
        r = _finish(astar_run)
        r.expanded += found.expanded
        if r.status is SearchStatus.PLAN:
            r.first_plan = time.monotonic() - t0
        return r
    assert found.plan is not None
    found.first_plan = time.monotonic() - t0
    if len(found.plan.steps) > 1:
        until = None if deadline is None else time.monotonic() + (deadline - time.monotonic()) / 4
        found.plan = _improve(task, found.plan, until)
        found.length = len(found.plan.steps)
    length = len(found.plan.steps)
    if length == 0:
        return found
    if not prove:
        found.shortest = False
        found.reason = "the greedy search's composition (no proof that it is shortest was sought)"
        return found
    bound[0] = min(bound[0], length - 1)  # a shorter one, or a proof that there is none
    better = _finish(astar_run)
    better.expanded += found.expanded
    if better.status is SearchStatus.PLAN:
        better.first_plan = found.first_plan
        return better
    if better.status is SearchStatus.NONE:
        found.reason = f"no composition within {length - 1} steps (A*)"
        return found
    found.shortest = False
    found.reason = (
        f"not proven shortest: A* found no shorter composition before the time ran out ({better.expanded} states)"
    )
    return found


def _counting_first(counting: _Counting, hadd: Callable[[State], int]) -> Callable[[State], tuple[int, int]]:
    """The greedy search's order where the task has numeric goal conditions: the counting
    bound first (h_add counts a worker moved once per condition it helps, and plateaus where
    many moves are needed; the bound sees them all at once), h_add to break its ties. A dead
    end the bound proves goes last (not dropped: the greedy search's exhaustion stays a proof)."""

    def key(s: State) -> tuple[int, int]:
        c = counting.h(s)
        return (_FAR if c is None else c, hadd(s))

    return key


#: Expansions between two turns of the interleaved searches (:func:`search`).
SLICE = 16

Run = Generator[None, None, SearchResult]


def _finish(run: Run) -> SearchResult:
    """Drive a search to its end (its result)."""
    while True:
        try:
            next(run)
        except StopIteration as done:
            return done.value  # type: ignore[no-any-return]


def _greedy(task: Any, hadd: Callable[[Any], Any], horizon: int, deadline: float | None) -> SearchResult:
    """:func:`_greedy_run` to its end."""
    return _finish(_greedy_run(task, hadd, horizon, deadline))


def _greedy_run(task: Any, hadd: Callable[[Any], Any], horizon: int, deadline: float | None) -> Run:
    """Greedy best-first search on h_add (ties: the state generated first), every state once;
    the goal tested when a state is generated. Exhausting the states without cutting any at
    the horizon proves that there is no composition. A generator: it yields every ``SLICE``
    expansions (a turn of :func:`search`'s interleaving) and returns its result."""
    start = task.init
    if task.is_goal(start):
        return SearchResult(SearchStatus.PLAN, Plan([]))
    g_of: dict[Any, int] = {start: 0}
    parent: dict[Any, tuple[Any, int] | None] = {start: None}
    tie = itertools.count()
    heap: list[tuple[Any, int, Any]] = [(hadd(start), next(tie), start)]
    expanded = 0
    cut = False
    while heap:
        _, _, s = heapq.heappop(heap)
        expanded += 1
        if expanded % SLICE == 0:
            yield
        if len(g_of) > GREEDY_STATES or (deadline is not None and expanded % 64 == 0 and time.monotonic() >= deadline):
            return SearchResult(SearchStatus.STOPPED, expanded=expanded, reason="the greedy search's share")
        g2 = g_of[s] + 1
        for a_i, t in task.successors(s):
            if t in g_of:
                continue
            if g2 > horizon:
                cut = True
                continue
            g_of[t] = g2
            parent[t] = (s, a_i)
            if task.is_goal(t):
                return SearchResult(SearchStatus.PLAN, _plan(task, parent, t), expanded=expanded)
            heapq.heappush(heap, (hadd(t), next(tie), t))
    if cut:
        return SearchResult(SearchStatus.NONE, expanded=expanded, reason=f"no composition within {horizon} steps")
    return SearchResult(
        SearchStatus.NONE, final=True, expanded=expanded, reason=f"every reachable state ({len(g_of)}) was expanded"
    )


def _astar(task: Any, horizon: int, deadline: float | None) -> SearchResult:
    """:func:`_astar_run` to its end."""
    return _finish(_astar_run(task, horizon, deadline, [horizon]))


def _astar_run(task: Any, horizon: int, deadline: float | None, bound: list[int]) -> Run:
    """A* for the shortest composition of at most ``bound[0]`` (≤ ``horizon``) steps (module
    docstring). ``bound`` may be lowered while it runs (a composition of ``bound[0] + 1`` steps
    found meanwhile, :func:`search`): states beyond it are cut from then on, and once the least
    f in the queue exceeds it there is none within ``bound[0]`` (every f is a lower bound). A
    generator: it yields every ``SLICE`` expansions and returns its result."""
    start = task.init
    cap = horizon + 1
    h0 = task.h(start, cap)
    if h0 is None:
        return SearchResult(SearchStatus.NONE, final=True, reason="a dead end from the initial state")
    cut = h0 > horizon  # some state was cut by the horizon: no proof for longer plans
    if cut:
        return SearchResult(SearchStatus.NONE, reason=f"no composition within {horizon} steps (h^max)")
    # lazy A*: a state enters the queue with its parent's h − 1 and is evaluated only when it
    # comes out; if its f then grows it goes back in. Most generated states are never
    # evaluated. The heuristic need only be admissible: h(parent) ≤ h*(parent) ≤ 1 + h*(t)
    # for every successor t, so the estimate h(parent) − 1 is admissible for t too; every f in
    # the queue is a lower bound, a state reached more cheaply is queued again (no closed
    # set), and a goal comes out at its g (its estimate ≤ h* = 0): the first is shortest.
    g_of: dict[Any, int] = {start: 0}
    parent: dict[Any, tuple[Any, int] | None] = {start: None}
    tie = itertools.count()
    heap: list[tuple[int, int, int, int, Any, bool]] = [(h0, h0, next(tie), 0, start, True)]
    expanded = alive = 0
    while heap:
        f, h, _, g, s, evaluated = heapq.heappop(heap)
        if f > bound[0]:  # every entry left has f > bound: no composition within it
            return SearchResult(SearchStatus.NONE, expanded=expanded, reason=f"no composition within {bound[0]} steps")
        if g > g_of[s]:
            continue  # a stale entry: s was reached more cheaply since
        if not evaluated:
            h2 = task.h(s, cap - g)
            if h2 is None:
                continue  # a proven dead end
            if g + h2 > bound[0]:
                cut = True
                continue
            alive += 1
            if g + h2 > f:
                heapq.heappush(heap, (g + h2, h2, next(tie), g, s, True))
                continue
            h = h2
        elif s is start:
            alive += 1
        if task.is_goal(s):
            return SearchResult(SearchStatus.PLAN, _plan(task, parent, s), expanded=expanded)
        expanded += 1
        if expanded % SLICE == 0:
            yield
        if deadline is not None and time.monotonic() >= deadline:
            return SearchResult(SearchStatus.STOPPED, expanded=expanded, reason="timeout")
        g2, est = g + 1, max(h - 1, 0)
        for a_i, t in task.successors(s):
            old = g_of.get(t)
            if old is not None and old <= g2:
                continue
            g_of[t] = g2
            parent[t] = (s, a_i)
            heapq.heappush(heap, (g2 + est, est, next(tie), g2, t, False))
    if cut:
        return SearchResult(SearchStatus.NONE, expanded=expanded, reason=f"no composition within {bound[0]} steps")
    return SearchResult(
        SearchStatus.NONE,
        final=True,
        expanded=expanded,
        reason=f"every reachable state not proven a dead end ({alive}) was expanded",
    )


#: The most states the plan's neighbourhood (:func:`_improve`) may hold, and how many depths
#: past the last one that shortened the plan it tries.
NEIGHBOURHOOD_STATES = 100_000
IMPROVE_DEPTHS = 2


def _improve(task: Any, plan: Plan, deadline: float | None) -> Plan:
    """A shorter plan through the plan's neighbourhood (plan neighbourhood graph search,
    Nakhost & Müller 2010): the states within d steps of a state of the plan, d = 1, 2, …,
    searched breadth-first from the initial state for a goal state; a shorter plan found
    becomes the plan, and its neighbourhood is searched again. Every plan it returns is a path
    of successors from the initial state to a goal state (the validator replays it all the
    same). Stops at the deadline or when a neighbourhood outgrows ``NEIGHBOURHOOD_STATES``,
    keeping the best plan so far, or after ``IMPROVE_DEPTHS`` depths in a row found nothing
    shorter; it claims nothing about length."""
    by_name = {n: i for i, n in enumerate(_action_names(task))}
    steps = [by_name[step[0].morphism] for step in plan.steps]
    depth = last = 1
    while depth < last + IMPROVE_DEPTHS:
        states = [task.init]
        for a_i in steps:
            states.append(next(t for b, t in task.successors(states[-1]) if b == a_i))
        succ: dict[Any, list[tuple[int, Any]]] = {}
        frontier = list(dict.fromkeys(states))
        nodes = set(frontier)
        for d in range(depth + 1):
            nxt = []
            for s in frontier:
                if deadline is not None and time.monotonic() >= deadline:
                    return _as_plan(task, steps)
                succ[s] = task.successors(s)
                if d < depth:
                    for _, t in succ[s]:
                        if t not in nodes:
                            nodes.add(t)
                            nxt.append(t)
            if len(nodes) > NEIGHBOURHOOD_STATES:
                return _as_plan(task, steps)
            frontier = nxt
        better = _bfs(task, succ, nodes, len(steps) - 1)
        if better is not None:
            steps, last = better, depth
        else:
            depth += 1
    return _as_plan(task, steps)


def _bfs(task: Any, succ: dict[Any, list[tuple[int, Any]]], nodes: set[Any], limit: int) -> list[int] | None:
    """A shortest path of at most ``limit`` steps from the initial state to a goal state within
    ``nodes``, as action indices; None when there is none."""
    parent: dict[Any, tuple[Any, int] | None] = {task.init: None}
    layer = [task.init]
    for _ in range(limit):
        nxt = []
        for s in layer:
            for a_i, t in succ.get(s, ()):
                if t in nodes and t not in parent:
                    parent[t] = (s, a_i)
                    if task.is_goal(t):
                        out = []
                        link = parent[t]
                        while link is not None:
                            out.append(link[1])
                            link = parent[link[0]]
                        return out[::-1]
                    nxt.append(t)
        layer = nxt
    return None


def _action_names(task: Any) -> list[str]:
    return task.names if isinstance(task, _Strips) else [a.name for a in task.actions]


def _as_plan(task: Any, steps: list[int]) -> Plan:
    names = _action_names(task)
    return Plan([(Activation(names[a_i]),) for a_i in steps])


def _plan(task: Any, parent: dict[Any, tuple[Any, int] | None], s: Any) -> Plan:
    names = []
    link = parent[s]
    while link is not None:
        prev, a_i = link
        names.append(task.names[a_i] if isinstance(task, _Strips) else task.actions[a_i].name)
        link = parent[prev]
    return Plan([(Activation(n),) for n in reversed(names)])


def reachable_states(inst: ir.Instance, limit: int) -> tuple[list[str], list[tuple[Any, ...]]] | None:
    """Every state sequential compositions of any length reach (breadth first over the
    concrete step of :class:`_Task`), as the resource names and one value tuple per state:
    a certificate's invariant (issue 31). None when the search does not model the instance,
    a goal state is reachable, or there are more than ``limit`` states."""
    try:
        task = _Task(inst)
    except _Unsupported:
        return None
    seen: dict[Any, None] = {task.init: None}
    todo = [task.init]
    while todo:
        s = todo.pop()
        if task.is_goal(s):
            return None
        for _, t in task.successors(s):
            if t not in seen:
                if len(seen) >= limit:
                    return None
                seen[t] = None
                todo.append(t)
    return task.names, list(seen)
