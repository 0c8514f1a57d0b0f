"""One decision of the lifelong loop (paper Algorithm 1) for the model as it is now.

1. With a deployed composition A₀: replay it on the updated model with the independent
   validator — cheap, no solver.  Still valid: keep it.
2. Else (or with nothing deployed) look for a composition: recompose with least churn
   against A₀ (stability first, then the problem's objective), or, at the start, optimise
   (a metric or soft constraints) or solve.
3. None exists: diagnose (an irreducible core, relative to A₀) and compute the least
   restoration of the world's initial values (relax) — a proposal that waits for approval.

Every answer carries the query's own JSON document, the reason in words and the time each
phase took.  Solver queries get the configured time limits; a query that runs out of time
leaves the deployed composition as it is and says so.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from enum import StrEnum
from fractions import Fraction
from typing import TYPE_CHECKING, Any, cast

from catc import ir
from catc.api import Model, composed, deploy_query, read_plan, refuted, relax_weights, stopped_early, validate
from catc.ir.numbers import ratio_text
from catc.semantics.plan import Plan, PlanFormatError, plan_to_json

if TYPE_CHECKING:  # pragma: no cover
    from catc.api import Diagnosis, Recomposition, RelaxResult, WarmStart


@dataclass(frozen=True)
class Limits:
    """Time limits (seconds) of the solver queries a decision may run."""

    compose: float | None = 120.0
    diagnose: float | None = 30.0
    relax: float | None = 30.0
    #: Seconds all the queries of one decision may take together (``[limits] decision``):
    #: past it the decision is ``undecided`` with E1017, the deployed composition stays.
    decision: float | None = None

    def within(self, deadline: float | None) -> Limits:
        """These limits, none past ``deadline`` (a ``time.monotonic()``); OutOfBudget when
        it has passed."""
        if deadline is None:
            return self
        left = deadline - _now()
        if left <= 0:
            raise OutOfBudget
        cut = lambda limit: left if limit is None else min(limit, left)  # noqa: E731
        return Limits(cut(self.compose), cut(self.diagnose), cut(self.relax), self.decision)


def _now() -> float:
    """The clock of the decision budget (a test's fake clock replaces it)."""
    return time.monotonic()


@dataclass(frozen=True)
class RelaxPolicy:
    """How restorations weigh the initial values they change (``[relax]`` in config.toml):
    ``weights`` per resource (per unit of it), ``fixed`` resources never changed; the rest by
    catc's one policy, :func:`catc.api.relax_weights` (weight 1 when of one unit, else the
    relative change; no scale: no proposal, the operator is asked for weights)."""

    weights: dict[str, Fraction] = field(default_factory=dict)
    fixed: frozenset[str] = frozenset()

    def for_model(self, inst: ir.Instance) -> tuple[list[str], dict[str, Fraction], str | None]:
        """(``only``, ``weights``, why none) of the relax query: the initial values that may
        change, the weight of each, and why no weights exist (or None)."""
        numeric = sorted(r for r, iv in inst.problem.init.items()
                         if r in inst.resources and inst.resources[r].sort.is_numeric)  # fmt: skip
        free = [r for r in numeric if r not in self.fixed]
        only = ([f"init/{r}" for r in free] if self.fixed else ["init/"]) if free else []
        if not only:
            return [], {}, None
        given = {f"init/{r}": w for r, w in self.weights.items() if r in free}
        weights, why = relax_weights(inst, only, given)
        return only, weights, why


class OutOfBudget(Exception):
    """The decision budget ran out before the next query."""


#: The code of a decision whose budget ran out.
BUDGET_CODE = "E1017"


class Action(StrEnum):
    """What a decision does (its value is the journal's ``action``)."""

    KEEP = "keep"  # the deployed composition is still valid
    COMPOSE = "compose"  # nothing was deployed: a composition
    RECOMPOSE = "recompose"  # the deployed one no longer holds: the least change
    RESTORE = "restore"  # no composition exists: a restoration waits for approval
    STUCK = "stuck"  # no composition, nothing to propose
    UNDECIDED = "undecided"  # a query ran out of time; the deployed composition stays
    INFEASIBLE = "infeasible"  # (within decide only) no composition: restore or stuck follows

    @property
    def deploys(self) -> bool:
        """The decision's plan is the one to deploy."""
        return self in (Action.KEEP, Action.COMPOSE, Action.RECOMPOSE)


@dataclass
class Decision:
    """What to do about the model as it is now (:class:`Action`), why, and what it took."""

    action: Action
    reason: str
    plan: Plan | None = None
    documents: dict[str, Any] = field(default_factory=dict)  # query → its --json document
    timings: dict[str, float] = field(default_factory=dict)
    solver_calls: int = 0
    proposal: dict[str, Any] | None = None
    churn: str | None = None
    changes: list[dict[str, Any]] = field(default_factory=list)
    code: str | None = None  # E1017: the decision budget ran out
    #: A kept composition's states as the validator replayed them (s₀ … sₙ; not journaled):
    #: what its grounding reads.
    states: Any = field(default=None, repr=False)

    def to_json(self) -> dict[str, Any]:
        return {
            "action": self.action,
            "reason": self.reason,
            "plan": plan_to_json(self.plan) if self.plan is not None else None,
            "churn": self.churn,
            "changes": self.changes,
            "proposal": self.proposal,
            "solver_calls": self.solver_calls,
            "timings": {k: round(v, 6) for k, v in self.timings.items()},
            "documents": self.documents,
            **({"code": self.code} if self.code else {}),
        }


def incumbent_plan(inst: ir.Instance, doc: dict[str, Any] | None) -> tuple[Plan | None, str | None]:
    """A₀ read against the model as it is now, or (None, why it cannot be)."""
    if doc is None:
        return None, None
    missing = sorted({a["morphism"] for step in doc["steps"] for a in step} - set(inst.morphisms))
    if missing:
        return None, f"{', '.join(missing)} {'is' if len(missing) == 1 else 'are'} no longer in the catalogue"
    try:
        return read_plan(inst, doc), None
    except PlanFormatError as exc:
        return None, str(exc)


def kept(model: Model, incumbent: dict[str, Any] | None) -> Decision | None:
    """The keep decision when the deployed composition is still valid in ``model`` (the
    validator's replay, no solver), else None: :func:`decide` answers."""
    if incumbent is None:
        return None
    t = time.perf_counter()
    plan, _ = incumbent_plan(model.instance, incumbent)
    if plan is None:
        return None
    report = validate(model.instance, plan)
    if not report.ok:
        return None
    return Decision(Action.KEEP, KEPT, plan, timings={"validate": time.perf_counter() - t}, states=report.states)


KEPT = "the deployed composition is still valid (replayed step by step)"


def decide(model: Model, incumbent: dict[str, Any] | None, limits: Limits, warm: WarmStart | None = None,
           policy: RelaxPolicy | None = None) -> Decision:  # fmt: skip
    """``warm`` (kept by the caller from one decision to the next) lets ``solve`` answer on
    the previous decision's encoding when only initial values or the goal changed."""
    deadline = _now() + limits.decision if limits.decision is not None else None
    timings: dict[str, float] = {}
    try:
        return _decide(model, incumbent, limits, warm, deadline, timings, policy or RelaxPolicy())
    except OutOfBudget:
        return _out_of_budget(limits, timings)


def _out_of_budget(limits: Limits, timings: dict[str, float], documents: dict[str, Any] | None = None) -> Decision:
    return Decision(Action.UNDECIDED, f"error[{BUDGET_CODE}]: the decision budget of {limits.decision:g} s ran out "
                    "(config.toml [limits] decision); the deployed composition stays", documents=documents or {},
                    timings=timings, code=BUDGET_CODE)  # fmt: skip


def _decide(model: Model, incumbent: dict[str, Any] | None, limits: Limits, warm: WarmStart | None,
            deadline: float | None, timings: dict[str, float], policy: RelaxPolicy) -> Decision:  # fmt: skip
    inst = model.instance
    if incumbent is not None:
        t = time.perf_counter()
        plan, why = incumbent_plan(inst, incumbent)
        if plan is not None:
            report = validate(inst, plan)
            timings["validate"] = time.perf_counter() - t
            if report.ok:
                return Decision(Action.KEEP, KEPT, plan, timings=timings, states=report.states)
            why = "; ".join(_violation_text(v) for v in report.violations[:3])
        timings.setdefault("validate", time.perf_counter() - t)
        decision = _recompose(model, incumbent, limits.within(deadline), why or "it no longer applies")
    else:
        decision = _compose(model, limits.within(deadline), warm)
    decision.timings = {**timings, **decision.timings}
    if decision.action is Action.UNDECIDED and deadline is not None and _now() >= deadline:
        return _out_of_budget(limits, decision.timings, decision.documents)
    if decision.action is not Action.INFEASIBLE:
        return decision
    timings.update(decision.timings)
    restore = _restore(model, incumbent, limits, deadline, policy)
    restore.timings = {**decision.timings, **restore.timings}
    restore.solver_calls += decision.solver_calls
    restore.documents = {**decision.documents, **restore.documents}
    return restore


def _violation_text(v: Any) -> str:
    message = str(v.message)
    step = getattr(v, "step", None)
    return message if step is None or message.startswith("step ") else f"step {step}: {message}"


def _components(doc: dict[str, Any]) -> list[str]:
    return sorted({a["morphism"] for step in doc["steps"] for a in step})


def _recompose(model: Model, incumbent: dict[str, Any], limits: Limits, why: str) -> Decision:
    inst = model.instance
    deployed = _components(incumbent)
    vanished = [c for c in deployed if c not in inst.morphisms]
    t = time.perf_counter()
    rec = cast("Recomposition", model.query("recompose", deployed=[c for c in deployed if c in inst.morphisms],
                                            priority="stability", timeout=limits.compose))  # fmt: skip
    took = {"recompose": time.perf_counter() - t}
    doc = model.to_json(rec)
    plan = rec.result.plan
    if composed(rec):
        changes = doc["changes"] + [
            {"morphism": c, "change": "removed", "weight": None, "vanished": True} for c in vanished
        ]
        churn = ratio_text(rec.churn) if rec.churn is not None else None
        note = "" if not stopped_early(rec) else " (the best found in the time limit)"
        if vanished:
            note += f", besides removing {', '.join(vanished)}, which must go"
        return Decision(Action.RECOMPOSE, f"the deployed composition no longer holds: {why}; recomposed with least churn"
                        f" {churn}{note}", plan, {"recompose": doc}, took, 1, churn=churn, changes=changes)  # fmt: skip
    if refuted(rec):
        return Decision(Action.INFEASIBLE, f"the deployed composition no longer holds: {why}; no composition exists",
                        documents={"recompose": doc}, timings=took, solver_calls=1)  # fmt: skip
    return Decision(Action.UNDECIDED, f"the deployed composition no longer holds: {why}; recomposition ran out of time"
                    " (the deployed composition stays)", documents={"recompose": doc}, timings=took, solver_calls=1)  # fmt: skip


def _compose(model: Model, limits: Limits, warm: WarmStart | None) -> Decision:
    inst = model.instance
    name = deploy_query(inst)
    t = time.perf_counter()
    result = model.query(name, timeout=limits.compose, **({"warm": warm} if name == "solve" else {}))
    took = {name: time.perf_counter() - t}
    doc = model.to_json(result)
    plan = getattr(result, "plan", None)
    status = result.status.value
    if composed(result):
        return Decision(Action.COMPOSE, f"nothing is deployed: composed ({name}, {status})", plan, {name: doc}, took, 1)
    if refuted(result):
        return Decision(Action.INFEASIBLE, "nothing is deployed and no composition exists", documents={name: doc},
                        timings=took, solver_calls=1)  # fmt: skip
    return Decision(Action.UNDECIDED, f"nothing is deployed and {name} ran out of time", documents={name: doc},
                    timings=took, solver_calls=1)  # fmt: skip


def _restore(model: Model, incumbent: dict[str, Any] | None, limits: Limits, deadline: float | None,
             policy: RelaxPolicy) -> Decision:  # fmt: skip
    """Diagnose, then the least restoration of initial values: a proposal."""
    inst = model.instance
    limits = limits.within(deadline)
    only, weights, unweighable = policy.for_model(inst)
    relative = _components(incumbent) if incumbent is not None else []
    relative = [c for c in relative if c in inst.morphisms]
    t = time.perf_counter()
    diag = cast("Diagnosis", model.query("diagnose", relative_to=relative, timeout=limits.diagnose))
    timings = {"diagnose": time.perf_counter() - t}
    documents = {"diagnose": model.to_json(diag)}
    core = diag.cores[0] if diag.cores else []
    t = time.perf_counter()
    if not only:  # every initial value is fixed: nothing to propose
        timings["relax"] = 0.0
        return Decision(Action.STUCK, f"no composition exists (core: {', '.join(core) or 'none found'}) and every "
                        "initial value is fixed ([relax] fixed): waiting for a change of the task or the catalogue",
                        documents=documents, timings=timings, solver_calls=1)  # fmt: skip
    if unweighable is not None:  # unlike units and no scale: never 1 W for 1 USD
        timings["relax"] = 0.0
        return Decision(Action.STUCK, f"no composition exists (core: {', '.join(core) or 'none found'}) and no "
                        f"restoration is proposed: {unweighable.replace('--weights', '[relax] weights')}",
                        documents=documents, timings=timings, solver_calls=1)  # fmt: skip
    limits = limits.within(deadline)
    options: dict[str, Any] = {"only": only, **({"weights": weights} if weights else {})}
    rel = cast("RelaxResult", model.query("relax", relative_to=relative, timeout=limits.relax, **options))
    if relative and not rel.relaxations:  # nothing restores the deployed composition: any composition
        limits = limits.within(deadline)
        rel = cast("RelaxResult", model.query("relax", relative_to=(), timeout=limits.relax, **options))
    timings["relax"] = time.perf_counter() - t
    documents["relax"] = model.to_json(rel)
    values: dict[str, str] = {}
    for r in rel.relaxations:
        resource = r.label.removeprefix("init/")
        old = inst.problem.init[resource].value
        values[resource] = ratio_text(Fraction(old.value) + r.delta)  # type: ignore[union-attr]
    core_text = ", ".join(core) or "none found in the time limit"
    if not values:
        return Decision(Action.STUCK, f"no composition exists (core: {core_text}) and no change of initial values "
                        "restores one: waiting for a change of the task or the catalogue", documents=documents,
                        timings=timings, solver_calls=2)  # fmt: skip
    proposal = {
        "set": values,
        "relaxations": [
            {"label": r.label, "delta": ratio_text(r.delta), "weight": ratio_text(r.weight)} for r in rel.relaxations
        ],
        "cost": ratio_text(rel.cost) if rel.cost is not None else None,
        "proven": rel.proven,
        "core": core,
    }
    said = ", ".join(f"{k} → {v}" for k, v in values.items())
    least = (
        "the least restoration" if rel.proven else "a restoration (the least found in the time limit, not proven least)"
    )
    return Decision(Action.RESTORE, f"no composition exists (core: {core_text}); {least}: {said}",
                    documents=documents, timings=timings, solver_calls=2, proposal=proposal)  # fmt: skip
