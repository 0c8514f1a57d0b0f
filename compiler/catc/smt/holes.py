"""The encoding of a structural free variable μ (a hole) and reading its effects back.

Within the horizon, μ may run once, alone in its step: it may set or clear any bool
resource, assign any symbolic one, add to or remove from any set, and change any numeric
resource by any amount.  Each possible effect has a selector (shared by all steps, since μ
runs once) and, where it carries a value, a value variable; at most ``max_effects``
selectors may be on.  ``catc synthesize`` minimises the selectors used and reads the chosen
effects back as IR effects.
"""

from __future__ import annotations

from collections.abc import Mapping

from catc import ir
from catc.ir import SortKind
from catc.semantics.plan import Activation, Plan
from catc.smt.backend import Backend
from catc.smt.encoder import Assigns, Deltas, Encoder, SetChanges
from catc.smt.readback import read_value
from catc.smt.script import SmtSort, Symbol, at_most, count_text, or_text


class HoleEncoding:
    """μ's variables in an encoding: one activation per step, one selector (and value) per
    possible effect.  Create it before the steps are added: it adds μ's effects to every step
    through the encoder's ``step_hook``."""

    def __init__(self, enc: Encoder, hole: ir.Hole) -> None:
        self.enc, self.hole = enc, hole
        self.acts: list[Symbol] = []
        # (kind, selector, resource, value variable or None)
        self.selectors: list[tuple[str, Symbol, ir.Resource, Symbol | None]] = []
        declare = enc.script.declare
        for r in enc.resources:
            for kind in _effect_kinds(r.sort):
                sel = declare(f"mu.{kind}.{r.name}", SmtSort.BOOL)
                value: Symbol | None = None
                if kind == "change":
                    value = declare(f"mu.amount.{r.name}", SmtSort.INT if r.sort.kind is SortKind.INT else SmtSort.REAL)
                elif kind in ("add", "remove", "assign"):
                    sort = r.sort.element if kind != "assign" else r.sort
                    assert sort is not None  # a set resource's element sort
                    value = declare(f"mu.value.{kind}.{r.name}", SmtSort.INT)
                    enc.add(None, enc.domain_constraint(value, sort))
                self.selectors.append((kind, sel, r, value))
        for r in enc.resources:  # set and clear of one bool exclude each other
            if r.sort.kind is SortKind.BOOL:
                enc.add(None, f"(not (and |mu.set.{r.name}| |mu.clear.{r.name}|))")
        if hole.max_effects is not None:
            enc.add(None, f"(<= {count_text([s for _, s, _, _ in self.selectors])} {hole.max_effects})")
        enc.step_hook = self._step

    def _step(
        self,
        t: int,
        b: dict[str, Symbol],
        assigns: dict[str, Assigns],
        deltas: dict[str, Deltas],
        adds: dict[str, SetChanges],
        removes: dict[str, SetChanges],
    ) -> None:
        q = self.enc.script.declare(f"b.mu.{t}", SmtSort.BOOL)
        others = list(b.values())
        if others:
            self.enc.add(None, f"(=> {q} (not {or_text(others)}))")  # μ runs alone in its step
        b[f"<{self.hole.name}>"] = q
        self.acts.append(q)
        for kind, sel, r, value in self.selectors:
            on = f"(and {q} {sel})"
            if kind == "set":
                assigns[r.name].append((on, "true"))
            elif kind == "clear":
                assigns[r.name].append((on, "false"))
            else:
                assert value is not None  # every other kind of effect has a value variable
                if kind == "assign":
                    assigns[r.name].append((on, value))
                elif kind == "change":
                    zero = "0" if r.sort.kind is SortKind.INT else "0.0"
                    deltas[r.name].append(f"(ite {on} {value} {zero})")
                elif kind == "add":
                    adds[r.name].append((f"<{self.hole.name}>", on, value))
                else:
                    removes[r.name].append((f"<{self.hole.name}>", on, value))

    def once(self) -> str:
        """μ runs at most once (assert after the steps are added)."""
        return at_most(list(self.acts), 1)

    def effects_count(self, only: set[str] | None = None) -> str:
        """The number of effects μ uses (over resources in ``only``, when given)."""
        return count_text([s for _, s, r, _ in self.selectors if only is None or r.name in only])

    # ------------------------------------------------------------ reading a model
    def applied_step(self, backend: Backend) -> int:
        """The step (0-based) where the model applies μ."""
        return next(t for t, q in enumerate(self.acts) if backend.value(q) is True)

    def effects(self, backend: Backend) -> list[ir.Effect]:
        """The effects the model selects, as IR effects labelled ``eff/μ/n``."""
        out: list[ir.Effect] = []
        for kind, sel, r, value in self.selectors:
            if backend.value(sel) is not True:
                continue
            label = ir.Label.eff(self.hole.name, len(out) + 1)
            if kind in ("set", "clear"):
                out.append(ir.Effect(ir.EffectKind.ASSIGN, r.name, ir.Const(kind == "set", ir.BOOL), label))
                continue
            assert value is not None
            raw = backend.value(value)
            assert not isinstance(raw, bool)
            if kind == "change":
                effect = ir.EffectKind.INCREASE if raw >= 0 else ir.EffectKind.DECREASE
                sort = r.sort if r.sort.kind is SortKind.INT else ir.REAL
                out.append(ir.Effect(effect, r.name, ir.Const(abs(raw), sort), label))
            else:
                of = r.sort.element if kind != "assign" else r.sort
                assert of is not None  # a set resource's element sort
                universe = self.enc.finite.universe(of)
                element = ir.Const(universe.elements[int(raw)], of)
                kinds = {"add": ir.EffectKind.ADD, "remove": ir.EffectKind.REMOVE, "assign": ir.EffectKind.ASSIGN}
                out.append(ir.Effect(kinds[kind], r.name, element, label))
        return out

    def plan(self, backend: Backend, k: int, fresh: Mapping[str, str]) -> Plan:
        """The model's composition with μ's activation in its step."""
        enc = self.enc
        step = self.applied_step(backend)
        steps = []
        for t in range(k):
            acts = []
            for m in enc.morphisms:
                if backend.value(enc.act[t][m.name]) is not True:
                    continue
                params = {
                    p.name: read_value(backend, enc, enc.theta[t][(m.name, p.name)], p.sort, {}) for p in m.params
                }
                acts.append(Activation(m.name, params))
            if t == step:
                acts.append(Activation(self.hole.name))
            if acts:
                steps.append(tuple(acts))
        return Plan(tuple(steps), fresh)


def _effect_kinds(sort: ir.Sort) -> list[str]:
    if sort.kind is SortKind.BOOL:
        return ["set", "clear"]
    if sort.is_numeric:
        return ["change"]
    if sort.kind is SortKind.SET:
        return ["add", "remove"]
    return ["assign"]
