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

import z3

from catc import ir
from catc.ir import SortKind
from catc.ir.text import effect_text, to_text
from catc.ir.views import project_instance
from catc.queries.solve import ValidationFailure, default_horizon
from catc.semantics.plan import Activation, Plan
from catc.smt.encoder import Encoder, _or, quote
from catc.smt.z3backend import Z3Session, to_fraction


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


class _Hole:
    """μ's variables in the encoding: one activation per step, one selector (and value) per
    possible effect, shared by all steps (μ is used at most once)."""

    def __init__(self, enc: Encoder, hole: ir.Hole):
        self.enc, self.hole = enc, hole
        self.acts: list[str] = []
        self.selectors: list[tuple[str, str, ir.Resource, object]] = []  # (kind, selector, resource, value var)
        decl = enc.script.decls
        for r in enc.resources:
            kinds: list[str]
            if r.sort.kind is SortKind.BOOL:
                kinds = ["set", "clear"]
            elif r.sort.is_numeric:
                kinds = ["change"]
            elif r.sort.kind is SortKind.SET:
                kinds = ["add", "remove"]
            else:
                kinds = ["assign"]
            for kind in kinds:
                sel = quote(f"mu.{kind}.{r.name}")
                decl.append((sel, "Bool"))
                value: object = None
                if kind == "change":
                    value = quote(f"mu.amount.{r.name}")
                    decl.append((value, "Int" if r.sort.kind is SortKind.INT else "Real"))
                elif kind in ("add", "remove", "assign"):
                    sort = r.sort.element if kind != "assign" else r.sort
                    value = quote(f"mu.value.{kind}.{r.name}")
                    decl.append((value, "Int"))
                    enc.add(None, enc._domain(value, sort))  # type: ignore[arg-type]
                self.selectors.append((kind, sel, r, value))
        for r in enc.resources:  # set and clear of one bool exclude each other
            if r.sort.kind is SortKind.BOOL:
                enc.add(None, f"(not (and |mu.set.{r.name}| |mu.clear.{r.name}|))")
        if hole.max_effects is not None:
            enc.add(
                None, f"(<= (+ 0 {' '.join(f'(ite {s} 1 0)' for _, s, _, _ in self.selectors)}) {hole.max_effects})"
            )

    def hook(self, t: int, b: dict, assigns, deltas, adds, removes) -> None:
        q = quote(f"b.mu.{t}")
        self.enc.script.decls.append((q, "Bool"))
        others = list(b.values())
        if others:
            self.enc.add(None, f"(=> {q} (not {_or(others)}))")  # μ runs alone in its step
        b[f"<{self.hole.name}>"] = q
        self.acts.append(q)
        for kind, sel, r, value in self.selectors:
            on = f"(and {q} {sel})"
            if kind == "set":
                assigns[r.name].append((on, "true"))
            elif kind == "clear":
                assigns[r.name].append((on, "false"))
            elif kind == "assign":
                assigns[r.name].append((on, value))
            elif kind == "change":
                zero = "0" if r.sort.kind is SortKind.INT else "0.0"
                deltas[r.name].append(f"(ite {on} {value} {zero})")
            elif kind == "add":
                adds[r.name].append((f"<{self.hole.name}>", on, value))
            else:
                removes[r.name].append((f"<{self.hole.name}>", on, value))

    def once(self) -> str:
        from catc.smt.encoder import at_most

        return at_most(self.acts, 1)


def synthesize(
    inst: ir.Instance,
    hole_name: str | None = None,
    *,
    horizon: int | None = None,
    sequential: bool = False,
    timeout: float | None = None,
) -> Synthesis:
    from catc.queries.solve import Status, solve
    from catc.semantics.validate import validate

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
    mu = _Hole(enc, hole)
    enc.step_hook = mu.hook
    for _ in range(k):
        enc.add_step()
    for label, c in enc.goal_constraints(k) + enc.uses_constraints(k):
        enc.add(label, c)
    enc.add(None, mu.once())
    session = Z3Session(enc, optimize=True)
    session.flush()
    opt = session.solver
    count = session.parse_term(f"(+ 0 {' '.join(f'(ite {s} 1 0)' for _, s, _, _ in mu.selectors)})")
    opt.minimize(count)
    # Among minimal specifications, prefer effects no existing component has: the hole is a
    # missing capability, not a shortcut around the components that exist.
    written = {e.resource for m in inst.morphisms.values() for e in m.effects}
    overlap = [f"(ite {s} 1 0)" for _, s, r, _ in mu.selectors if r.name in written]
    if overlap:
        opt.minimize(session.parse_term(f"(+ 0 {' '.join(overlap)})"))
    if timeout:
        session.set_timeout(timeout)
    r = opt.check()
    result.timings["solve"] = time.perf_counter() - start
    if r != z3.sat:
        result.status = "unsat" if r == z3.unsat else "unknown"
        return _finish(result, start)
    model = opt.model()
    step = next(
        t for t, q in enumerate(mu.acts) if z3.is_true(model.eval(z3.Bool(q[1:-1], model.ctx), model_completion=True))
    )
    effects = _effects(model, mu, inst)
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
    plan = _plan_with_mu(session.extract(k), model, mu, step, hole.name, k)
    with_mu = _with_morphism(inst, skeleton)
    report = validate(with_mu, plan, horizon=k, sequential=sequential)
    if not report.ok:
        raise ValidationFailure(
            "the synthesised component does not complete the composition: "
            + "; ".join(v.message for v in report.violations[:5])
        )
    mu_step = next(i for i, s in enumerate(plan.steps) if any(a.morphism == hole.name for a in s))
    pre = _assumptions(inst, report.states[mu_step], effects, hole.max_preconditions)
    final = replace(skeleton, pre=tuple(pre))
    with_mu = _with_morphism(inst, final)
    report = validate(with_mu, plan, horizon=k, sequential=sequential)
    if not report.ok:  # pragma: no cover - the assumptions hold where μ applies by construction
        raise ValidationFailure("the synthesised preconditions do not hold where μ applies")
    result.status = "synthesised"
    result.morphism, result.plan, result.states, result.step = final, plan, report.states, mu_step + 1
    result.instance = with_mu
    return _finish(result, start)


def _effects(model: z3.ModelRef, mu: _Hole, inst: ir.Instance) -> list[ir.Effect]:
    out: list[ir.Effect] = []
    n = 0
    for kind, sel, r, value in mu.selectors:
        if not z3.is_true(model.eval(z3.Bool(sel[1:-1], model.ctx), model_completion=True)):
            continue
        n += 1
        label = f"eff/{mu.hole.name}/{n}"
        if kind in ("set", "clear"):
            out.append(ir.Effect(ir.EffectKind.ASSIGN, r.name, ir.Const(kind == "set", ir.BOOL), label))
        elif kind == "change":
            raw = model.eval(
                z3.Int(value[1:-1], model.ctx) if r.sort.kind is SortKind.INT else z3.Real(value[1:-1], model.ctx),
                model_completion=True,
            )
            amount = to_fraction(raw)
            k = ir.EffectKind.INCREASE if amount >= 0 else ir.EffectKind.DECREASE
            out.append(
                ir.Effect(k, r.name, ir.Const(abs(amount), r.sort if r.sort.kind is SortKind.INT else ir.REAL), label)
            )
        else:
            sort = r.sort.element if kind != "assign" else r.sort
            index = model.eval(z3.Int(value[1:-1], model.ctx), model_completion=True).as_long()
            universe = mu.enc.grounding.universe(sort)  # type: ignore[arg-type]
            element = ir.Const(universe.elements[index], sort)  # type: ignore[arg-type]
            kinds = {"add": ir.EffectKind.ADD, "remove": ir.EffectKind.REMOVE, "assign": ir.EffectKind.ASSIGN}
            out.append(ir.Effect(kinds[kind], r.name, element, label))
    return out


def _plan_with_mu(plan_without: Plan, model, mu: _Hole, step: int, name: str, k: int) -> Plan:
    """The solver's composition with μ's activation put back in its step."""
    enc = mu.enc
    steps = []
    for t in range(k):
        acts = [
            Activation(m.name, _params(model, enc, t, m))
            for m in enc.morphisms
            if z3.is_true(model.eval(z3.Bool(enc.act[t][m.name][1:-1], model.ctx), model_completion=True))
        ]
        if t == step:
            acts.append(Activation(name))
        if acts:
            steps.append(tuple(acts))
    return Plan(tuple(steps), plan_without.fresh)


def _params(model, enc, t, m):
    from catc.smt.z3backend import value_in_model

    fresh: dict = {}
    return {p.name: value_in_model(model, enc.theta[t][(m.name, p.name)][1:-1], p.sort, enc, fresh) for p in m.params}


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
