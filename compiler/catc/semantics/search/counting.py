"""The operator-counting lower bound (:class:`_Counting`) and its exact simplex (:class:`_Dual`)."""

from __future__ import annotations

import math
from collections.abc import Callable
from fractions import Fraction
from typing import TYPE_CHECKING, Any

from catc import ir
from catc.ir import EffectKind
from catc.semantics.search.common import Fn, State

if TYPE_CHECKING:
    from catc.semantics.search.atoms import _Atoms
    from catc.semantics.search.task import _Task


Row = tuple[list[tuple[int, Fraction]], Callable[[State], Any]]


def state_equation(task: _Task, atoms: _Atoms, morphisms: list[ir.Morphism]) -> tuple[list[Row], list[Row]]:
    """The numeric state equation of operator counting, as rows ``(column, rhs)`` meaning
    Σ_a c_a·Y_a ≥ rhs(s): one per linear goal condition Σ w·x + k ≥ 0 over numbers changed only
    by constant increases and decreases (the goal rows), then one per bound lo ≤ x / x ≤ hi of
    such a number (the bound rows). Any plan from ``s`` fires morphism a Y_a times and ends with
    x + Σ_a Y_a·Δ_a(x) for each such x, so its counts satisfy every row."""
    n_act = len(task.actions)
    deltas: list[dict[int, Fraction]] = [{} for _ in range(n_act)]
    counted = [k == "number" for k in task.kinds]
    for a_i, m in enumerate(morphisms):
        for e in m.effects:
            i = task.index[e.resource]
            if task.kinds[i] != "number":
                continue
            if e.kind is EffectKind.ASSIGN or not isinstance(e.value, ir.Const):
                counted[i] = False
                continue
            c = Fraction(e.value.value)
            deltas[a_i][i] = deltas[a_i].get(i, Fraction(0)) + (-c if e.kind is EffectKind.DECREASE else c)

    def column(w: list[tuple[int, Fraction]]) -> list[tuple[int, Fraction]]:
        out = []
        for a_i in range(n_act):
            c = sum((wi * deltas[a_i].get(i, 0) for i, wi in w), Fraction(0))
            if c:
                out.append((a_i, c))
        return out

    def rhs(w: list[tuple[int, Fraction]], k: Any) -> Callable[[State], Any]:
        return lambda s: -k - sum((wi * s[i] for i, wi in w), 0)  # Σ w·(x + Σ c·Δ) + k ≥ 0

    goal_rows: list[Row] = []
    for atom in atoms.goal:
        what, j = atoms.kind[atom]
        if what != "linear":
            continue
        terms, k, _strict = atoms.linear[j]
        if all(counted[i] for i, _ in terms):
            goal_rows.append((column(terms), rhs(terms, k)))
    bound_rows: list[Row] = []
    for i, (lo, hi) in enumerate(task.bounds):
        if not counted[i]:
            continue
        if lo is not None:
            bound_rows.append((column([(i, Fraction(1))]), rhs([(i, Fraction(1))], -lo)))  # x ≥ lo
        if hi is not None:
            bound_rows.append((column([(i, Fraction(-1))]), rhs([(i, Fraction(-1))], hi)))  # x ≤ hi
    return goal_rows, bound_rows


class _Counting:
    """An operator-counting lower bound (Pommerening et al. 2014, the state equation over
    numbers): the least Σ c_a over real c ≥ 0, c_a standing for how often morphism a fires on
    the way to the goal, such that the values at the end, x + Σ c_a·Δ_a (Δ_a: a's constant
    change of each numeric resource), satisfy every linear goal condition and the resources'
    bounds (declared, and inferred: :func:`infer_bounds`), and every goal fact false now has
    an achiever with c_a ≥ 1.

    Only resources every morphism changes by constants (or leaves alone) take part, so the
    counts of any composition reaching the goal are a solution: the least Σ c_a, rounded up,
    is a lower bound on its length (admissible), and an infeasible system proves a dead end.
    It is consistent: from s, a step a to s′ and a solution c′ for s′ give the solution c′ +
    e_a for s (the same values at the end; a fact false in s and true in s′ has a as an
    achiever), so h(s) ≤ h(s′) + 1.

    The least Σ c_a is read from the dual, max r·y subject to Mᵀy ≤ 1, y ≥ 0, solved by an
    exact simplex (Fractions, Bland's rule): the slacks are a feasible start, every basis on
    the way is dual feasible, so its value is a lower bound even if the pivots are capped, and
    an unbounded dual is an infeasible primal."""

    PIVOTS = 200

    def __init__(self, rows: list[tuple[list[tuple[int, Fraction]], Callable[[State], Any]]], n_actions: int) -> None:
        self.rows = rows  # (the column's non-zero entries (action, coefficient), rhs of the state)
        used = sorted({a for coeffs, _ in rows for a, _ in coeffs})
        where = {a: k for k, a in enumerate(used)}
        # the dual's constraint matrix: one row per action taking part, one column per primal row
        matrix = [[Fraction(0)] * len(rows) for _ in used]
        for j, (coeffs, _) in enumerate(rows):
            for a, c in coeffs:
                matrix[where[a]][j] += c
        self.dual = _Dual(matrix, len(rows))

    @classmethod
    def build(cls, task: _Task, atoms: _Atoms, inst: ir.Instance) -> _Counting | None:
        n_act = len(task.actions)
        goal_rows, bound_rows = state_equation(task, atoms, list(inst.domain.morphisms.values()))
        if not goal_rows:
            return None
        rows: list[Row] = goal_rows + bound_rows
        for atom in atoms.goal:
            if atoms.kind[atom][0] != "fact":
                continue
            achievers = [(a_i, Fraction(1)) for a_i in range(n_act) if atom in atoms.adds[a_i]]
            rows.append((achievers, _unmet(dict(atoms.tests)[atom])))
        return cls(rows, n_act)

    def h(self, s: State) -> int | None:
        r = []
        for _, f in self.rows:
            try:
                r.append(Fraction(f(s)))
            except ArithmeticError:
                return 0
        if all(x <= 0 for x in r):
            return 0
        value = self.dual.solve(r, self.PIVOTS)
        if value is None:
            return None
        return int(-((-value) // 1))  # ⌈value⌉


def _unmet(test: Fn) -> Callable[[State], Any]:
    return lambda s: 0 if test(s) else 1


def _max_dual(matrix: list[list[Fraction]], r: list[Fraction], pivots: int) -> Fraction | None:
    """max r·y subject to matrix·y ≤ 1, y ≥ 0 (:class:`_Dual`, from the slack basis)."""
    return _Dual(matrix, len(r)).solve(r, pivots)


class _Dual:
    """max r·y subject to A·y ≤ 1, y ≥ 0 for one A and many r, by an exact simplex (Fractions,
    Bland's rule). The feasible region does not depend on r, so the basis the last call ended
    in is a feasible start for the next (a warm start: a state's bound differs from its
    parent's by a few pivots); every basis on the way is feasible, so the value reached after
    ``pivots`` pivots is a lower bound on the maximum; None when unbounded."""

    def __init__(self, matrix: list[list[Fraction]], n: int) -> None:
        m = len(matrix)
        self.n, self.m = n, m
        # each row of the tableau as whole numerators over one positive denominator (N, D):
        # exact as Fractions, but a pivot is a few int operations per entry and one gcd
        self.rows = [
            _ints(list(row) + [Fraction(int(i == k)) for k in range(m)] + [Fraction(1)]) for i, row in enumerate(matrix)
        ]
        self.basis = [n + i for i in range(m)]

    def solve(self, r: list[Fraction], pivots: int) -> Fraction | None:
        n, m, rows, basis = self.n, self.m, self.rows, self.basis
        cost = list(r) + [Fraction(0)] * m
        z, dz = _ints([-c for c in cost] + [Fraction(0)])
        for i, b in enumerate(basis):  # the reduced costs in the kept basis: −c + Σ c_B·row
            cb = Fraction(cost[b])
            if cb:
                row, d = rows[i]
                p, q = cb.numerator, cb.denominator * d  # z + (p/q)·row
                z, dz = _reduce([x * q + p * y * dz for x, y in zip(z, row)], dz * q)
        for _ in range(pivots):
            j = next((j for j in range(n + m) if z[j] < 0), None)
            if j is None:
                break
            best: tuple[Fraction, int, int] | None = None
            for i, (row, _d) in enumerate(rows):
                if row[j] > 0:
                    key = (Fraction(row[-1], row[j]), basis[i], i)
                    if best is None or key < best:
                        best = key
            if best is None:
                return None  # unbounded
            i = best[2]
            prow = rows[i][0]
            p = prow[j]  # the pivot row divided by its entry j: prow / p
            rows[i] = _reduce(list(prow), p)
            for k, (row, d) in enumerate(rows):
                f = row[j]
                if k != i and f:  # row/d − (f/d)·prow/p = (p·row − f·prow) / (d·p)
                    rows[k] = _reduce([p * x - f * y for x, y in zip(row, prow)], d * p)
            f = z[j]
            z, dz = _reduce([p * x - f * y for x, y in zip(z, prow)], dz * p)
            basis[i] = j
        return Fraction(z[-1], dz)


def _ints(row: list[Fraction]) -> tuple[list[int], int]:
    """A row of Fractions as whole numerators over their least common denominator."""
    d = math.lcm(*(x.denominator for x in row)) if row else 1
    return [x.numerator * (d // x.denominator) for x in row], d


def _reduce(row: list[int], d: int) -> tuple[list[int], int]:
    """row / d with a positive denominator and no common factor."""
    g = math.gcd(d, *row)
    if d < 0:
        g = -g
    if g != 1:
        return [x // g for x in row], d // g
    return row, d
