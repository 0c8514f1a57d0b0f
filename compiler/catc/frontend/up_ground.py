"""catc's grounder for unified-planning problems: which parameter tuples of each action are worth
instantiating, found before anything is instantiated.

UP 1.3's own grounder enumerates the product of the parameters' objects, pruned one parameter at
a time, and then instantiates and simplifies every candidate (18,264 on a nomystery task to keep
114); its pruning also crashes (``list.remove(x)``) when one parameter fails two static
preconditions, as in the untyped IPC encodings of ferry, miconic, logistics, driverlog and
satellite. Here the parameters are bound one at a time (depth first, the most constrained
first) and each static precondition — a predicate no action writes, its negation, or an
equality of parameters and objects — is tested as soon as its last parameter is bound, on a
table of the predicate's true tuples built once. Only the tuples that pass are handed to UP's
``GrounderHelper``, which instantiates them and drops the rest it can refute (exactly what its
own grounder does to each candidate). The clock (``deadline``, ``time.monotonic()``) is read
throughout: :class:`GroundingStopped` when it has passed.

unified-planning is imported only inside these functions (the ``up`` extra).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

__all__ = ["Grounding", "GroundingStopped", "ground"]

#: Candidate bindings between two looks at the clock.
_CLOCK_EVERY = 512


class GroundingStopped(Exception):
    """The deadline passed while grounding."""


@dataclass
class Grounding:
    """The ground problem, the map from its action instances back to the original problem's,
    and how many parameter tuples were instantiated (``candidates``) and kept (``actions``)."""

    problem: Any
    back: Callable[[Any], Any]
    candidates: int
    actions: int


class _Clock:
    def __init__(self, deadline: float | None) -> None:
        self.deadline, self.ticks = deadline, 0

    def tick(self) -> None:
        self.ticks += 1
        if self.deadline is not None and self.ticks % _CLOCK_EVERY == 0:
            self.check()

    def check(self) -> None:
        if self.deadline is not None and time.monotonic() >= self.deadline:
            raise GroundingStopped("the time ran out while grounding")


def ground(problem: Any, deadline: float | None = None) -> Grounding:
    """Remove quantifiers (UP's ``QuantifiersRemover``) and ground ``problem``: the actions'
    parameter tuples that pass every static precondition (:func:`_bindings`), instantiated by
    UP's ``GrounderHelper`` (static fluents simplified away, refuted instances dropped)."""
    from unified_planning.engines import CompilationKind
    from unified_planning.engines.compilers.grounder import GrounderHelper, ground_minimize_action_costs_metric
    from unified_planning.engines.compilers.quantifiers_remover import QuantifiersRemover
    from unified_planning.engines.compilers.utils import lift_action_instance
    from unified_planning.model import InstantaneousAction

    clock = _Clock(deadline)
    maps: list[Callable[[Any], Any]] = []
    kind = problem.kind
    if kind.has_existential_conditions() or kind.has_universal_conditions() or kind.has_forall_effects():
        # _compile, not compile: the kind check would refuse undefined initial values, which
        # catc decides on after grounding (only the values a ground action reads matter)
        res = QuantifiersRemover()._compile(problem, CompilationKind.QUANTIFIERS_REMOVING)
        problem = res.problem
        maps.append(res.map_back_action_instance)
    clock.check()
    tables = _StaticTables(problem)
    chosen: dict[Any, list[tuple[Any, ...]]] = {}
    for action in problem.actions:
        if isinstance(action, InstantaneousAction):
            chosen[action] = list(_bindings(problem, action, tables, clock))
        else:  # pragma: no cover - refused by kind before grounding (time)
            chosen[action] = []
    helper = GrounderHelper(problem, chosen, True)
    trace: dict[Any, tuple[Any, list[Any]]] = {}
    new_problem = problem.clone()
    new_problem.name = f"catc_grounded_{problem.name}"
    new_problem.clear_actions()
    candidates = 0
    for old, params, new in helper.get_grounded_actions():
        candidates += 1
        if candidates % 16 == 0:
            clock.check()
        if new is not None:
            new_problem.add_action(new)
            trace[new] = (old, list(params))
    new_problem.clear_quality_metrics()
    for qm in problem.quality_metrics:
        if qm.is_minimize_action_costs():
            new_problem.add_quality_metric(ground_minimize_action_costs_metric(qm, trace, helper.simplifier))
        else:
            new_problem.add_quality_metric(qm)
    clock.check()

    def lift(ai: Any) -> Any:
        return lift_action_instance(ai, trace)

    maps.append(lift)

    def back(ai: Any) -> Any:
        for f in reversed(maps):
            ai = f(ai)
        return ai

    return Grounding(new_problem, back, candidates, len(trace))


class _StaticTables:
    """For each static Boolean fluent, the argument tuples it is true of (built on first use)."""

    def __init__(self, problem: Any) -> None:
        self.problem = problem
        self.static = problem.get_static_fluents()
        self.tables: dict[Any, frozenset[tuple[Any, ...]]] = {}

    def is_static_atom(self, node: Any) -> bool:
        return bool(node.is_fluent_exp() and node.fluent() in self.static and node.fluent().type.is_bool_type())

    def table(self, fluent: Any) -> frozenset[tuple[Any, ...]]:
        out = self.tables.get(fluent)
        if out is None:
            out = self.tables[fluent] = frozenset(self._true_tuples(fluent))
        return out

    def _true_tuples(self, fluent: Any) -> Iterator[tuple[Any, ...]]:
        p = self.problem
        default = p.fluents_defaults.get(fluent, None)
        if default is not None and default.is_false():  # only the explicit values can be true
            for key, value in p.explicit_initial_values.items():
                if key.fluent() == fluent and value.is_true():
                    yield tuple(key.args)
            return
        from unified_planning.model.fluent import get_all_fluent_exp

        for f_exp in get_all_fluent_exp(p, fluent):
            value = p.initial_value(f_exp)
            if value is not None and value.is_true():
                yield tuple(f_exp.args)


@dataclass
class _Test:
    """One static precondition over parameter positions and constants: ``args`` holds an int
    (the parameter's position) or an FNode (an object); ``kind`` is "atom" (the tuple is in
    ``table``), "eq"; ``positive`` False negates it."""

    kind: str
    args: tuple[Any, ...]
    positive: bool
    table: frozenset[tuple[Any, ...]] = frozenset()

    def holds(self, values: list[Any]) -> bool:
        vals = tuple(values[a] if isinstance(a, int) else a for a in self.args)
        ok = vals in self.table if self.kind == "atom" else vals[0] == vals[1]
        return ok == self.positive


def _static_tests(action: Any, tables: _StaticTables) -> list[_Test] | None:
    """The action's static preconditions as tests; None when one without parameters is false."""
    from unified_planning.engines.compilers.utils import split_all_ands

    position = {p.name: i for i, p in enumerate(action.parameters)}

    def arg(node: Any) -> Any:
        if node.is_parameter_exp() and node.parameter().name in position:
            return position[node.parameter().name]
        if node.is_object_exp():
            return node
        return None

    tests: list[_Test] = []
    for conjunct in split_all_ands(action.preconditions):
        positive = not conjunct.is_not()
        c = conjunct if positive else conjunct.arg(0)
        if tables.is_static_atom(c):
            args = tuple(arg(a) for a in c.args)
            if all(a is not None for a in args):
                tests.append(_Test("atom", args, positive, tables.table(c.fluent())))
        elif c.is_equals():
            args = tuple(arg(a) for a in c.args)
            if all(a is not None for a in args):
                tests.append(_Test("eq", args, positive))
    for t in tests:
        if not any(isinstance(a, int) for a in t.args) and not t.holds([]):
            return None
    return tests


def _bindings(problem: Any, action: Any, tables: _StaticTables, clock: _Clock) -> Iterator[tuple[Any, ...]]:
    """The parameter tuples of ``action`` that pass its static preconditions, depth first."""
    from unified_planning.model.types import domain_item, domain_size

    n = len(action.parameters)
    if n == 0:
        yield ()
        return
    tests = _static_tests(action, tables)
    if tests is None:
        return
    domains: list[list[Any]] = []
    for i, p in enumerate(action.parameters):
        items = [domain_item(problem, p.type, j) for j in range(domain_size(problem, p.type))]
        unary = [t for t in tests if all(a == i for a in t.args if isinstance(a, int))]
        scratch: list[Any] = [None] * n
        kept = []
        for v in items:
            scratch[i] = v
            if all(t.holds(scratch) for t in unary):
                kept.append(v)
        if not kept:
            return
        domains.append(kept)
    # the most constrained first: the fewest values, then the most tests
    order = sorted(range(n), key=lambda i: (len(domains[i]), -sum(i in t.args for t in tests)))
    rank = {p: r for r, p in enumerate(order)}
    at_level: list[list[_Test]] = [[] for _ in range(n)]
    for t in tests:
        params = [a for a in t.args if isinstance(a, int)]
        if len(set(params)) > 1:  # unary ones were applied to the domains above
            at_level[max(rank[a] for a in params)].append(t)
    values: list[Any] = [None] * n

    def extend(level: int) -> Iterator[tuple[Any, ...]]:
        i = order[level]
        for v in domains[i]:
            clock.tick()
            values[i] = v
            if all(t.holds(values) for t in at_level[level]):
                if level + 1 == n:
                    yield tuple(values)
                else:
                    yield from extend(level + 1)
        values[i] = None

    yield from extend(0)
