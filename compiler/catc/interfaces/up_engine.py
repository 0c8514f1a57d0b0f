"""catc as a unified-planning planning engine.

``OneshotPlanner(name="catc")`` and ``AnytimePlanner(name="catc")``.

Register it once per process (UP 1.3 finds engines by its factory, not by entry points)::

    get_environment().factory.add_engine("catc", "catc.interfaces.up_engine", "CatcEngine")

or in an ``up.ini`` (``[engine catc]`` with ``module_name = catc.interfaces.up_engine`` and
``class_name = CatcEngine``). The problem is converted to catc's IR directly
(:mod:`catc.frontend.up_import`, no text in between) and solved with sequential steps, so a
catc composition is a UP ``SequentialPlan``; every plan is replayed by catc's validator before
it is returned.

Statuses, honestly:

* ``SOLVED_SATISFICING`` — a plan; with a metric, one not proven optimal (the time ran out, or
  the metric has no bound on the length of better plans).
* ``SOLVED_OPTIMALLY`` — only with a metric, when optimality holds for *every* plan length,
  not only within catc's horizon: plan length (the shortest plan is found by deepening one
  step at a time); action costs all positive (a plan cheaper than the first one found, of cost
  C, has at most ⌊C / c_min⌋ actions, and catc optimises over exactly that horizon); any
  metric of the final state or of non-negative costs when the state space is finite, of N ≤
  ``max_horizon`` + 1 states (some best plan visits no state twice: N − 1 actions); and
  oversubscription when every goal is reached. Otherwise ``SOLVED_SATISFICING``.
* ``UNSOLVABLE_PROVEN`` — catc's answer is a proof for every horizon: the relaxed-reachability
  refutation, or a finite state space (Boolean and object fluents, and numbers bounded by
  declaration or by the preconditions guarding their changes) whose every state is within the
  horizon searched.
* ``UNSOLVABLE_INCOMPLETELY`` — no plan within the horizon searched (``max_horizon``), or the
  solver could not decide. ``TIMEOUT`` — the time ran out before any answer (while grounding,
  encoding or solving: every stop by the clock, whatever the solver calls it).
* ``UNSUPPORTED_PROBLEM`` — what catc cannot express (the import report in the log).
* ``INTERNAL_ERROR`` — anything else that went wrong (a bug in catc or in a library it calls):
  no exception escapes ``solve()``; the log holds the error.

Unsolvable answers carry catc's diagnosis — an irreducible set of the problem's constraints
that together admit no plan, in UP's words — in the result's ``log_messages``.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Iterator
from fractions import Fraction
from typing import IO, Any

from catc import ir
from catc.frontend import up_import
from catc.frontend.up_import import ImportReport, UpImportError, UpImportStopped, plan_to_up, up_to_instance
from catc.queries.diagnose import DiagnoseStatus, diagnose
from catc.queries.optimize import OptStatus, optimize
from catc.queries.solve import SolveResult, SolveStatus, solve, state_bound
from catc.semantics.plan import Plan
from catgrammar import limits

try:
    import unified_planning as up
    from unified_planning.engines import Credits, Engine, LogLevel, LogMessage, PlanGenerationResult
    from unified_planning.engines import PlanGenerationResultStatus as Status
    from unified_planning.engines.mixins import AnytimePlannerMixin, OneshotPlannerMixin
    from unified_planning.engines.mixins.anytime_planner import AnytimeGuarantee
    from unified_planning.engines.mixins.oneshot_planner import OptimalityGuarantee
except ImportError as exc:  # the module is only imported by UP's factory, or by hand
    raise up_import.UpMissing(up_import.MISSING) from exc

__all__ = ["DEFAULT_MAX_HORIZON", "DEFAULT_OPT_HORIZON", "CatcEngine", "register"]

#: The most actions of a plan the engine searches for (each horizon is checked in turn).
DEFAULT_MAX_HORIZON = 200

#: The horizon a metric is optimised over when it bounds no plan length (final values, gains,
#: zero-cost actions): at least the first plan's length.
DEFAULT_OPT_HORIZON = 20

#: Seconds the diagnosis of an unsolvable problem may take (within the call's timeout).
DIAGNOSIS_TIME = 10.0

CREDITS = _CREDITS = Credits(
    "catc",
    "the catc authors",
    "see the catc repository",
    "https://github.com/",
    "see the catc distribution",
    "An SMT-based compiler for robot recomposition, used as a bounded sequential planner.",
    "catc grounds the problem (parameters chosen by static preconditions, instances by unified-planning), encodes it to SMT (Z3) with "
    "sequential steps, deepens the horizon one step at a time, optimises the metric, and "
    "replays every plan in an independent validator; unsolvable problems are diagnosed.",
)


class CatcEngine(Engine, OneshotPlannerMixin, AnytimePlannerMixin):
    """catc behind UP's ``OneshotPlanner`` / ``AnytimePlanner``.

    Parameters (``OneshotPlanner(name="catc", params={...})``): ``max_horizon`` (the most
    actions searched; by default N − 1 for a finite state space of N ≤ :data:`DEFAULT_MAX_HORIZON`
    states — a shortest plan visits no state twice, so nothing is lost and "none within it" is a
    proof — else :data:`DEFAULT_MAX_HORIZON`), ``opt_horizon`` (the most actions
    optimised over when the metric gives no bound, default :data:`DEFAULT_OPT_HORIZON`), ``optimize`` (default True: with a
    metric, optimise it; False: the shortest plan only), ``diagnose`` (default True)."""

    def __init__(
        self,
        max_horizon: int | None = None,
        opt_horizon: int = DEFAULT_OPT_HORIZON,
        optimize: bool = True,
        diagnose: bool = True,
    ) -> None:
        Engine.__init__(self)
        OneshotPlannerMixin.__init__(self)
        AnytimePlannerMixin.__init__(self)
        #: None: from the problem's state count (above); given: that many actions
        self.horizon_given = None if max_horizon is None else int(max_horizon)
        self.max_horizon = DEFAULT_MAX_HORIZON if max_horizon is None else int(max_horizon)
        self.opt_horizon = int(opt_horizon)
        most = limits.current().horizon
        if not (0 <= self.max_horizon <= most and 0 <= self.opt_horizon <= most):
            raise ValueError(
                f"max_horizon and opt_horizon must be between 0 and the horizon limit ({most}); "
                "raise it for a block with catgrammar.limits.using(Limits(horizon=N))"
            )
        self.optimize = bool(optimize)
        self.diagnose = bool(diagnose)

    @property
    def name(self) -> str:
        return "catc"

    @staticmethod
    def supported_kind() -> Any:
        return up_import.supported_kind()

    @staticmethod
    def supports(problem_kind: Any) -> bool:
        return bool(problem_kind <= up_import.supported_kind())

    @staticmethod
    def satisfies(optimality_guarantee: Any) -> bool:
        # catc optimises a metric, but its horizon bounds the search: it cannot promise an
        # optimal plan for every problem, so it does not declare SOLVED_OPTIMALLY; each answer's
        # status says whether that one is proven optimal (above)
        return bool(optimality_guarantee == OptimalityGuarantee.SATISFICING)

    @staticmethod
    def ensures(anytime_guarantee: Any) -> bool:
        return bool(anytime_guarantee == AnytimeGuarantee.INCREASING_QUALITY)

    @staticmethod
    def get_credits(**kwargs: Any) -> Any:
        """None when UP asks while planning (so no coloured credits banner is printed on
        every call: the banner is UP's, not the user's output); the credits themselves for
        ``get_credits(full=True)`` and :data:`CREDITS`."""
        return _CREDITS if kwargs.get("full") else None

    # ------------------------------------------------------------ UP's entry points

    def _solve(
        self,
        problem: Any,
        heuristic: Any = None,
        timeout: float | None = None,
        output_stream: IO[str] | None = None,
    ) -> Any:
        if heuristic is not None:
            warnings.warn("catc ignores the heuristic: it searches by SMT, not by states", stacklevel=2)
        return list(_Run(self, problem, timeout).guarded())[-1]

    def _get_solutions(self, problem: Any, timeout: float | None = None, output_stream: IO[str] | None = None) -> Any:
        run = _Run(self, problem, timeout, anytime=True)
        yield from run.guarded()


class _Run:
    """One call: convert, solve, optimise, diagnose; the results as they come."""

    def __init__(self, engine: CatcEngine, problem: Any, timeout: float | None, anytime: bool = False) -> None:
        self.engine, self.problem, self.anytime = engine, problem, anytime
        self.deadline = None if timeout is None else time.monotonic() + timeout
        self.log: list[Any] = []

    def remaining(self) -> float | None:
        """Seconds left (None: no limit); at least a millisecond, so that a query whose time
        is up says so (UNKNOWN, "timeout") rather than refusing a zero limit."""
        return None if self.deadline is None else max(0.001, self.deadline - time.monotonic())

    def result(self, status: Any, plan: Plan | None = None, metrics: dict[str, str] | None = None) -> Any:
        up_plan = None if plan is None else plan_to_up(plan, self.report, self.problem)
        return PlanGenerationResult(status, up_plan, "catc", metrics=metrics or {}, log_messages=list(self.log))

    def say(self, message: str, level: Any = None) -> None:
        self.log.append(LogMessage(level or LogLevel.INFO, message))

    def expired(self) -> bool:
        return self.deadline is not None and time.monotonic() >= self.deadline

    def guarded(self) -> Iterator[Any]:
        """:meth:`results`, with any exception turned into an ``INTERNAL_ERROR`` result (or a
        ``TIMEOUT`` one once the time is up): nothing escapes UP's ``solve()``."""
        self.report = ImportReport()
        try:
            yield from self.results()
        except Exception as exc:  # a bug in catc or in a library: a status, not a traceback
            if self.expired():
                self.say(f"catc: the time ran out ({type(exc).__name__}: {exc})")
                yield PlanGenerationResult(Status.TIMEOUT, None, "catc", log_messages=list(self.log))
                return
            self.say(f"catc: internal error: {type(exc).__name__}: {exc}", LogLevel.ERROR)
            yield PlanGenerationResult(Status.INTERNAL_ERROR, None, "catc", log_messages=list(self.log))

    def results(self) -> Iterator[Any]:
        try:
            self.inst, self.report = up_to_instance(self.problem, timeout=self.remaining())
        except UpImportError as refused:
            self.report = refused.report
            self.say(
                "catc cannot express this problem (import report, E1201):\n" + refused.report.text(), LogLevel.ERROR
            )
            yield self.result(Status.UNSUPPORTED_PROBLEM)
            return
        except UpImportStopped:
            self.say("catc: the time ran out while grounding the problem")
            yield self.result(Status.TIMEOUT)
            return
        except limits.LimitExceeded as past:  # grounded too large for catc's limits
            self.say(f"catc: {past.message} ({past.code})", LogLevel.ERROR)
            yield self.result(Status.UNSUPPORTED_PROBLEM)
            return
        for note in self.report.notes:
            self.say("catc import: " + note, LogLevel.DEBUG)
        if self.expired():  # the grounding used up the time
            self.say("catc: the time ran out after grounding the problem")
            yield self.result(Status.TIMEOUT)
            return
        optimising = bool(self.problem.quality_metrics) and self.engine.optimize
        first = solve(
            self.inst,
            horizon=self._horizon(),
            sequential=True,
            timeout=self.remaining(),
            presolve=True,
            # forward search: greedy on h_add, then A* proves the plan shortest (or finds a shorter
            # one) while there is time; or a proof that every reachable state was seen; SMT where
            # it cannot
            strategy="search",
        )
        if first.status is not SolveStatus.SAT:
            yield self._no_plan(first)
            return
        assert first.plan is not None
        if optimising:
            if self.anytime:
                yield self.result(Status.INTERMEDIATE, first.plan)
            yield self._optimised(first.plan, first.shortest)
        else:
            what = "a shortest plan" if first.shortest else "a plan, not proven shortest (the time ran out),"
            self.say(f"catc: {what} ({_length(first.plan)} actions, sequential steps)")
            yield self.result(Status.SOLVED_SATISFICING, first.plan)

    def _horizon(self) -> int:
        """``max_horizon`` when given; else N − 1 for a finite state space of N ≤
        ``DEFAULT_MAX_HORIZON`` states (a shortest plan visits no state twice), else the default."""
        if self.engine.horizon_given is not None:
            return self.engine.horizon_given
        states = _finite_states(self.inst, DEFAULT_MAX_HORIZON + 1)
        if states is not None:
            self.say(f"catc: at most {states} states: plans of at most {states - 1} actions searched", LogLevel.DEBUG)
            return max(states - 1, 0)
        return DEFAULT_MAX_HORIZON

    # ------------------------------------------------------------ no plan

    def _no_plan(self, r: SolveResult) -> Any:
        if r.status is SolveStatus.UNKNOWN:
            # every stop by the clock: catc's own ("timeout"), Z3's timer ("canceled"), or a
            # reason the solver gave once the deadline had passed
            if r.reason in _TIMER_REASONS or self.expired():
                self.say(
                    f"catc: the time ran out after {r.horizons_tried} of {r.horizon + 1} horizons (0 to {r.horizon})"
                )
                return self.result(Status.TIMEOUT)
            self.say(f"catc: the solver could not decide ({r.reason})", LogLevel.WARNING)
            return self.result(Status.UNSOLVABLE_INCOMPLETELY)
        states = _finite_states(self.inst, r.horizon + 1)
        proven = r.final or states is not None
        if r.refutation is not None:
            why = f"no plan of any length: {r.refutation.reason} (relaxed reachability)"
        elif r.final and not r.reason:
            why = f"no plan of any length: no plan within {r.horizon} actions, the most any plan can take"
        elif states is not None:
            why = (
                f"no plan of any length: no plan within {r.horizon} actions, and the problem has at most "
                f"{states} states, each reachable within {states - 1} actions if at all"
            )
        elif r.final:  # the forward search saw every reachable state
            why = f"no plan of any length: {r.reason}"
        else:
            why = f"no plan of at most {r.horizon} actions (longer plans were not searched: max_horizon)"
        self.say("catc: " + why)
        if proven:
            self._certificate(r)
        if self.engine.diagnose:
            self._diagnosis(min(r.horizon, 2 * len(self.inst.morphisms) + 2))
        return self.result(Status.UNSOLVABLE_PROVEN if proven else Status.UNSOLVABLE_INCOMPLETELY)

    def _certificate(self, r: Any, options: dict[str, Any] | None = None, scope: str = "") -> None:
        """The proof of an unsolvable or optimal answer in the log, for a second tool (issue
        31): a catc.certificate/1 document, or why there is none (catc.queries.certify).
        ``scope``: what the certificate proves when it is less than the answer says (an
        optimum within the horizon; the bound that makes it every length's is the log's)."""
        import json

        from catc.queries.registry import certificate_document

        doc, why = certificate_document(self.inst, r, options)
        if doc is None:
            self.say(f"catc certificate: none ({why})", LogLevel.DEBUG)
            return
        said = f" ({scope})" if scope else ""
        self.say(
            f"catc certificate{said} (check with catc.queries.certify.certify): " + json.dumps(doc), LogLevel.DEBUG
        )

    def _diagnosis(self, horizon: int) -> None:
        budget = DIAGNOSIS_TIME if self.remaining() is None else min(DIAGNOSIS_TIME, self.remaining() or 0.0)
        d = diagnose(self.inst, horizon=horizon, sequential=True, relative_to=(), timeout=budget)
        if d.status is DiagnoseStatus.UNSAT and d.cores:
            self.report.labels.setdefault("horizon", f"at most {horizon} actions (longer plans were not searched)")
            lines = [f"  - {self.report.describe(label)}" for label in d.cores[0]]
            self.say(
                f"catc diagnose: these constraints conflict: together they admit no plan of at most {horizon} "
                "actions, and without any one of them the others do (an irreducible set):\n" + "\n".join(lines)
            )
        else:
            self.say(f"catc diagnose: no core found ({d.status.value}{', ' + d.reason if d.reason else ''})")

    # ------------------------------------------------------------ a metric

    def _optimised(self, first: Plan, shortest: bool = True) -> Any:
        kind = self.report.optimal_metric
        horizon, bound_proves = self._opt_horizon(first, kind)
        if kind == "length" and not shortest:  # the greedy plan; A* ran out of time
            self.say(f"catc: a plan of {_length(first)} actions, not proven shortest (the time ran out)")
            return self.result(Status.SOLVED_SATISFICING, first, _metric(_length(first)))
        if kind == "length":
            self.say(f"catc: a shortest plan ({_length(first)} actions): optimal for plan length")
            found = SolveResult(SolveStatus.SAT, _length(first), plan=first, sequential=True)
            self._certificate(found, {"sequential": True, "shortest": True})  # nothing shorter (issue 31)
            return self.result(Status.SOLVED_OPTIMALLY, first, _metric(_length(first)))
        r = optimize(self.inst, horizon=horizon, sequential=True, timeout=self.remaining())
        if r.plan is None:  # the time ran out (or the solver gave up) before anything was settled
            self.say(f"catc optimize: {r.status.value} ({r.reason}); the first plan found is returned")
            return self.result(Status.SOLVED_SATISFICING, first)
        value = r.values[0].value if r.values else None
        shown = None if value is None else value
        if kind == "gain":
            shown = _gain(self.inst, r)
        proven = r.status is OptStatus.OPT and (bound_proves or (kind == "gain" and _all_softs_met(r)))
        if r.status is OptStatus.OPT and not proven:
            self.say(f"catc: optimal among plans of at most {horizon} actions (longer plans were not searched)")
        elif proven:
            self.say(f"catc: optimal (value {shown}) over every plan length")
            self._certificate(r, {"sequential": True}, f"optimal among plans of at most {horizon} actions")
        else:
            self.say(f"catc: the best plan found before the time ran out ({r.status.value})")
        return self.result(Status.SOLVED_OPTIMALLY if proven else Status.SOLVED_SATISFICING, r.plan, _metric(shown))

    def _opt_horizon(self, first: Plan, kind: str | None) -> tuple[int, bool]:
        """The horizon to optimise over, and whether optimality over it is optimality over
        every plan length. Two bounds prove it: with every action cost c ≥ c_min > 0, a plan
        cheaper than the first one found (cost C) has at most ⌊C / c_min⌋ actions; with a
        finite state space of N states, some best plan visits no state twice (the metric
        depends on the final state, or on costs that are never negative), so it has at most
        N − 1 actions."""
        most = self.engine.max_horizon
        length = _length(first)
        bounds = []
        states = _finite_states(self.inst, most + 1)
        if states is not None:
            bounds.append(states - 1)
        if kind == "cost":
            c_min = min((_cost(m) for m in self.inst.morphisms.values()), default=Fraction(0))
            if c_min > 0:
                c0 = sum((_cost(self.inst.morphisms[a.morphism]) for step in first.steps for a in step), Fraction(0))
                bounds.append(int(c0 // c_min))
        if bounds and max(length, min(bounds)) <= most:
            return max(length, min(bounds)), True
        return max(length, min(most, self.engine.opt_horizon)), False


#: What the queries and Z3 call a stop by the clock.
_TIMER_REASONS = frozenset({"timeout", "interrupted", "canceled"})


def _cost(m: ir.Morphism) -> Fraction:
    if m.cost is None:
        return Fraction(1)
    assert isinstance(m.cost, ir.Const) and isinstance(m.cost.value, Fraction)
    return m.cost.value


def _length(plan: Plan) -> int:
    return sum(len(step) for step in plan.steps)


def _metric(value: Any) -> dict[str, str]:
    return {} if value is None else {"catc_metric_value": str(value)}


def _all_softs_met(r: Any) -> bool:
    return all(not s.violated for s in r.softs)


def _gain(inst: ir.Instance, r: Any) -> Fraction:
    return sum((s.soft.weight for s in r.softs if not s.violated), Fraction(0))


def _finite_states_within(inst: ir.Instance, horizon: int) -> bool:
    """Every reachable state is reachable within ``horizon`` steps."""
    return _finite_states(inst, horizon + 1) is not None


def _finite_states(inst: ir.Instance, most: int) -> int | None:
    """An upper bound on the number of states when it is finite and at most ``most``, else
    None (:func:`catc.semantics.horizon.state_bound`: Boolean, object and bounded numeric
    fluents — bounds declared, or inferred from the preconditions that guard every change of
    an imported number, whose constant changes keep it on a lattice); a shortest plan visits
    no state twice, so it has fewer actions than that."""
    return state_bound(inst, most)


def register(environment: Any = None) -> None:
    """Add the engine to UP's factory as ``catc`` (once; the documented one-liner does the same)."""
    env = environment or up.environment.get_environment()
    if "catc" not in env.factory.engines:
        env.factory.add_engine("catc", __name__, "CatcEngine")


_ = up  # the package itself: imported above so that a missing extra fails here
