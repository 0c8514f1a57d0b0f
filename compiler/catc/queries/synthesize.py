"""Structural free variables μ (paper §IV-C): synthesise the missing component.

A hole ``(:hole μ :view v :max-effects n :max-preconditions p)`` is a morphism whose effects
are unknown.  Within view ``v`` (the functor F_v applied first), μ may, once, in a step of
its own: set or clear any bool resource, assign any symbolic one, add to or remove from
any set, and change any numeric resource by any amount.  One solver call minimises the
number of effects used (at most ``n``) subject to the problem becoming feasible, then —
among those — effects on resources some component already writes (a hole is a missing
capability, not a shortcut around existing components); what μ may
*assume* is then read off the state where it is applied — its precondition — keeping at
most ``p`` literals, those over resources μ writes first.

The answer is checked the honest way: the specification is turned into an ordinary IR
morphism, the composition with μ replaced by it is replayed by the independent validator,
and ``to_cat`` prints it as a ``(:morphism ...)`` skeleton that can be pasted into the
domain in place of the hole.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

from catc import ir
from catc.ir import SortKind
from catc.ir.text import effect_text, to_text
from catc.ir.views import project_instance
from catc.present.composition import print_composition
from catc.present.console import Console, counted, escape
from catc.queries.base import ExitCode, Kind, Option, Query, Result, Status, Use, json_option, timeout_option
from catc.queries.solve import SolveStatus, solve
from catc.semantics.compositions import checked
from catc.semantics.horizon import horizon_of
from catc.semantics.plan import Plan
from catc.smt.backend import DEFAULT_BACKEND, Backend, Check, open_backend
from catc.smt.encoder import Encoder
from catc.smt.holes import HoleEncoding
from catc.smt.readback import read_plan
from catgrammar import limits


class SynthesisStatus(Status):
    SYNTHESISED = "synthesised", ExitCode.OK
    NOT_NEEDED = "not-needed", ExitCode.OK  # feasible without the hole
    UNSAT = "unsat", ExitCode.FAIL  # even a component in the hole cannot help
    UNKNOWN = "unknown", ExitCode.UNKNOWN


@dataclass
class Synthesis(Result):
    query = "synthesize"
    status: SynthesisStatus
    hole: ir.Hole
    morphism: ir.Morphism | None = None
    plan: Plan | None = None
    states: tuple = ()
    step: int | None = None  # where μ is applied (1-based)
    instance: ir.Instance | None = None  # the view-projected instance, with μ as a morphism
    timings: dict[str, float] = field(default_factory=dict)
    reason: str | None = None  # why UNKNOWN


def synthesize(
    inst: ir.Instance,
    hole: str | None = None,
    *,
    horizon: int | None = None,
    sequential: bool = False,
    timeout: float | None = None,
) -> Synthesis:
    start = time.perf_counter()
    mu = inst.domain.holes[pick_hole(inst, hole)]
    if mu.view is not None:
        inst = project_instance(inst, inst.domain.views[mu.view].kept, mu.view)
    with limits.deadline(timeout):
        k = horizon_of(inst, horizon)
        result = Synthesis(SynthesisStatus.UNKNOWN, mu, instance=inst)
        try:
            return _synthesize(inst, mu, k, sequential, result, start)
        except limits.Stopped as stop:  # encoding or validating when the time ran out
            result.status, result.reason, result.morphism = SynthesisStatus.UNKNOWN, stop.reason, None
            return _finish(result, start)


def _synthesize(inst: ir.Instance, mu: ir.Hole, k: int, sequential: bool, result: Synthesis, start: float) -> Synthesis:
    plain = solve(inst, horizon=k, sequential=sequential, strategy="single")
    if plain.status is SolveStatus.SAT:
        result.status = SynthesisStatus.NOT_NEEDED
        result.plan, result.states = plain.plan, plain.states
        return _finish(result, start)
    if limits.expired():  # out of time (or interrupted) before the hole was tried
        result.reason = limits.stop_reason()
        return _finish(result, start)

    enc = Encoder(inst, k, sequential=sequential, extra_written=frozenset(inst.resources))
    encoding = HoleEncoding(enc, mu)
    enc.unroll(k)
    enc.add(None, encoding.once())
    solver = open_backend(DEFAULT_BACKEND, optimize=True)
    solver.add(*enc.script.take())
    solver.minimize(solver.intern(encoding.effects_count()))
    # Among minimal specifications, prefer effects no existing component has: the hole is a
    # missing capability, not a shortcut around the components that exist.
    written = {e.resource for m in inst.morphisms.values() for e in m.effects}
    if any(r.name in written for _, _, r, _ in encoding.selectors):
        solver.minimize(solver.intern(encoding.effects_count(written)))
    solver.set_timeout(limits.for_check())  # None: no limit, not a stale one
    r = solver.check()
    result.timings["solve"] = time.perf_counter() - start
    if r is Check.SAT and limits.expired():  # stopped (Ctrl-C) as the check ended: not read, not validated
        r = Check.UNKNOWN
    if r is not Check.SAT:
        result.status = SynthesisStatus.UNSAT if r is Check.UNSAT else SynthesisStatus.UNKNOWN
        result.reason = None if r is Check.UNSAT else limits.stop_reason() or solver.reason_unknown()
        return _finish(result, start)
    _read_specification(result, inst, encoding, solver, k, sequential)
    return _finish(result, start)


def _read_specification(
    result: Synthesis, inst: ir.Instance, encoding: HoleEncoding, solver: Backend, k: int, sequential: bool
) -> None:
    """μ's effects from the model, then what it may assume: the state where it applies,
    learnt by replaying the composition with μ as an ordinary morphism."""
    mu = encoding.hole
    effects = encoding.effects(solver)
    skeleton = ir.Morphism(
        mu.name,
        ir.MorphismKind.SOFTWARE,
        (),
        (),
        tuple(effects),
        uses=1,
        doc="synthesised by catc for hole " + mu.name,
    )
    plan = encoding.plan(solver, k, read_plan(solver, encoding.enc, k).fresh)
    states = checked(_with_morphism(inst, skeleton), plan, k, sequential, "the synthesised component's composition")
    mu_step = next(i for i, s in enumerate(plan.steps) if any(a.morphism == mu.name for a in s))
    pre = _assumptions(inst, states[mu_step], effects, mu.max_preconditions)
    final = replace(skeleton, pre=tuple(pre))
    with_mu = _with_morphism(inst, final)
    # the assumptions hold where μ applies by construction: checked all the same
    states = checked(with_mu, plan, k, sequential, "the synthesised preconditions")
    result.status = SynthesisStatus.SYNTHESISED
    result.morphism, result.plan, result.states, result.step = final, plan, states, mu_step + 1
    result.instance = with_mu


def pick_hole(inst: ir.Instance, name: str | None) -> str:
    """The hole to fill: ``name``, or the domain's only one; ValueError when there is none."""
    holes = inst.domain.holes
    if not holes:
        raise ValueError(f"domain '{inst.domain.name}' declares no (:hole ...)")
    if name is None:
        if len(holes) > 1:
            raise ValueError(f"several holes ({', '.join(holes)}): choose one")
        return next(iter(holes))
    if name not in holes:
        raise ValueError(f"no hole named '{name}' (holes: {', '.join(holes)})")
    return name


def _with_morphism(inst: ir.Instance, m: ir.Morphism) -> ir.Instance:
    morphisms = dict(inst.domain.morphisms)
    morphisms[m.name] = m
    holes = {n: h for n, h in inst.domain.holes.items() if n != m.name}
    domain = replace(inst.domain, morphisms=ir.frozen(morphisms), holes=ir.frozen(holes))
    return ir.Instance(domain, inst.problem, inst.view)


def _assumptions(inst: ir.Instance, state, effects: list[ir.Effect], limit: int | None) -> list[ir.Literal]:
    """Facts of the state where μ applies, as precondition literals: bools that hold,
    set memberships, symbolic values, and numeric lower bounds; those over resources μ
    writes first."""
    written = [e.resource for e in effects]
    order = sorted(inst.resources.values(), key=lambda r: (r.name not in written, list(inst.resources).index(r.name)))
    lits: list[ir.Expr] = []
    for r in order:
        v = state[r.name]
        ref = ir.ResourceRef(r.name, r.sort)
        if r.sort.kind is SortKind.BOOL:
            if v is True:
                lits.append(ref)
            elif r.name in written:
                lits.append(ir.BoolOp(ir.BoolOpKind.NOT, (ref,)))
        elif r.sort.kind is SortKind.SET:
            for e in sorted(v):
                lits.append(ir.Member(ir.Const(e, r.sort.element), ref))  # type: ignore[arg-type]
        elif r.sort.is_numeric:
            lits.append(ir.Compare(ir.CmpOp.GE, ref, ir.Const(v, r.sort if r.sort.kind is SortKind.INT else ir.REAL)))
        else:
            lits.append(ir.Compare(ir.CmpOp.EQ, ref, ir.Const(v, r.sort)))
    if limit is not None:
        lits = lits[:limit]
    return [ir.Literal(e, ir.Label.pre("mu", i)) for i, e in enumerate(lits, 1)]


def to_cat(m: ir.Morphism, hole: ir.Hole) -> str:
    """The synthesised component as a (:morphism ...) skeleton for the domain file."""
    pre = [to_text(l.expr) for l in m.pre]
    eff = [effect_text(e) for e in m.effects]
    lines = [
        f"  ; synthesised by catc for hole {hole.name}" + (f" (view {hole.view})" if hole.view else ""),
        f"  (:morphism {m.name}",
        "    :kind software",
        "    :uses 1",
    ]
    if pre:
        lines.append(f"    :precondition (and {' '.join(pre)})" if len(pre) > 1 else f"    :precondition {pre[0]}")
    lines.append(f"    :effect (and {' '.join(eff)}))" if len(eff) > 1 else f"    :effect {eff[0]})")
    return "\n".join(lines) + "\n"


def _finish(result: Synthesis, start: float) -> Synthesis:
    result.timings["total"] = time.perf_counter() - start
    return result


# ====================================================================== output


def synthesize_json(inst: ir.Instance, result: Synthesis) -> dict:
    m = result.morphism
    return {
        "schema": "catc.synthesize/1",
        "status": result.status.value,
        "hole": result.hole.name,
        "view": result.hole.view,
        "effects": [effect_text(e) for e in m.effects] if m else None,
        "preconditions": [to_text(lit.expr) for lit in m.pre] if m else None,
        "applied_at_step": result.step,
        "skeleton": to_cat(m, result.hole) if m is not None else None,
    }


def render(console: Console, inst: ir.Instance, result: Synthesis, options: Mapping[str, Any]) -> None:
    skeleton = to_cat(result.morphism, result.hole) if result.morphism is not None else None
    if options.get("emit") == "cat":  # only the skeleton, ready to paste into the domain
        console.print(
            escape(skeleton.rstrip("\n")) if skeleton is not None else f"; no skeleton: {result.status.value}"
        )
        return
    hole = result.hole
    if result.status is SynthesisStatus.NOT_NEEDED:
        console.print(f"SAT  no hole needed: a composition exists without '{hole.name}'")
    elif result.status is SynthesisStatus.SYNTHESISED and result.morphism is not None and skeleton is not None:
        console.print(
            f"SYNTHESISED  hole '{hole.name}'"
            + (f" in view '{hole.view}'" if hole.view else "")
            + f": {counted(len(result.morphism.effects), 'effect')} it must provide, "
            f"{counted(len(result.morphism.pre), 'precondition')} it may assume; applied at step {result.step}"
        )
        console.print(escape(skeleton.rstrip()))
        console.print("\nthe composition it completes:")
        assert result.plan is not None and result.instance is not None
        print_composition(console, result.instance, result.plan, result.states)
    elif result.status is SynthesisStatus.UNSAT:
        console.print(f"UNSAT  even a component in hole '{hole.name}' cannot make the problem feasible")
    else:
        console.print("UNKNOWN  " + ("interrupted" if result.reason == "interrupted" else "the solver gave up"))


def check(inst: ir.Instance, options: Mapping[str, Any]) -> str | None:
    try:
        pick_hole(inst, options.get("hole"))
    except ValueError as exc:
        return str(exc)
    return None


QUERY = Query(
    "synthesize",
    summary="The weakest specification of a missing component (a hole μ) that makes the problem feasible.",
    description=(
        "Exit 0 when synthesised (or no hole is needed), 1 when even a hole cannot help, 2 input error, 3 unknown."
    ),
    options=(
        Option("hole", ("--hole",), Kind.NAME, "The hole to fill (default: the domain's only one)."),
        Option(
            "emit",
            ("--emit",),
            Kind.CHOICE,
            "cat: print only the (:morphism ...) skeleton, ready to paste into the domain.",
            default="text",
            choices=("text", "cat"),
            show_default=True,
            use=Use.OUTPUT,
        ),
        timeout_option(),
        json_option("catc.synthesize/1"),
    ),
    run=synthesize,
    to_json=synthesize_json,
    render=render,
    check=check,
)
