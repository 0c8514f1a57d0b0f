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
from dataclasses import dataclass, field, replace

from catc import ir
from catc.ir import SortKind
from catc.ir.text import effect_text, to_text
from catc.ir.views import project_instance
from catc.queries.solve import Status, solve
from catc.semantics.compositions import checked
from catc.semantics.horizon import default_horizon
from catc.semantics.plan import Plan
from catc.smt.backend import DEFAULT_BACKEND, Check, open_backend
from catc.smt.encoder import Encoder
from catc.smt.holes import HoleEncoding
from catc.smt.readback import read_plan


@dataclass
class Synthesis:
    status: str  # "synthesised" | "not-needed" | "unsat" | "unknown"
    hole: ir.Hole
    morphism: ir.Morphism | None = None
    plan: Plan | None = None
    states: tuple = ()
    step: int | None = None  # where μ is applied (1-based)
    instance: ir.Instance | None = None  # the view-projected instance, with μ as a morphism
    timings: dict[str, float] = field(default_factory=dict)


def synthesize(
    inst: ir.Instance,
    hole_name: str | None = None,
    *,
    horizon: int | None = None,
    sequential: bool = False,
    timeout: float | None = None,
) -> Synthesis:
    start = time.perf_counter()
    holes = inst.domain.holes
    if not holes:
        raise ValueError(f"domain '{inst.domain.name}' declares no (:hole ...)")
    if hole_name is None:
        if len(holes) > 1:
            raise ValueError(f"several holes ({', '.join(holes)}): choose one")
        hole_name = next(iter(holes))
    if hole_name not in holes:
        raise ValueError(f"no hole named '{hole_name}' (holes: {', '.join(holes)})")
    hole = holes[hole_name]
    if hole.view is not None:
        inst = project_instance(inst, inst.domain.views[hole.view].kept, hole.view)
    k = default_horizon(inst) if horizon is None else horizon
    result = Synthesis("unknown", hole, instance=inst)

    plain = solve(inst, horizon=k, sequential=sequential, timeout=timeout, strategy="single")
    if plain.status is Status.SAT:
        result.status = "not-needed"
        result.plan, result.states = plain.plan, plain.states
        return _finish(result, start)

    enc = Encoder(inst, k, sequential=sequential, extra_written=frozenset(inst.resources))
    mu = HoleEncoding(enc, hole)
    enc.unroll(k)
    enc.add(None, mu.once())
    solver = open_backend(DEFAULT_BACKEND, optimize=True)
    solver.add(*enc.script.take())
    solver.minimize(solver.intern(mu.effects_count()))
    # Among minimal specifications, prefer effects no existing component has: the hole is a
    # missing capability, not a shortcut around the components that exist.
    written = {e.resource for m in inst.morphisms.values() for e in m.effects}
    if any(r.name in written for _, _, r, _ in mu.selectors):
        solver.minimize(solver.intern(mu.effects_count(written)))
    if timeout:
        solver.set_timeout(timeout)
    r = solver.check()
    result.timings["solve"] = time.perf_counter() - start
    if r is not Check.SAT:
        result.status = "unsat" if r is Check.UNSAT else "unknown"
        return _finish(result, start)
    effects = mu.effects(solver)
    skeleton = ir.Morphism(
        hole.name,
        ir.MorphismKind.SOFTWARE,
        (),
        (),
        tuple(effects),
        uses=1,
        doc="synthesised by catc for hole " + hole.name,
    )
    # Replay with μ as an ordinary morphism to learn the state where it applies.
    plan = mu.plan(solver, k, read_plan(solver, enc, k).fresh)
    states = checked(_with_morphism(inst, skeleton), plan, k, sequential, "the synthesised component's composition")
    mu_step = next(i for i, s in enumerate(plan.steps) if any(a.morphism == hole.name for a in s))
    pre = _assumptions(inst, states[mu_step], effects, hole.max_preconditions)
    final = replace(skeleton, pre=tuple(pre))
    with_mu = _with_morphism(inst, final)
    # the assumptions hold where μ applies by construction: checked all the same
    states = checked(with_mu, plan, k, sequential, "the synthesised preconditions")
    result.status = "synthesised"
    result.morphism, result.plan, result.states, result.step = final, plan, states, mu_step + 1
    result.instance = with_mu
    return _finish(result, start)


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
    return [ir.Literal(e, f"pre/{'mu'}/{i}") for i, e in enumerate(lits, 1)]


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
