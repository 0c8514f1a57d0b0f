"""Composition synthesis: find the shortest composition within the horizon.

Strategy (chosen by measurement, docs/benchmarks.md): *incremental deepening* on one
solver — the encoding grows one step at a time and the goal is checked at each new state
inside a push/pop scope, so the first SAT answer is a shortest composition and the solver
keeps what it learnt from the shorter horizons.  ``strategy="single"`` encodes the whole
horizon with idle steps and checks once: any composition, not necessarily a shortest one,
but one check settles an infeasible problem, which is faster when most answers are UNSAT.
``strategy="search"`` (sequential steps, ground morphisms) runs the forward A* search of
:mod:`catc.semantics.search` instead — a shortest composition, or a proof that none exists —
and falls back to ``incremental`` where that search does not apply.  ``strategy="auto"`` (the
default of ``catc solve`` and ``model.solve()``: :func:`solve_query`) chooses before anything
runs (:func:`_chosen`): ``search`` where the forward search applies (sequential steps, no
∃-steps or warm start, a task it models: morphisms without parameters θ or use limits, no
holes or set effects), else ``incremental`` exactly as that strategy answers; the answer
names the strategy used.

Every SAT answer is replayed by the independent validator (:mod:`catc.semantics.validate`) before it
is returned; a rejected answer is an internal error, never shown as a composition.
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from catc import ir
from catc.present.composition import print_composition, where_text
from catc.present.console import Console, counted
from catc.present.values import parameter_units_json, state_json, steps_json, timings_json, units_json
from catc.queries.base import (
    ExitCode,
    Kind,
    Option,
    Progress,
    Query,
    Result,
    Status,
    backend_option,
    certificate_option,
    diagram_artifact,
    diagram_option,
    json_option,
    presolve_option,
    timeout_option,
)
from catc.semantics.compositions import canonical_fresh, checked, prune_plan
from catc.semantics.horizon import horizon_of, state_bound, use_bound
from catc.semantics.plan import Plan
from catc.semantics.relaxed import Refutation, refute
from catc.semantics.validate import validate
from catc.semantics.witness import _candidate
from catc.smt.backend import DEFAULT_BACKEND, Check, open_backend
from catc.smt.consumption import BY as CONSUMPTION_BY
from catc.smt.consumption import FixedSet, bound_refutation, cheapest_support, consumption_proof, least_length
from catc.smt.encoder import Encoder
from catc.smt.finite import FiniteSorts
from catc.smt.readback import read_plan
from catc.smt.script import SmtSort, Symbol, and_text
from catc.smt.terms import implies, not_, to_text
from catgrammar import limits


class SolveStatus(Status):
    SAT = "sat", ExitCode.OK
    UNSAT = "unsat", ExitCode.FAIL
    UNKNOWN = "unknown", ExitCode.UNKNOWN


class SolveResult(Result):
    """The answer of :func:`solve`; filled in as the search goes."""

    query = "solve"
    __slots__ = (
        "status",
        "horizon",
        "plan",
        "states",
        "final",
        "length_bound",
        "reason",
        "timings",
        "horizons_tried",
        "sequential",
        "strategy",
        "backend",
        "refutation",
        "shortest",
        "simple_path",
    )
    status: SolveStatus

    def __init__(
        self,
        status: SolveStatus,
        horizon: int,
        plan: Plan | None = None,
        states: tuple = (),
        final: bool = False,  # UNSAT holds for every horizon (use limits bound the length)
        length_bound: int | None = None,  # Σ uses when every morphism is limited
        reason: str | None = None,  # why UNKNOWN
        timings: dict[str, float] | None = None,
        horizons_tried: int = 0,
        sequential: bool = False,  # how it was solved (echoed by catc.solve/1)
        strategy: str = "incremental",
        backend: str = DEFAULT_BACKEND,
        refutation: Refutation | None = None,  # UNSAT proved by the relaxation (at any horizon)
    ) -> None:
        self.status = status
        self.horizon = horizon
        self.plan = plan
        self.states = states
        self.final = final
        self.length_bound = length_bound
        self.reason = reason
        self.timings: dict[str, float] = {} if timings is None else timings
        self.horizons_tried = horizons_tried
        self.sequential = sequential
        self.strategy = strategy
        self.backend = backend
        self.refutation = refutation
        #: False when the plan is the forward greedy search's, not proven shortest (``greedy``,
        #: or ``search`` when the time ran out before A* settled it)
        self.shortest = True
        #: t when the UNSAT is final because no path of t steps visits no state twice
        #: (:meth:`_Search._no_simple_path`; its certificate, catc.queries.certify.finals)
        self.simple_path: int | None = None

    def __repr__(self) -> str:
        return f"SolveResult({self.status.name}, horizon={self.horizon}, plan={self.plan!r})"


STRATEGIES = ("auto", "incremental", "single", "search", "greedy")


def solve(
    inst: ir.Instance,
    *,
    horizon: int | None = None,
    sequential: bool = False,
    timeout: float | None = None,
    progress: Progress | None = None,
    strategy: str = "incremental",
    validate_answer: bool = True,
    prune: bool = True,
    backend: str = DEFAULT_BACKEND,
    phase: str = "solving",
    presolve: bool = True,
    warm: WarmStart | None = None,
    exists_step: bool = False,
) -> SolveResult:
    """The shortest composition within the horizon (``strategy``: ``"incremental"``; ``"search"``;
    ``"auto"``, :func:`_chosen`), or any composition (``"single"``, ``"greedy"``), on the
    named backend.  ``progress(message)`` is told each horizon as it is tried (``"{phase}:
    horizon t of k"``).  With ``presolve`` the relaxed reachability analysis runs first: when it
    proves that no composition of any length exists, that is the answer (final UNSAT).

    ``warm`` (a :class:`WarmStart`, passed again on every call) keeps the encoding and the
    solver between calls: a problem that differs from the previous one only in its initial
    values and goal is answered on the same solver, whose initial values and goals sit behind
    assumption literals; any other change (the domain, its objects, the horizon, the semantics,
    the backend) encodes afresh; the answers are the same as without it.  ``exists_step`` (no
    ``warm``): ∃-steps in the SMT search (:func:`_deepen`), for sequential compositions."""
    sequential = _sequential(strategy, sequential, exists_step, warm)
    strategy = _chosen(inst, strategy, sequential, exists_step, warm)
    start = time.perf_counter()
    with limits.deadline(timeout):
        k = horizon_of(inst, horizon)
        timings = {"start": 0.0, "encode": 0.0, "solve": 0.0, "validate": 0.0}
        try:
            forward = strategy in ("search", "greedy")
            # the forward search ends by the solve's deadline less a margin to replay the plan
            ends = None if timeout is None else time.monotonic() + 0.95 * timeout
            found: list[SolveResult] = []  # the consumption abstraction's shortest composition
            proof = (
                _presolve(
                    inst, k, sequential, timings, found if strategy == "incremental" else None, consumption=not forward
                )
                if presolve
                else None
            )
            searched = None
            if proof is None and not found and forward:
                t0 = time.perf_counter()
                searched = _forward(inst, k, sequential, ends, prove=strategy == "search")
                timings["solve"] = time.perf_counter() - t0
                if searched is None and presolve:  # the SMT search runs: issue 24's bound first
                    proof = _presolve(inst, k, sequential, timings, None, refuted=True)
            if proof is not None:  # no composition of any length: nothing to encode
                result = SolveResult(SolveStatus.UNSAT, k, final=True, length_bound=use_bound(inst), refutation=proof)
            elif found:  # the abstraction's composition, of the least length any can have
                result = found[0]
                timings["support"] = timings.get("presolve", 0.0)  # found in the presolve, nothing encoded
                if validate_answer:
                    _validated(inst, result, k, sequential, prune, timings)
            elif searched is not None:  # the forward search settled it
                result = searched
                timings.update(searched.timings)  # first_plan: when the greedy search found one
                if result.status is SolveStatus.SAT and validate_answer:
                    _validated(inst, result, k, sequential, prune, timings)
            else:
                search = (
                    _Search(inst, k, sequential, backend, timings, exists=exists_step)
                    if warm is None
                    else warm.search(inst, k, sequential, backend, timings)
                )
                result = _deepen(inst, search, k, strategy, progress, phase, exists_step)
                if result.status is SolveStatus.SAT and validate_answer:
                    _validated(inst, result, max(k, len(result.plan or ())), sequential, prune, timings)
        except limits.Stopped as stop:  # encoding or validating when the time ran out
            result = SolveResult(SolveStatus.UNKNOWN, k, reason=stop.reason, length_bound=use_bound(inst))
    result.sequential, result.strategy, result.backend = sequential, strategy, backend
    timings["total"] = time.perf_counter() - start
    result.timings = timings
    return result


def solve_query(inst: ir.Instance, *, strategy: str = "auto", **options: Any) -> SolveResult:
    """:func:`solve` as the query registry runs it — ``catc solve``, ``model.solve()`` and the
    language server — whose default strategy is ``"auto"`` (:func:`_chosen`); the options are
    :func:`solve`'s.  :func:`solve` itself keeps ``"incremental"`` for the queries built on it
    (optimize's first composition, certify's witnesses), which choose their own route."""
    return solve(inst, strategy=strategy, **options)


def _sequential(strategy: str, sequential: bool, exists_step: bool, warm: WarmStart | None) -> bool:
    """Whether the steps are sequential (∃-steps stand for sequential compositions); a
    ValueError for an unknown strategy, or ∃-steps with a warm start."""
    if strategy not in STRATEGIES:
        raise ValueError(f"unknown strategy {strategy!r}; expected one of {', '.join(STRATEGIES)}")
    if exists_step and warm is not None:
        raise ValueError("∃-steps (exists_step) keep no warm start")
    return sequential or exists_step


def _chosen(inst: ir.Instance, strategy: str, sequential: bool, exists_step: bool, warm: WarmStart | None) -> str:
    """The strategy ``auto`` stands for (any other: itself): ``search`` where the forward
    search applies — sequential steps, neither ∃-steps nor a warm start (both belong to the
    SMT deepening), and a task :mod:`catc.semantics.search` models (:func:`_searchable`) —
    else ``incremental``.  Decided before anything runs, so that where the search does not
    apply the answer is the ``incremental`` one, presolve and all (``search`` itself falls back
    after its own presolve, which skips the consumption abstraction's shortest composition)."""
    if strategy != "auto":
        return strategy
    return "search" if sequential and not exists_step and warm is None and _searchable(inst) else "incremental"


def _searchable(inst: ir.Instance) -> bool:
    """Whether the forward search models the task: the test its :func:`~catc.semantics.search.search`
    makes first (the bitmask task, else the numeric one after static numbers are folded in)."""
    from catc.semantics.search import _inline_statics, _Strips, _Task, _Unsupported

    if inst.domain.holes or any(m.params or m.uses is not None for m in inst.morphisms.values()):
        return False  # what neither task models, without building one
    try:
        _Strips(inst)
    except _Unsupported:
        try:
            _Task(_inline_statics(inst))
        except _Unsupported:
            return False
    return True


def _deepen(
    inst: ir.Instance,
    search: _Search,
    k: int,
    strategy: str,
    progress: Progress | None,
    phase: str,
    exists_step: bool,
) -> SolveResult:
    """The SMT search's answer: horizons 0..k (``single``: k alone), no further than the
    reachable-state bound (:func:`_state_steps`), which then makes an UNSAT final.

    ``exists_step`` (with ``sequential``, not with ``warm``): the search encodes ∃-step
    parallel steps (:meth:`~catc.smt.encoder.Encoder._exists_step`): a step is a run of
    activations in a fixed order, and the composition found is :func:`linearised` into a
    sequential one, which the validator replays. The horizon counts ∃-steps, so longer
    compositions are reached, but the composition is not proven shortest (``shortest`` is
    False). An UNSAT at horizon h still says that no sequential composition of at most h
    steps exists (each of its steps is an ∃-step of one activation)."""
    why = _sum_refuted(inst)
    if why is not None:  # no reachable state satisfies the goal: nothing to deepen
        result = SolveResult(SolveStatus.UNSAT, k, final=True, length_bound=use_bound(inst))
        result.reason = why
        return result
    most = _state_steps(inst, k)  # every state within this many steps: deepen no further
    if strategy == "single":
        horizons: range | tuple[int, ...] = (k,)
    else:
        horizons = range((k if most is None else most) + 1)
    # without a state bound, each UNSAT horizon also asks for a path visiting no state twice
    loops = most is None and strategy != "single" and not isinstance(search, _WarmSearch)
    result = search.run(horizons, progress, phase, loops=loops)
    if result.status is SolveStatus.UNSAT and most is not None and not result.final:
        result.final = True
        result.reason = _states_reason(most)
    if result.status is SolveStatus.SAT and exists_step:
        assert result.plan is not None
        result.plan = linearised(result.plan)
        result.shortest = False
        result.reason = "found with ∃-steps (--exists-step), each of which may fire several morphisms"
    return result


def linearised(plan: Plan) -> Plan:
    """A composition of ∃-steps as the sequential one it stands for: each step's activations
    one per step, in the order the step fires them (the encoder's, which the plan keeps)."""
    return Plan(tuple((a,) for step in plan.steps for a in step), plan.fresh)


def _loop_check_at(t: int) -> bool:
    """The horizons after whose UNSAT the search asks for a path visiting no state twice:
    the powers of two from 8 — few checks (their number logarithmic in the horizon, none
    on the shortest tasks), the first that succeeds within twice the least horizon that
    would, or 8."""
    return t >= 8 and t & (t - 1) == 0


def _sum_refuted(inst: ir.Instance) -> str | None:
    """Why no reachable state satisfies the goal by a sum of numbers that never grows (or
    never shrinks): :func:`catc.semantics.bounds.sum_refutation`; None when none shows it."""
    from catc.semantics.bounds import sum_refutation
    from catc.semantics.validate import initial_state

    if inst.domain.holes:
        return None
    return sum_refutation(inst, initial_state(inst))


def _state_steps(inst: ir.Instance, k: int) -> int | None:
    """N − 1 for a model of at most N ≤ k + 1 states (:func:`state_bound`), else None: a
    shortest composition visits no state twice, so none within N − 1 steps is none at all,
    and the deepening stops there. None also where the use limits already bound the length
    within ``k`` (that proof needs no count)."""
    uses = use_bound(inst)
    if uses is not None and uses <= k:
        return None
    n = state_bound(inst, k + 1)
    return None if n is None else max(n - 1, 0)


def _states_reason(most: int) -> str:
    return (
        f"the model has at most {counted(most + 1, 'state')}, so some shortest composition, if any, "
        f"has at most {counted(most, 'step')} (it visits no state twice)"
    )


def _forward(
    inst: ir.Instance, k: int, sequential: bool, deadline: float | None, *, prove: bool = True
) -> SolveResult | None:
    """The forward search's answer (:mod:`catc.semantics.search`), or None where it does not
    apply (parallel steps, or what it does not model): then the SMT search runs. ``prove``:
    A* proves the greedy search's composition shortest (or finds a shorter one); ``deadline``:
    a ``time.monotonic()`` instant."""
    from catc.semantics.search import SearchStatus, search

    if not sequential:
        return None
    r = search(inst, k, deadline=deadline, prove=prove)
    if r.status is SearchStatus.UNSUPPORTED:
        return None
    if r.status is SearchStatus.PLAN:
        out = SolveResult(SolveStatus.SAT, k, r.plan, length_bound=use_bound(inst))
        out.shortest = r.shortest
        if not r.shortest:
            out.reason = r.reason
        if r.first_plan is not None:
            out.timings["first_plan"] = r.first_plan
        return out
    if r.status is SearchStatus.STOPPED:
        return SolveResult(
            SolveStatus.UNKNOWN, k, reason=limits.stop_reason() or "timeout", length_bound=use_bound(inst)
        )
    why = f"forward search: {r.reason}" if r.final else None
    return SolveResult(SolveStatus.UNSAT, k, final=r.final, length_bound=use_bound(inst), reason=why)


def _presolve(
    inst: ir.Instance,
    k: int,
    sequential: bool,
    timings: dict[str, float],
    found: list[SolveResult] | None,
    *,
    consumption: bool = True,
    refuted: bool = False,
) -> Refutation | None:
    """A proof that no composition of any length exists: relaxed reachability (unless
    ``refuted``: already tried), then the consumption abstraction (issue 24's catalogs;
    ``consumption``: not before the forward search, which proves more on ground tasks and
    for which that bound costs seconds: blocks-8, 4 CPU s).  With ``found`` (a list), the
    abstraction's shortest composition (:func:`_abstract`) is tried between its solver-free
    bound and its solver check, and appended when found: then nothing else is needed."""
    t0 = time.perf_counter()
    proof = None if refuted else refute(inst)
    if proof is None and (consumption or refuted):
        proof = bound_refutation(inst)
        if proof is None and found is not None:
            shortest = _abstract(inst, k, sequential)
            if shortest is not None:
                found.append(shortest)
        if proof is None and not found and not _passes_abstraction(inst):
            proof = consumption_proof(inst)
    timings["presolve"] = timings.get("presolve", 0.0) + time.perf_counter() - t0
    return proof


def _passes_abstraction(inst: ir.Instance) -> bool:
    """Whether a set of components passes the consumption abstraction with every label
    enforced, found without a solver (:func:`cheapest_support`, checked by
    :class:`~catc.smt.consumption.FixedSet`): the abstraction is then satisfiable, its solver
    check (:func:`consumption_proof`) can prove nothing, and the process makes no Z3 context
    for it — the search makes the only one, as a hand-written script does (issue 23)."""
    order = cheapest_support(inst)
    return order is not None and FixedSet(inst).order(order) is not None


def _abstract(inst: ir.Instance, k: int, sequential: bool) -> SolveResult | None:
    """A shortest composition without the step encoding (issue 24), or None: the morphisms
    of :func:`cheapest_support`, one per step in an order they can fire, each θ at its lower
    bound.  It counts only when the independent validator accepts it within the horizon and
    its length equals :func:`least_length`, a lower bound on every composition's length —
    then no shorter one exists, which is what the deepening would prove horizon by horizon."""
    lower = least_length(inst)
    if lower == 0 or lower > k:
        return None
    FiniteSorts(inst, k)  # the universe limit holds as for an encoding (E1106)
    order = cheapest_support(inst)
    if order is None or len(order) != lower:
        return None
    bounds = frozenset(m.bound_label(p.name) for m in inst.morphisms.values() for p in m.params)
    plan = _candidate(inst, bounds, order, order)  # every θ at its lower bound (else its upper, else 0)
    if plan is None or not validate(inst, plan, horizon=k, sequential=sequential).ok:
        return None
    return SolveResult(SolveStatus.SAT, k, plan, length_bound=use_bound(inst))


def _validated(
    inst: ir.Instance, result: SolveResult, k: int, sequential: bool, prune: bool, timings: dict[str, float]
) -> None:
    """Replay the solver's composition, prune it (while there is time) and replay the result."""
    t0 = time.perf_counter()
    assert result.plan is not None
    checked(inst, result.plan, k, sequential, "the solver's composition")
    plan = prune_plan(inst, result.plan, k, sequential) if prune else result.plan
    result.plan = canonical_fresh(plan)
    result.states = checked(inst, result.plan, k, sequential, "the pruned composition")
    timings["validate"] = time.perf_counter() - t0


class _Search:
    """One solver over an encoding that grows a step at a time; the goal and the use limits
    at horizon ``t`` are checked inside a push/pop scope."""

    def __init__(
        self,
        inst: ir.Instance,
        k: int,
        sequential: bool,
        backend: str,
        timings: dict[str, float],
        assumed: frozenset[str] = frozenset(),
        exists: bool = False,
    ) -> None:
        self.k = k
        self.bound = use_bound(inst)
        # start: creating the solver (the first Z3 context of a process initialises Z3,
        # ~10 ms; a hand-written Z3 script pays it too)
        self.timings = timings
        self.tried = 0
        t0 = time.perf_counter()
        self.enc = Encoder(inst, k, sequential=sequential and not exists, assumed=assumed, exists=exists)
        t1 = time.perf_counter()
        self.solver = open_backend(backend)
        t2 = time.perf_counter()
        self.solver.add(*self.enc.script.take())
        self.timings["start"] = t2 - t1
        self.timings["encode"] += (t1 - t0) + (time.perf_counter() - t2)
        self.backend = backend
        self.loop_solver: Any = None  # the solver of :meth:`_no_simple_path`, once needed
        self.fed = (0, 0)  # how many of the encoding's declarations and assertions it has
        self.distinct = 0  # its states 0..distinct are pairwise distinct

    def run(
        self, horizons: range | tuple[int, ...], progress: Progress | None, phase: str, loops: bool = False
    ) -> SolveResult:
        """Check the goal at each horizon in turn; the first SAT or UNKNOWN answers.
        ``loops``: after an UNSAT at some horizons t (:func:`_loop_check_at`), also ask
        whether any path of t steps visits no state twice (:meth:`_no_simple_path`); when
        none does, the UNSAT is final."""
        for t in horizons:
            if progress is not None:
                progress(f"{phase}: horizon {t} of {self.k}")
            r = self._check(t)
            result = None
            if r is Check.SAT:
                result = SolveResult(
                    SolveStatus.SAT, self.k, read_plan(self.solver, self.enc, t), length_bound=self.bound
                )
            elif r is Check.UNKNOWN:
                result = self._unknown()
            self._end_check()
            if result is None and loops and _loop_check_at(t) and self._no_simple_path(t):
                result = SolveResult(SolveStatus.UNSAT, self.k, final=True, length_bound=self.bound)
                result.simple_path = t
                result.reason = (
                    f"no path of {counted(t, 'step')} visits no state twice, so some shortest composition, "
                    f"if any, has fewer steps, and none within {counted(t - 1, 'step')} exists"
                )
            if result is not None:
                break
        else:  # UNSAT at every horizon tried
            final = self.bound is not None and self.k >= self.bound
            result = SolveResult(SolveStatus.UNSAT, self.k, final=final, length_bound=self.bound)
        result.horizons_tried = self.tried
        return result

    def _no_simple_path(self, t: int) -> bool:
        """No path of ``t`` steps from the initial state visits no state twice (the solver's
        UNSAT; anything else, a timeout included, is no claim). Then every composition of
        t or more steps visits some state twice, and cutting the steps between two visits
        leaves a shorter one (its steps fire from the same states, use no morphism more
        often and end in the same state): some shortest composition, if any, has fewer than
        t steps. The same holds of parallel steps, between which the states are those a
        composition visits. States are compared on the resources some morphism writes (the
        others are one variable in every state); a non-idle step never repeats a state
        here, so an idle step (only at the end) fails the test as a repeat would."""
        t0 = time.perf_counter()
        if self.loop_solver is None:  # a solver of its own: the main one's goal checks slow
            self.loop_solver = open_backend(self.backend)  # down after a check with these constraints
        script = self.enc.script
        decls, asserts = script.decls[self.fed[0] :], script.asserts[self.fed[1] :]
        self.fed = (len(script.decls), len(script.asserts))
        distinct = [
            (None, to_text(not_(self.enc.same_state(i, j)))) for j in range(self.distinct + 1, t + 1) for i in range(j)
        ]
        self.distinct = max(self.distinct, t)  # states 0..distinct pairwise distinct, for every later t too
        self.loop_solver.add(decls, [*asserts, *distinct])
        self.timings["encode"] += time.perf_counter() - t0
        self.loop_solver.set_timeout(limits.for_check())
        t0 = time.perf_counter()
        r = self.loop_solver.check([])
        self.timings["solve"] += time.perf_counter() - t0
        return r is Check.UNSAT

    def _grow(self, t: int) -> None:
        """Encode up to step ``t``."""
        t0 = time.perf_counter()
        while len(self.enc.act) < t:
            self.enc.add_step()
        self.solver.add(*self.enc.script.take())
        self.timings["encode"] += time.perf_counter() - t0

    def _check(self, t: int) -> Check:
        """Check the goal and the use limits at horizon ``t`` (:meth:`_end_check` ends the
        scope :meth:`_goal_at` opened)."""
        self._grow(t)
        t0 = time.perf_counter()
        assumptions = self._goal_at(t)
        self.timings["encode"] += time.perf_counter() - t0
        return self._timed_check(assumptions)

    def _goal_at(self, t: int) -> list[Symbol]:
        """State the goal and the use limits at horizon ``t``: here in a new scope, with
        nothing to assume."""
        extra = [c for _, c in self.enc.goal_constraints(t)] + [c for _, c in self.enc.uses_constraints(t)]
        self.solver.push()
        self.solver.add((), [(None, c) for c in extra])
        return []

    def _timed_check(self, assumptions: Sequence[Symbol]) -> Check:
        """One check within the command's time (an exhausted budget still checks, so that
        push and pop stay paired)."""
        self.solver.set_timeout(limits.for_check())  # None: no limit, not a stale one
        t0 = time.perf_counter()
        r = self.solver.check(assumptions)
        self.timings["solve"] += time.perf_counter() - t0
        self.tried += 1
        return r

    def _end_check(self) -> None:
        self.solver.pop()

    def _unknown(self) -> SolveResult:
        reason = limits.stop_reason() or self.solver.reason_unknown()
        return SolveResult(SolveStatus.UNKNOWN, self.k, reason=reason, length_bound=self.bound)


class _WarmSearch(_Search):
    """A search whose encoding outlives one problem.  The goal at each horizon, and the
    initial values of the resources in ``assumed`` (those events have changed), are
    asserted as ``(=> lit constraint)`` and checked with ``lit`` assumed; every other initial
    value is a plain assertion (a fact the solver simplifies with, as in a cold search).
    So a problem that differs only in the goal and the initial values of ``assumed`` is
    checked on the same solver, with everything it learnt before.

    A literal no longer wanted stays, so that a value that comes back finds what the solver
    learnt about it; past the :attr:`KEEP` most recent values of a resource (and goals) the
    oldest is retired: ``(not lit)`` is asserted, and the solver drops its implication."""

    KEEP = 16

    def __init__(
        self,
        inst: ir.Instance,
        k: int,
        sequential: bool,
        backend: str,
        timings: dict[str, float],
        assumed: frozenset[str],
    ) -> None:
        super().__init__(inst, k, sequential, backend, timings, assumed)
        self.structure = _structure(inst, k, sequential, backend)
        #: the initial values asserted as facts (resource → constraint; "" when it has none)
        self.facts = {r: self._init_text(inst, r) for r in inst.resources if r not in assumed}
        self.inits: dict[str, dict[str, Symbol]] = {}  # resource → its initial values' literals
        self.known_goals: dict[tuple[ir.Literal, ...], dict[int, Symbol]] = {}  # goal → its literals
        self.goals: dict[int, Symbol] = {}  # horizon → the literal of this problem's goal there
        self.uses: dict[int, Symbol] = {}  # horizon → the literal of the use limits there
        self.goal: tuple[ir.Literal, ...] = ()
        self.literals: list[Symbol] = []  # this problem's initial values
        self.made = 0  # literals declared

    def _init_text(self, inst: ir.Instance, resource: str) -> str:
        init = inst.problem.init.get(resource)
        return "" if init is None else self.enc.init_constraint(init)

    def changed_facts(self, inst: ir.Instance) -> set[str]:
        """The resources whose initial value ``inst`` gives otherwise than the facts."""
        return {r for r, text in self.facts.items() if self._init_text(inst, r) != text}

    def retarget(self, inst: ir.Instance, timings: dict[str, float]) -> None:
        """Answer ``inst`` next (same structure and facts): its goal and the initial values
        of the assumed resources replace the previous ones."""
        t0 = time.perf_counter()
        self.timings, self.tried = timings, 0
        retired: list[Symbol] = []
        self.literals = []
        for r in sorted(self.enc.assumed):
            text = self._init_text(inst, r)
            if not text:  # no initial value: the resource starts free
                continue
            known = self.inits.setdefault(r, {})
            self.literals.append(self._literal(known, text, text))
            known[text] = known.pop(text)  # the most recent last
            while len(known) > self.KEEP:
                retired.append(known.pop(next(iter(known))))
        self.goal = inst.problem.goal
        self.goals = self.known_goals.pop(self.goal, {})
        self.known_goals[self.goal] = self.goals
        while len(self.known_goals) > self.KEEP:
            retired.extend(self.known_goals.pop(next(iter(self.known_goals))).values())
        for lit in retired:
            self.enc.add(None, to_text(not_(lit)))
        self.solver.add(*self.enc.script.take())
        timings["encode"] += time.perf_counter() - t0

    def _literal(self, table: dict[Any, Symbol], key: Any, constraint: str) -> Symbol:
        lit = table.get(key)
        if lit is None:
            self.made += 1
            lit = self.enc.script.declare(f"assume.{self.made}", SmtSort.BOOL)
            self.enc.add(None, to_text(implies(lit, constraint)))
            table[key] = lit
        return lit

    def _goal_at(self, t: int) -> list[Symbol]:
        """The goal and the use limits at horizon ``t`` behind literals, to be assumed."""
        goal = self.goals.get(t)
        if goal is None:
            goal = self._literal(self.goals, t, and_text([c for _, c in self.enc.goal_constraints(t, self.goal)]))
        assumed = [*self.literals, goal]
        if t not in self.uses:
            limits_at = [c for _, c in self.enc.uses_constraints(t)]
            if limits_at:
                self._literal(self.uses, t, and_text(limits_at))
        if t in self.uses:
            assumed.append(self.uses[t])
        self.solver.add(*self.enc.script.take())
        return assumed

    def _end_check(self) -> None:
        pass


def _structure(inst: ir.Instance, k: int, sequential: bool, backend: str) -> tuple[Any, ...]:
    """What an encoding depends on besides the initial values and the goal."""
    return (inst.domain, dict(inst.problem.objects), inst.view, k, sequential, backend)


class WarmStart:
    """What :func:`solve` keeps between the calls given the same ``warm``: the last encoding,
    its solver, and which initial values have changed so far.

    The first problem is encoded as a cold search encodes it (every initial value a fact).
    A later problem with the same structure (domain, objects, view, horizon, semantics,
    backend) reuses the encoding when its initial values differ only in resources already
    *assumed*; when one more resource's value changed, the problem is encoded afresh with
    that resource assumed too — so the resources a lifelong run's events touch end up behind
    literals, and the rest stay facts.  ``cold`` counts the encodings made, ``reused`` the
    answers given on an encoding made for an earlier problem.  ``assumed`` names resources
    known in advance to change (sensed values): they start behind literals."""

    def __init__(self, assumed: Iterable[str] = ()) -> None:
        self._search: _WarmSearch | None = None
        self.assumed: frozenset[str] = frozenset(assumed)
        self.cold = 0
        self.reused = 0

    def search(self, inst: ir.Instance, k: int, sequential: bool, backend: str, timings: dict[str, float]) -> _Search:
        old = self._search
        if old is not None and old.structure == _structure(inst, k, sequential, backend):
            changed = old.changed_facts(inst)
            if not changed:
                self.reused += 1
                old.retarget(inst, timings)
                return old
            self.assumed |= changed
        self._search = None  # the old solver goes before the new one is made
        self.assumed &= frozenset(inst.resources)
        self._search = _WarmSearch(inst, k, sequential, backend, timings, self.assumed)
        self.cold += 1
        self._search.retarget(inst, timings)
        return self._search


# ====================================================================== output


def solve_json(inst: ir.Instance, result: SolveResult) -> dict:
    plan = result.plan
    doc: dict = {
        "schema": "catc.solve/1",
        "status": result.status.value,
        "problem": inst.problem.name,
        "domain": inst.domain.name,
        "view": inst.view,
        "horizon": result.horizon,
        "sequential": result.sequential,
        "strategy": result.strategy,
        "steps": None,
        "fresh": None,
        "initial_state": None,
        "final_state": None,
        "unsat": None,
        "reason": result.reason,
        "timings": timings_json(result.timings),
    }
    if result.backend != DEFAULT_BACKEND:
        doc["backend"] = result.backend
    if not result.shortest:  # only then: the forward greedy search's plan, not proven shortest
        doc["shortest"] = False
    if plan is not None:
        doc["steps"] = steps_json(inst, plan)
        doc["fresh"] = dict(plan.fresh)
        if result.states:
            doc["initial_state"] = state_json(result.states[0])
            doc["final_state"] = state_json(result.states[-1])
            doc["units"] = units_json(inst)
            if parameter_units := parameter_units_json(inst):  # only when some parameter declares one
                doc["parameter_units"] = parameter_units
    if result.status is SolveStatus.UNSAT:
        proof = result.refutation
        doc["unsat"] = {
            "final": result.final,
            "length_bound": result.length_bound,
            "proof": "solver" if proof is None else "consumption" if proof.by == CONSUMPTION_BY else "relaxation",
            "why": None if proof is None else proof.reason,
            "label": None if proof is None else proof.label,
        }
    return doc


def unsat_sentence(inst: ir.Instance, result: SolveResult) -> str:
    k = result.horizon
    head = f"no composition within {k} step{'s' if k != 1 else ''}"
    proof = result.refutation
    if proof is not None:
        from catc.ir.labels import label_index  # answers only (the fast route imports no dataclasses)
        from catc.present.labels import describe, where

        info = label_index(inst).get(proof.label or "")
        what = f" ({' '.join(describe(info).split())}, {where(info)})" if info is not None else ""
        return (
            f"no composition of any length: {proof.reason}{what}, by {proof.by} "
            "(catc diagnose names the constraints responsible)"
        )
    if result.final and result.reason:  # the forward search saw every reachable state
        return f"{head}; this is final: {result.reason}"
    if result.final:
        return (
            f"{head}; this is final: every morphism has a use limit, so no composition needs more than "
            f"{result.length_bound} step{'s' if result.length_bound != 1 else ''}"
        )
    if result.length_bound is not None:
        return (
            f"{head} (not final: compositions may need up to {counted(result.length_bound, 'step')}; raise --horizon)"
        )
    unlimited = [m.name for m in inst.morphisms.values() if m.uses is None]
    names = ", ".join(unlimited[:3]) + (", ..." if len(unlimited) > 3 else "")
    return (
        f"{head} (not final: {names} {'has' if len(unlimited) == 1 else 'have'} no use limit; try a larger --horizon)"
    )


_COLOUR = {SolveStatus.SAT: "green", SolveStatus.UNSAT: "red", SolveStatus.UNKNOWN: "yellow"}


def render(console: Console, inst: ir.Instance, result: SolveResult, options: Mapping[str, Any]) -> None:
    status = f"[bold {_COLOUR[result.status]}]{result.status.value.upper()}[/]"
    where = where_text(inst)
    if result.plan is not None and result.status is SolveStatus.SAT:
        n = len(result.plan)
        console.print(f"{status}  composition of {n} step{'s' if n != 1 else ''} for {where}")
        if not result.shortest:
            console.print(f"[yellow]not proven shortest[/]: {result.reason}")
        print_composition(console, inst, result.plan, result.states)
    elif result.status is SolveStatus.UNSAT:
        console.print(f"{status}  {unsat_sentence(inst, result)} ({where})")
    elif result.reason == "interrupted":
        console.print(f"{status}  interrupted before an answer for {where}")
    else:
        console.print(f"{status}  the solver gave up ({result.reason}) for {where}")
    t = result.timings
    if t and result.refutation is not None:
        console.print(f"[dim]time: relaxed reachability {t.get('presolve', 0) * 1000:.0f} ms; nothing encoded[/]")
    elif t and "support" in t:
        console.print(
            f"[dim]time: presolve {t['support'] * 1000:.0f} ms (a supporting composition as short as the least length "
            f"any can have), validate {t.get('validate', 0) * 1000:.0f} ms; nothing encoded[/]"
        )
    elif t:
        engine = "Z3" if result.backend == "z3" else result.backend
        start = f"{engine} start {t['start'] * 1000:.0f} ms, " if "start" in t else ""
        console.print(
            f"[dim]time: {start}encode {t.get('encode', 0) * 1000:.0f} ms, solve {t.get('solve', 0) * 1000:.0f} ms, "
            f"validate {t.get('validate', 0) * 1000:.0f} ms; horizons tried {result.horizons_tried}[/]"
        )


QUERY = Query(
    "solve",
    summary="Find the shortest composition that reaches the goal.",
    description="PATHS is PROBLEM, or DOMAIN PROBLEM.  Exit 0 SAT, 1 UNSAT, 2 input error, 3 unknown/timeout.",
    options=(
        timeout_option(),
        Option(
            "strategy",
            ("--strategy",),
            Kind.CHOICE,
            "auto: search where the forward search applies (--sequential, no --exists-step, morphisms "
            "without parameters θ or use limits, no holes or set effects: ground tasks such as catc import "
            "pddl writes), else incremental; --json names the strategy used. "
            "incremental: deepen the horizon one step at a time (shortest composition); "
            "single: one check of the whole horizon; search: a forward search (sequential steps, "
            "ground morphisms: greedy on h_add, then A* proves it shortest or finds a shorter one; "
            "or a proof of none), else incremental; greedy: the forward greedy search alone (any "
            "composition, not proven shortest), else incremental.",
            default="auto",
            choices=STRATEGIES,
            show_default=True,
        ),
        json_option("catc.solve/1"),
        diagram_option(),
        Option(
            "prune",
            ("--no-prune",),
            Kind.NO_FLAG,
            "Keep activations the composition does not need (as the solver found them).",
        ),
        Option(
            "exists_step",
            ("--exists-step",),
            Kind.FLAG,
            "Search with ∃-step parallel steps (a step fires its morphisms in a fixed order, each on the state "
            "the earlier ones left) and answer the sequential composition they stand for: reaches longer "
            "compositions in fewer horizons, not proven shortest; implies --sequential (docs/benchmarks.md).",
            default=False,
        ),
        backend_option(),
        presolve_option(),
        certificate_option(),
    ),
    run=solve_query,
    to_json=solve_json,
    render=render,
    artifacts=diagram_artifact,
    progress=True,
)
