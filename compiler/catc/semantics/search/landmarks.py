"""Counting plus landmarks: an admissible A* heuristic for the forward search
(:mod:`catc.semantics.search`), an operator-counting linear program (Pommerening, Röger, Helmert
& Bonet 2014) whose rows are

* the numeric state equation of :class:`catc.semantics.search._Counting` (each linear goal
  condition and each resource bound holds at the end, x + Σ Y_a·Δ_a; only resources every
  morphism changes by constants take part);
* **landmarks**: a fact p (a literal ``resource = value`` of a condition) is a landmark of the
  state s when it is false in s and every composition from s to the goal makes it true: every
  goal fact false in s, and, backwards, every fact false in s that all achievers of a landmark
  require (Porteous, Sebastia & Hoffmann 2001's backchaining). A landmark gives
  Σ_{a achieves p} Y_a ≥ 1 (a disjunctive action landmark), and, with e_p the first layer of
  the interval relaxation (:meth:`catc.semantics.search.task._Task._layer`) in which an achiever of p
  may fire, Σ_{a relevant to p or achieving p} Y_a ≥ e_p + 1 (the relevance argument of
  :meth:`catc.semantics.search._Task._achiever_bound`, for any fact);
* **net change** (the state equation over facts, Bonet 2013): for each fact p,
  [p now] + Σ_{a may add p} Y_a − Σ_{a requires p and sets its resource to another constant}
  Y_a ≥ [p is a goal fact]: each firing of the latter turns p from true to false, each firing
  of any other morphism raises p by at most one, and p's value at the end is ≥ the goal's
  demand and ≥ 0;

and, on top of the program, a **case split on a gate fact** (for a fact p false in s that
a morphism the program's optimum fires requires): either no composition makes p true — then no
morphism that requires p fires (their Y_a = 0) — or one does, and it has the relevance row of p
above. The bound is the smaller of the two programs' optima. This is the shape of "hours plus
trades" in hydropower: selling at the last hour's price needs the clock advanced to it (the
relevance row counts the advances), and without it every trade earns too little (the program
without the last hour's morphisms needs many more trades).

Admissible. Take any composition π from s to the goal and Y_a the number of times π fires a.
Every row above holds for these counts (argued row by row above and in the docstrings cited),
so the least Σ Y_a of the program — read from the dual (every dual feasible point is a lower
bound, so the capped simplex is sound) and rounded up — is at most |π|. In the case split π
either makes p true, and its counts satisfy the second program, or it does not, and its counts
satisfy the first: the smaller optimum is still at most |π|. An infeasible program (an
unbounded dual) in every case proves that no composition exists from s (a dead end).
Arithmetic is exact (``Fraction``).
"""

from __future__ import annotations

from collections.abc import Callable
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir import EffectKind
from catc.semantics.search.common import _constant, _reads
from catc.semantics.search.counting import state_equation
from catc.semantics.search.terms import _point

# catc.semantics.search builds this bound, so nothing here imports it (no cycle): the task
# (search._Task) and its atoms (search._Atoms) come in as arguments
State = tuple[Any, ...]

__all__ = ["LandmarkCounting"]

#: Simplex pivots per program and state (a capped run still gives a lower bound).
PIVOTS = 200
#: Pivots of the test at the start (:meth:`LandmarkCounting.build`): a capped run is still a
#: lower bound, and where the program needs many pivots it is too slow to pay off anyway.
START_PIVOTS = 40
#: Gate facts tried per state (each costs two more programs; the one reached last first).
GATES = 1
#: Layers of the interval relaxation read for e_p.
LAYERS = 200

Column = list[tuple[int, Fraction]]  # the non-zero coefficients (action, c) of one primal row


def _assigned(e: ir.Expr) -> Any:
    """The constant an assignment writes (a Boolean or a symbol), None when not a constant
    (a Boolean folded as :func:`~catc.semantics.search.common._constant` folds it)."""
    return e.value if isinstance(e, ir.Const) else _constant(e)


class _Simplex:
    """max r·y subject to A·y ≤ 1, y ≥ 0 (the dual of min Σ Y subject to Aᵀ… ≥ r, Y ≥ 0), by an
    exact simplex with Bland's rule, warm-started from the last basis (the region does not
    depend on r). Like :class:`catc.semantics.search._Dual`, and it also keeps the primal
    solution of the last call (the reduced costs of the slacks): ``primal[k]`` is Y of the
    k-th action of the program."""

    def __init__(self, matrix: list[list[Fraction]], n: int) -> None:
        m = len(matrix)
        self.n, self.m = n, m
        self.rows = [
            list(row) + [Fraction(int(i == k)) for k in range(m)] + [Fraction(1)] for i, row in enumerate(matrix)
        ]
        self.basis = [n + i for i in range(m)]
        self.primal: list[Fraction] = [Fraction(0)] * m

    def solve(self, r: list[Fraction], pivots: int) -> Fraction | None:
        n, m, rows, basis = self.n, self.m, self.rows, self.basis
        cost = list(r) + [Fraction(0)] * m
        z = [-c for c in cost] + [Fraction(0)]
        for i, b in enumerate(basis):
            cb = cost[b]
            if cb:
                z = [x + cb * y for x, y in zip(z, rows[i])]
        for _ in range(pivots):
            j = next((j for j in range(n + m) if z[j] < 0), None)
            if j is None:
                break
            best: tuple[Fraction, int, int] | None = None
            for i, row in enumerate(rows):
                if row[j] > 0:
                    key = (row[-1] / row[j], basis[i], i)
                    if best is None or key < best:
                        best = key
            if best is None:
                return None  # unbounded dual: the primal is infeasible
            i = best[2]
            prow = [x / rows[i][j] for x in rows[i]]
            rows[i] = prow
            for k, row in enumerate(rows):
                f = row[j]
                if k != i and f:
                    rows[k] = [x - f * y for x, y in zip(row, prow)]
            f = z[j]
            z = [x - f * y for x, y in zip(z, prow)]
            basis[i] = j
        self.primal = z[n : n + m]
        return z[-1]


class _Program:
    """min Σ Y over the actions ``acts`` subject to the primal rows ``columns`` (Σ c·Y ≥ rhs)."""

    def __init__(self, columns: list[Column], acts: list[int]) -> None:
        self.acts = acts
        where = {a: k for k, a in enumerate(acts)}
        matrix = [[Fraction(0)] * len(columns) for _ in acts]
        for j, col in enumerate(columns):
            for a, c in col:
                if a in where:
                    matrix[where[a]][j] += c
        self.lp = _Simplex(matrix, len(columns))

    def value(self, r: list[Fraction], pivots: int) -> int | None:
        if all(x <= 0 for x in r):
            self.lp.primal = [Fraction(0)] * len(self.acts)
            return 0
        v = self.lp.solve(r, pivots)
        return None if v is None else int(-((-v) // 1))  # ⌈v⌉

    def used(self) -> list[int]:
        return [a for a, y in zip(self.acts, self.lp.primal) if y > 0]


class LandmarkCounting:
    """The heuristic of the module docstring for one task (:meth:`h`)."""

    def __init__(self, task: Any, atoms: Any, inst: ir.Instance) -> None:
        self.task = task
        morphisms = list(inst.domain.morphisms.values())
        self.columns: list[Column] = []
        self.numeric: list[Callable[[State], Any]] = []
        self._numeric_rows(atoms, morphisms)
        self._facts(atoms, morphisms)
        self._fact_rows()
        acts = sorted({a for col in self.columns for a, _ in col})
        self.acts = acts
        self.base = _Program(self.columns, acts)
        self.gates: dict[int, tuple[_Program, _Program]] = {}  # fact → the two programs of its split
        self.pivots = PIVOTS

    def _numeric_rows(self, atoms: Any, morphisms: list[ir.Morphism]) -> None:
        """The numeric state equation (:func:`~catc.semantics.search.counting.state_equation`)."""
        goal_rows, bound_rows = state_equation(self.task, atoms, morphisms)
        for col, rhs in goal_rows + bound_rows:
            self.columns.append(col)
            self.numeric.append(rhs)
        self.numeric_goal = bool(goal_rows)

    def _facts(self, atoms: Any, morphisms: list[ir.Morphism]) -> None:
        """The facts: achievers, consumers, what each morphism requires, the facts all
        achievers of one require (``shared``), and the morphisms relevant to each."""
        task = self.task
        n = len(task.actions)
        self.facts = [atom for atom, (what, _) in enumerate(atoms.kind) if what == "fact"]
        self.fact_of = {atom: f for f, atom in atoms.facts.items()}
        self.goal_facts = {p for p in atoms.goal if atoms.kind[p][0] == "fact"}
        self.requires = [{p for p in atoms.pre[a] if atoms.kind[p][0] == "fact"} for a in range(n)]
        self.adders = {p: [a for a in range(n) if p in atoms.adds[a]] for p in self.facts}
        self.needs = {p: [a for a in range(n) if p in self.requires[a]] for p in self.facts}
        self.consumers: dict[int, list[int]] = {}
        consumers = self.consumers
        for p in self.facts:
            i, v = self.fact_of[p]
            name = task.names[i]
            consumers[p] = [
                a
                for a in self.needs[p]
                if any(
                    e.resource == name
                    and e.kind is EffectKind.ASSIGN
                    and (to := _assigned(e.value)) is not None
                    and to != v
                    for e in morphisms[a].effects
                )
            ]
        shared: dict[int, set[int]] = {}
        for p in self.facts:
            ach = self.adders[p]
            shared[p] = set.intersection(*(self.requires[a] for a in ach)) - {p} if ach else set()
        self.shared = shared
        # relevance (:meth:`_Task._achievers`, for every fact): the morphisms writing a resource
        # of R_p, the resources p's achievers' preconditions read, closed under writers
        writes = [{task.index[e.resource] for e in m.effects} for m in morphisms]
        reads_pre = [{task.index[x] for lit in m.pre for x in _reads(lit.expr)} for m in morphisms]
        reads_all = [
            reads_pre[a] | {task.index[x] for e in m.effects for x in _reads(e.value)} for a, m in enumerate(morphisms)
        ]
        self.relevant: dict[int, list[int]] = {}
        for p in self.facts:
            ach = self.adders[p]
            rel: set[int] = set().union(*(reads_pre[a] for a in ach)) if ach else set()
            grew = True
            while grew:
                grew = False
                for a, w in enumerate(writes):
                    if w & rel and not reads_all[a] <= rel:
                        rel |= reads_all[a]
                        grew = True
            self.relevant[p] = sorted({a for a, w in enumerate(writes) if w & rel} | set(ach))

    def _fact_rows(self) -> None:
        """The fact rows: landmark and relevance (per landmark candidate), net change."""
        shared, consumers = self.shared, self.consumers
        # only facts that may be landmarks of some state get rows: the goal facts and, backwards,
        # the facts all achievers of one of them require (a superset of every state's landmarks)
        self.candidates = set(self.goal_facts)
        todo = list(self.candidates)
        while todo:
            for p in shared[todo.pop()]:
                if p not in self.candidates:
                    self.candidates.add(p)
                    todo.append(p)
        self.landmark_row: dict[int, int] = {}
        self.relevance_row: dict[int, int] = {}
        for p in sorted(self.candidates):
            self.landmark_row[p] = len(self.columns)
            self.columns.append([(a, Fraction(1)) for a in self.adders[p]])
            self.relevance_row[p] = len(self.columns)
            self.columns.append([(a, Fraction(1)) for a in self.relevant[p]])
        self.flow: list[tuple[int, int]] = []  # (fact, row)
        for p in self.facts:
            if not consumers[p]:
                continue
            coeffs: dict[int, Fraction] = {}
            for a in self.adders[p]:
                coeffs[a] = coeffs.get(a, Fraction(0)) + 1
            for a in consumers[p]:
                coeffs[a] = coeffs.get(a, Fraction(0)) - 1
            self.flow.append((p, len(self.columns)))
            self.columns.append([(a, c) for a, c in coeffs.items() if c])

    @classmethod
    def build(cls, task: Any, atoms: Any, inst: ir.Instance) -> LandmarkCounting | None:
        lm = cls(task, atoms, inst)
        if not lm.numeric_goal:
            # measured (docs/benchmarks.md): with Boolean goals only (rover) it raised no
            # estimate at the start, and its first evaluation took 2.3 CPU s on rover-16
            return None
        # kept only where it raises the initial estimate above the other bounds (``task.h``
        # before the hook)
        before = task.h(task.init, LAYERS)
        if before is None:
            return None
        lm.pivots = START_PIVOTS
        mine = lm.h(task.init)
        lm.pivots = PIVOTS
        return lm if mine is None or mine > before else None

    def _holds(self, p: int, s: State) -> bool:
        i, v = self.fact_of[p]
        return bool(s[i] == v)

    def _landmarks(self, s: State, false: set[int]) -> set[int] | None:
        """The landmarks of ``s`` (module docstring); None when one has no achiever."""
        todo = [p for p in self.goal_facts if p in false]
        found = set(todo)
        while todo:
            q = todo.pop()
            if not self.adders[q]:
                return None
            for p in self.shared[q]:
                if p in false and p not in found:
                    found.add(p)
                    todo.append(p)
        return found

    def _first_layers(self, s: State, want: set[int]) -> dict[int, int]:
        """For each fact of ``want``: e_p + 1, e_p the first layer of the interval relaxation
        from ``s`` in which an achiever of p may fire (LAYERS + 1 when none within LAYERS; a
        large number when none ever)."""
        never = 1 << 30
        out = {p: never for p in want if not self.adders[p]}  # nothing makes p true
        want = {p for p in want if self.adders[p]}
        if not want:
            return out
        task = self.task
        first = [-1] * len(task.actions)
        fired: set[int] = set()
        r: list[Any] = [_point(v, k) for v, k in zip(s, task.kinds)]
        layer = 0
        fixpoint = False
        enabled = [0] * len(task.actions)  # the incremental layers' state (search.task._layer)
        dirty: set[int] | None = None
        shifts: dict[int, list[Any]] = {}
        while layer < LAYERS:
            new = task._layer(tuple(r), fired, first, layer, enabled, dirty, shifts)
            if new is None:
                fixpoint = True
                break
            r, dirty = new
            layer += 1
            if all(any(first[a] >= 0 for a in self.adders[p]) for p in want):
                break
        for p in want:
            e = min((first[a] for a in self.adders[p] if first[a] >= 0), default=-1)
            out[p] = e + 1 if e >= 0 else (never if fixpoint else layer + 1)
        return out

    def h(self, s: State) -> int | None:
        """The bound of the module docstring in ``s``; None for a proven dead end."""
        r: list[Fraction] = []
        for f in self.numeric:
            try:
                r.append(Fraction(f(s)))
            except ArithmeticError:
                return 0
        false = {p for p in self.facts if not self._holds(p, s)}
        lms = self._landmarks(s, false)
        if lms is None:
            return None
        layers = self._first_layers(s, lms) if lms else {}
        if any(e >= 1 << 30 for e in layers.values()):
            return None
        r += [Fraction(0)] * (len(self.columns) - len(r))
        for p in lms:
            r[self.landmark_row[p]] = Fraction(1)
            r[self.relevance_row[p]] = Fraction(layers[p])
        for p, row in self.flow:
            r[row] = Fraction(int(p in self.goal_facts) - int(p not in false))
        best = self.base.value(r, self.pivots)
        if best is None:
            return None
        gates = sorted({p for a in self.base.used() for p in self.requires[a] if p in false and p not in lms})
        if not gates:
            return best
        e = self._first_layers(s, set(gates))
        gates.sort(key=lambda p: (e[p] >= 1 << 30, -e[p]))  # reached last first, unreachable ones after
        for p in gates[:GATES]:
            without, with_p = self._gate(p)
            a_value = without.value(r, self.pivots)
            # p unreachable: only the first case; else the base rows and p's relevance row
            b_value = None if e[p] >= 1 << 30 else with_p.value(r + [Fraction(e[p])], self.pivots)
            if a_value is None and b_value is None:
                return None
            split = min(v for v in (a_value, b_value) if v is not None)
            best = max(best, split)
        return best

    def _gate(self, p: int) -> tuple[_Program, _Program]:
        """The two programs of the case split on ``p``: without the morphisms that require p,
        and the base program with p's relevance row (its right-hand side e_p + 1 in the state)."""
        if p not in self.gates:
            banned = set(self.needs[p])
            relevance = [(a, Fraction(1)) for a in self.relevant[p]]
            self.gates[p] = (
                _Program(self.columns, [a for a in self.acts if a not in banned]),
                _Program([*self.columns, relevance], sorted(set(self.acts) | set(self.relevant[p]))),
            )
        return self.gates[p]
