"""The certificates of the SMT route's finals without a state count (issue 27, issue 31):
*no path visiting no state twice* (the recurrence diameter, ``simple-path``) and *a conserved
sum* (``conserved-sum``); docs/semantics.md §7.

**simple-path** (``steps`` = t, ``horizon`` = h ≥ t − 1), two obligations, each unsat:

* ``simple-path``: the step encoding of t steps from the initial state (no goal, no use
  limits) with its t + 1 states pairwise distinct (compared on the written resources, as
  :meth:`catc.smt.encoder.Encoder.same_state` does);
* ``bounded``: the bounded problem at horizon h (``catc compile``'s text: the goal at state
  h, idle steps allowed, the use limits).

Together they prove that no composition of any length exists. Suppose one does; take a
shortest, of n steps. Its states are pairwise distinct: were states i < j equal, cutting
steps i+1..j would leave a composition (its steps fire from the same states, use no morphism
more often and end in the same state) that is shorter. If n ≥ t its first t steps are a path
of t steps from the initial state with pairwise distinct states — a model of ``simple-path``;
so n ≤ t − 1 ≤ h, and the composition padded with idle steps is a model of ``bounded``. An
∃-step answer (``--exists-step``) is certified with sequential steps: a sequential
composition is an ∃-step one of one activation per step, so both obligations hold there when
they hold for ∃-steps.

**conserved-sum**: an inductive invariant over the unrelaxed one-step encoding, written and
checked as the relaxation's (:func:`catc.queries.certify.document._inductive`: initiation,
consecution, goal exclusion): every conserved sum Σ_S ≤ Σ₀ (or ≥) of
:func:`catc.semantics.bounds.conserved_sums`, every bound of
:func:`catc.semantics.bounds.numeric_ranges`, and every numeric resource no morphism writes
at its initial value (the ranges read those as constants). The claims are the certificate's;
the obligations check them, so a wrong Σ₀ is refuted by a checker, not trusted."""

from __future__ import annotations

from collections.abc import Mapping
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir import SortKind
from catc.queries.base import InputError
from catc.queries.certify.document import _header, _inductive, _number, _obligation, _produced, _script
from catgrammar import codes

# -- the recurrence diameter


def simple_path_obligations(inst: ir.Instance, steps: int, horizon: int, sequential: bool) -> list[dict]:
    """``simple-path`` (no path of ``steps`` steps with pairwise distinct states) and
    ``bounded`` (no composition of at most ``horizon`` steps), each unsat."""
    from catc.smt.encoder import Encoder
    from catc.smt.smtlib import emit_smt2

    enc = Encoder(inst, max(steps, 1), sequential=sequential)
    while len(enc.act) < steps:
        enc.add_step()
    decls, asserts = enc.script.take()
    distinct = [f"(not {enc.same_state(i, j)})" for j in range(1, steps + 1) for i in range(j)]
    return [
        _obligation(
            "simple-path",
            f"no path of {steps} steps from the initial state visits no state twice (so a shortest composition, "
            f"having pairwise distinct states, has fewer than {steps} steps)",
            _script(
                _header(inst, f"simple path: {steps} steps, pairwise distinct states, is unsat"),
                [s.declaration() for s in decls],
                [*(a for _, a in asserts), *distinct],
            ),
        ),
        _obligation(
            "bounded",
            f"no composition of at most {horizon} steps exists (the step encoding at horizon {horizon})",
            emit_smt2(inst, horizon, sequential=sequential),
        ),
    ]


def simple_path_certificate(doc: dict[str, Any], inst: ir.Instance, result: Any) -> dict | None:
    """The simple-path certificate of ``result`` (its ``simple_path``: the t of the check
    that made the UNSAT final), or None when the answer did not end that way."""
    steps = getattr(result, "simple_path", None)
    if not isinstance(steps, int) or steps < 1:
        return None
    sequential = bool(result.sequential)
    doc = doc | {"answer": "unsat", "method": "simple-path", "producer": result.backend, "horizon": steps - 1}
    doc |= {"sequential": sequential, "steps": steps}
    doc["obligations"] = simple_path_obligations(inst, steps, steps - 1, sequential)
    return _produced(doc, result.backend)


def expected_simple_path(inst: ir.Instance, doc: Mapping[str, Any], horizon: int) -> list[dict]:
    """``catc certify``'s rebuild: none match when the horizon is below ``steps`` − 1 (the
    two obligations then leave lengths steps − 1.. uncovered)."""
    steps = doc.get("steps")
    if not isinstance(steps, int) or isinstance(steps, bool) or steps < 1:
        raise InputError("a simple-path certificate needs its steps: a positive whole number", codes.BAD_CERTIFICATE)
    if horizon < steps - 1:
        return []
    return simple_path_obligations(inst, steps, horizon, bool(doc.get("sequential")))


# -- the conserved sums


def sums_json(inst: ir.Instance) -> dict | None:
    """The claims of a conserved-sum invariant: ``{"sums": [{"resources", "initial",
    "direction"}], "ranges": {name: [lo, hi]}, "constants": {name: value}}`` (exact strings;
    null: unbounded), or None when the model has no conserved sum."""
    from catc.semantics.bounds import conserved_sums, numeric_ranges
    from catc.semantics.validate import initial_state

    init = initial_state(inst)
    numbers = {n: init.get(n) for n, r in inst.resources.items() if r.sort.is_numeric and init.get(n) is not None}
    sums = conserved_sums(inst, numbers)
    if not sums:
        return None
    rng = numeric_ranges(inst, numbers)
    written = {e.resource for m in inst.domain.morphisms.values() for e in m.effects}

    def text(v: Any) -> str | None:
        return None if v is None else str(Fraction(v))

    return {
        "sums": [
            {"resources": list(members), "initial": str(total), "direction": "at most" if sign < 0 else "at least"}
            for members, total, sign in sums
        ],
        "ranges": {n: [text(lo), text(hi)] for n, (lo, hi) in rng.items() if lo is not None or hi is not None},
        "constants": {n: str(Fraction(str(v))) for n, v in numbers.items() if n not in written},
    }


def _read_sums(inst: ir.Instance, spec: Any) -> dict:
    """The certificate's claims, checked for shape against the model (E1302 otherwise)."""

    def exact(v: Any) -> bool:
        try:
            return isinstance(v, str) and isinstance(Fraction(v), Fraction)
        except (ValueError, ZeroDivisionError):
            return False

    def numeric(n: Any) -> bool:
        return isinstance(n, str) and n in inst.resources and inst.resources[n].sort.is_numeric

    ok = isinstance(spec, dict) and set(spec) == {"sums", "ranges", "constants"}
    ok = ok and isinstance(spec["sums"], list) and bool(spec["sums"])
    ok = ok and all(
        isinstance(s, dict)
        and set(s) == {"resources", "initial", "direction"}
        and isinstance(s["resources"], list)
        and s["resources"]
        and all(numeric(n) for n in s["resources"])
        and exact(s["initial"])
        and s["direction"] in ("at most", "at least")
        for s in spec["sums"]
    )
    ok = ok and isinstance(spec["ranges"], dict) and isinstance(spec["constants"], dict)
    ok = ok and all(
        numeric(n) and isinstance(b, list) and len(b) == 2 and all(x is None or exact(x) for x in b)
        for n, b in spec["ranges"].items()
    )
    ok = ok and all(numeric(n) and exact(v) for n, v in spec["constants"].items())
    if not ok:
        raise InputError(
            "a conserved-sum certificate needs its sums (resources, initial, direction), ranges and constants over "
            "the model's numeric resources",
            codes.BAD_CERTIFICATE,
        )
    return spec


def _sums_text(enc: Any, spec: Mapping[str, Any], state: Mapping[str, Any]) -> str:
    """``Inv`` over the encoder's variables of one state."""
    from catc.smt.script import and_text

    resources = enc.inst.resources
    parts: list[str] = []

    def term(n: str, real: bool) -> str:
        kind = resources[n].sort.kind
        return f"(to_real {state[n]})" if real and kind is SortKind.INT else str(state[n])

    for s in spec["sums"]:
        real = any(resources[n].sort.kind is not SortKind.INT for n in s["resources"])
        kind = SortKind.REAL if real else SortKind.INT
        total = " ".join(term(n, real) for n in s["resources"])
        op = "<=" if s["direction"] == "at most" else ">="
        parts.append(f"({op} (+ {total} {_number(Fraction(0), kind)}) {_number(Fraction(s['initial']), kind)})")
    for n, (lo, hi) in spec["ranges"].items():
        kind = resources[n].sort.kind
        parts += [f"(>= {state[n]} {_number(Fraction(lo), kind)})"] if lo is not None else []
        parts += [f"(<= {state[n]} {_number(Fraction(hi), kind)})"] if hi is not None else []
    for n, v in spec["constants"].items():
        parts.append(f"(= {state[n]} {_number(Fraction(v), resources[n].sort.kind)})")
    return and_text(parts)


def sum_obligations(inst: ir.Instance, spec: Mapping[str, Any], horizon: int, sequential: bool) -> list[dict]:
    """Initiation, consecution and goal exclusion of the conserved-sum invariant ``spec``."""
    return _inductive(inst, horizon, sequential, lambda enc, state: _sums_text(enc, spec, state))


def sum_certificate(doc: dict[str, Any], inst: ir.Instance, result: Any) -> dict | None:
    """The conserved-sum certificate of ``result``, when its final UNSAT came from a
    conserved sum (:func:`catc.semantics.bounds.sum_refutation`); None otherwise."""
    from catc.semantics.bounds import sum_refutation
    from catc.semantics.validate import initial_state

    if inst.domain.holes or sum_refutation(inst, initial_state(inst)) is None:
        return None
    spec = sums_json(inst)
    if spec is None:
        return None
    sequential = bool(result.sequential)
    doc = doc | {"answer": "unsat", "method": "conserved-sum", "producer": "catc.bounds", "horizon": result.horizon}
    doc |= {"sequential": sequential, "conserved": spec}
    doc["obligations"] = sum_obligations(inst, spec, result.horizon, sequential)
    return _produced(doc, "catc.bounds")
