"""certify: check a ``catc.certificate/1`` document — the proof that comes with an answer no
composition can show — with tools catc did not write (docs/semantics.md §7).

A certificate is a list of *obligations*: a self-contained SMT-LIB2 script whose
``(check-sat)`` must answer ``unsat`` (or ``sat``), or a composition the independent
validator must replay (``valid``); each says what it proves, which tool produced the answer
and which checkers must confirm it — the ``z3`` binary (installed by z3-solver) and cvc5's own
SMT-LIB2 front end, each in a process of its own with a time limit, or ``catc.validator``.

* a final UNSAT by **relaxed reachability** (:mod:`catc.semantics.relaxed`): the relaxed
  fixpoint — intervals, possible values, may/must sets — as an *inductive invariant* of the
  unrelaxed one-step encoding (one parallel step, which covers sequential ones):
  ``Init ∧ ¬Inv``, ``Inv ∧ Step ∧ ¬Inv′`` and ``Inv ∧ Goal``, each unsat;
* a final UNSAT by **the step encoding at a complete horizon**: the bounded problem (``catc
  compile``'s text) unsat, and the horizon complete (Σ uses, a linear-arithmetic obligation);
* a **core** (``catc diagnose``): diagnose's labelled formula with the core enforced, unsat,
  and per member a witness composition of the rest (or a ``sat`` obligation);
* a **least restoration** (``catc relax``): the witness on the relaxed model with its
  weighted total, and relax's slack formula below that total, unsat;
* an **optimum** (``catc optimize``, ``catc recompose``): the witness with its values
  recomputed, and "lexicographically better within the horizon", unsat.

``catc certify PROBLEM CERT`` rebuilds every SMT obligation from the model it is given and the
certificate's claims, so a certificate for another model, or one whose text was edited, is a
mismatch before any solver runs; then it runs the checkers.  It exits 0 only when every
obligation is proven by a checker other than the tool that produced the answer and no checker
answers the opposite; 1 when one is refuted or does not match (the JSON names it and the
checker); 3 when one could not be decided (a time limit, a checker that is not installed).
`--certificate FILE` on the queries writes one (:func:`certificate_artifact`).
"""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Collection, Mapping, Sequence
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir import SortKind
from catc.present.console import Console, counted, escape
from catc.queries.base import (
    ExitCode,
    InputError,
    Kind,
    Option,
    Query,
    Result,
    Status,
    json_option,
    objectives_option,
)
from catgrammar import codes

SCHEMA = "catc.certificate/1"
CHECKERS = ("z3", "cvc5")
RELAXED = "catc.relaxed"  # the producer of an invariant: catc's relaxed reachability
CONSUMPTION = "catc.consumption"  # issue 24's h_max least-consumption bound (no solver)
SEARCH = "catc.search"  # the forward search's reachable states
#: How long each checker may take on one obligation, in seconds (``--check-timeout``).
CHECK_TIMEOUT = 60.0


# ====================================================================== building


class NotCertifiable(Exception):
    """This answer carries no certificate (E1304): a positive answer, or a "no" of a kind
    catc cannot certify yet (the message says which)."""


def _header(inst: ir.Instance, what: str) -> list[str]:
    return [
        f"; catc.certificate/1 obligation: {what}",
        f"; problem '{inst.problem.name}' of domain '{inst.domain.name}'"
        + (f", view '{inst.view}'" if inst.view else ""),
        "(set-logic ALL)",
    ]


def _script(head: list[str], decls: Sequence[str], asserts: Sequence[str]) -> str:
    return "\n".join([*head, *decls, *(f"(assert {a})" for a in asserts), "(check-sat)"]) + "\n"


def _number(v: Fraction, kind: SortKind) -> str:
    from catc.smt.script import int_literal, real_literal

    return int_literal(int(v)) if kind is SortKind.INT else real_literal(v)


# -- the invariant as JSON (what a reader sees) and as SMT-LIB2 (what the checkers see)


def invariant_json(inst: ir.Instance, state: Mapping[str, Any]) -> dict[str, dict]:
    """The relaxed fixpoint, resource by resource: ``{"interval": [lo, hi]}`` (null: ±∞),
    ``{"values": [...]}`` (a Boolean's or symbol's possible values; null: any) or
    ``{"may": [...] | null, "must": [...]}`` (a set's elements)."""
    from catc.semantics.relaxed import Finite, Interval, SetValue

    out: dict[str, dict] = {}
    for name in inst.resources:
        v = state[name]
        if isinstance(v, Interval):
            out[name] = {"interval": [None if v.lo is None else str(v.lo), None if v.hi is None else str(v.hi)]}
        elif isinstance(v, Finite):
            out[name] = {"values": None if v.values is None else sorted(v.values, key=repr)}
        else:
            assert isinstance(v, SetValue)
            out[name] = {"may": None if v.may is None else sorted(v.may, key=str), "must": sorted(v.must, key=str)}
    return out


def _index(enc: Any, sort: ir.Sort, value: object) -> int | None:
    u = enc.finite.universe(sort)
    return u.index(value) if isinstance(value, str) and value in u.elements else None


def _inv_of(enc: Any, r: ir.Resource, spec: Mapping[str, Any], var: Any) -> list[str]:
    """The conjuncts ``spec`` (one resource's entry of the invariant) states of ``var``."""
    kind = r.sort.kind
    if "interval" in spec:
        lo, hi = spec["interval"]
        parts = [f"(>= {var} {_number(Fraction(lo), kind)})"] if lo is not None else []
        return parts + ([f"(<= {var} {_number(Fraction(hi), kind)})"] if hi is not None else [])
    if "values" in spec:
        values = spec["values"]
        if values is None:
            return []
        if kind is SortKind.BOOL:
            if set(values) >= {True, False}:
                return []
            return [var if True in values else f"(not {var})"] if values else ["false"]
        idx = [_index(enc, r.sort, v) for v in values]
        if any(i is None for i in idx):  # a value the universe does not name: no claim
            return []
        return (
            [f"(or {' '.join(f'(= {var} {i})' for i in idx)})" if len(idx) > 1 else f"(= {var} {idx[0]})"]
            if idx
            else ["false"]
        )
    assert r.sort.element is not None
    parts = []
    for element in spec["must"]:
        i = _index(enc, r.sort.element, element)
        parts.append(var[i] if i is not None else "false")
    may = spec["may"]
    if may is not None:
        allowed = {_index(enc, r.sort.element, e) for e in may}
        parts += [f"(not {b})" for i, b in var.items() if i not in allowed]
    return parts


def invariant_text(enc: Any, inv: Mapping[str, Mapping[str, Any]], state: Mapping[str, Any]) -> str:
    """``Inv`` over the encoder's variables of one state."""
    from catc.smt.script import and_text

    parts: list[str] = []
    for name, r in enc.inst.resources.items():
        parts += _inv_of(enc, r, inv[name], state[name])
    return and_text(parts)


def _read_invariant(inst: ir.Instance, inv: Any) -> dict[str, dict]:
    """The certificate's invariant, checked for shape against the model (E1302 otherwise)."""
    if not isinstance(inv, dict) or set(inv) != set(inst.resources):
        raise InputError("the invariant must give every resource of the model, and only those", codes.BAD_CERTIFICATE)
    for name, spec in inv.items():
        r = inst.resources[name]
        ok = isinstance(spec, dict) and (
            (r.sort.is_numeric and set(spec) == {"interval"} and _pair(spec["interval"]))
            or (r.sort.kind is SortKind.SET and set(spec) == {"may", "must"} and isinstance(spec["must"], list))
            or (not r.sort.is_numeric and r.sort.kind is not SortKind.SET and set(spec) == {"values"})
        )
        if not ok:
            raise InputError(f"the invariant of resource '{name}' does not fit its sort", codes.BAD_CERTIFICATE)
    return inv


def _pair(v: Any) -> bool:
    if not (isinstance(v, list) and len(v) == 2):
        return False
    try:
        return all(x is None or isinstance(Fraction(x), Fraction) for x in v)
    except (ValueError, TypeError, ZeroDivisionError):
        return False


def invariant_obligations(inst: ir.Instance, inv: Mapping[str, Mapping[str, Any]], horizon: int) -> list[dict]:
    """Initiation, consecution and goal exclusion of ``inv`` over the unrelaxed one-step
    encoding (the symbolic universes of ``horizon``)."""
    return _inductive(inst, horizon, False, lambda enc, state: invariant_text(enc, inv, state))


def _inductive(inst: ir.Instance, horizon: int, sequential: bool, inv_of: Any) -> list[dict]:
    """Initiation, consecution and goal exclusion of the invariant ``inv_of(encoder, state
    variables)`` over the unrelaxed one-step encoding (parallel, or ``sequential``)."""
    from catc.smt.encoder import Encoder
    from catc.smt.script import at_most

    enc = Encoder(inst, max(horizon, 1), sequential=sequential)
    decls0, asserts0 = enc.script.take()
    base = [s.declaration() for s in decls0]
    state = [a for label, a in asserts0 if not (label or "").startswith("init/")]
    init = [a for label, a in asserts0 if (label or "").startswith("init/")]
    enc.add_step()
    decls1, asserts1 = enc.script.take()
    step = [a for _, a in asserts1]
    step += [at_most([enc.act[0][m.name]], 0) for m in inst.morphisms.values() if m.uses == 0]
    inv0, inv1 = inv_of(enc, enc.states[0]), inv_of(enc, enc.states[1])
    goal = [c for _, c in enc.goal_constraints(0)]
    return [
        _obligation(
            "initiation",
            "the initial state satisfies the invariant (Init ⇒ Inv)",
            _script(_header(inst, "initiation: Init ∧ ¬Inv is unsat"), base, [*state, *init, f"(not {inv0})"]),
        ),
        _obligation(
            "consecution",
            "one step of the unrelaxed encoding keeps the invariant (Inv ∧ Step ⇒ Inv′)",
            _script(
                _header(inst, "consecution: Inv ∧ Step ∧ ¬Inv′ is unsat"),
                base + [s.declaration() for s in decls1],
                [*state, inv0, *step, f"(not {inv1})"],
            ),
        ),
        _obligation(
            "goal",
            "no state satisfying the invariant satisfies the goal (Inv ∧ Goal ⇒ ⊥)",
            _script(_header(inst, "goal: Inv ∧ Goal is unsat"), base, [*state, inv0, *goal]),
        ),
    ]


def consumption_obligations(inst: ir.Instance) -> list[dict]:
    """The consumption abstraction of issue 24 (:class:`catc.smt.consumption.Consumption`,
    every label enforced): unsat.  Every composition of any length gives a model of it (its
    used components, their first firings, what they consume), so no composition exists."""
    from catc.smt.consumption import Consumption

    a = Consumption(inst)
    body = [*a.assertions, *(str(a.indicator[label]) for label in a.labels)]
    return [
        _obligation(
            "consumption",
            "no choice of components reaches the goal within what the bounded, only-decreasing resources have "
            "(the consumption abstraction: used components, first firings, total consumption)",
            _script(
                _header(inst, "consumption: the abstraction of every composition is unsat"),
                [s.declaration() for s in a.declarations],
                body,
            ),
        )
    ]


def consumption_claims(inst: ir.Instance) -> list[dict]:
    """The h_max least-consumption bounds that exceed a resource's room (what a reader sees;
    certify checks each room against the model)."""
    from catc.smt.consumption import least_consumption, room

    return [
        {"resource": name, "least": str(least), "room": str(room(inst, name))}
        for name, least in least_consumption(inst).items()
        if least > room(inst, name)
    ]


def _claims_hold(inst: ir.Instance, claims: Any) -> bool:
    """Each claimed bound names a bounded, only-decreasing resource, its room as the model
    gives it, and a least consumption above that room."""
    from catc.smt.consumption import _decreasing, room

    decreasing = _decreasing(inst)
    if not isinstance(claims, list):
        return False
    try:
        return all(
            isinstance(c, dict)
            and c.get("resource") in decreasing
            and Fraction(str(c.get("room"))) == room(inst, c["resource"])
            and Fraction(str(c.get("least"))) > Fraction(str(c.get("room")))
            for c in claims
        )
    except (ValueError, ZeroDivisionError):
        return False


#: The most states a forward search's invariant lists (more: E1304, with the count).
STATE_LIMIT = 2000


def states_json(inst: ir.Instance, names: Sequence[str], states: Sequence[Sequence[Any]]) -> dict:
    """The reachable states as JSON: the resources, and per state their values (a number as
    an exact string, a Boolean, a symbol's name)."""

    def value(v: Any) -> Any:
        return v if isinstance(v, bool | str) else str(Fraction(v))

    return {"resources": list(names), "values": [[value(v) for v in s] for s in states]}


def _read_states(inst: ir.Instance, spec: Any) -> dict:
    """The certificate's state set, checked for shape against the model (E1302 otherwise)."""
    ok = (
        isinstance(spec, dict)
        and set(spec) == {"resources", "values"}
        and isinstance(spec["resources"], list)
        and sorted(spec["resources"]) == sorted(inst.resources)
        and isinstance(spec["values"], list)
        and all(isinstance(s, list) and len(s) == len(spec["resources"]) for s in spec["values"])
    )
    if not ok:
        raise InputError("the states must give a value of every resource of the model per state", codes.BAD_CERTIFICATE)
    for s in spec["values"]:
        for name, v in zip(spec["resources"], s):
            sort = inst.resources[name].sort
            good = (
                (sort.is_numeric and isinstance(v, str) and _pair([v, None]))
                or (sort.kind is SortKind.BOOL and isinstance(v, bool))
                or (sort.kind in (SortKind.SYMBOL, SortKind.ENUM) and isinstance(v, str))
            )
            if not good:
                raise InputError(f"a state's value of resource '{name}' does not fit its sort", codes.BAD_CERTIFICATE)
    return spec


def _states_text(enc: Any, spec: Mapping[str, Any], state: Any) -> str:
    """``Inv``: the state is one of ``spec``'s (a disjunction of conjunctions of equalities)."""
    from catc.smt.script import and_text, or_text

    rows = []
    for values in spec["values"]:
        parts = []
        for name, v in zip(spec["resources"], values):
            r, var = enc.inst.resources[name], state[name]
            if r.sort.kind is SortKind.BOOL:
                parts.append(var if v else f"(not {var})")
            elif r.sort.is_numeric:
                parts.append(f"(= {var} {_number(Fraction(v), r.sort.kind)})")
            else:
                i = _index(enc, r.sort, v)
                parts.append("false" if i is None else f"(= {var} {i})")
        rows.append(and_text(parts))
    return or_text(rows)


def reachable_obligations(inst: ir.Instance, spec: Mapping[str, Any], horizon: int) -> list[dict]:
    """Initiation, consecution and goal exclusion of "the state is one the forward search
    reached" over the unrelaxed sequential one-step encoding."""
    return _inductive(inst, horizon, True, lambda enc, state: _states_text(enc, spec, state))


def bounded_obligations(inst: ir.Instance, horizon: int, sequential: bool) -> list[dict]:
    """The bounded problem at ``horizon`` (``catc compile``'s SMT-LIB2) and the completeness
    of that horizon: with every morphism limited, a composition has at most Σ uses non-idle
    steps, so none needs more than ``horizon`` steps."""
    from catc.smt.smtlib import emit_smt2

    morphisms = list(inst.morphisms.values())
    decls = [f"(declare-fun |n.{m.name}| () Int)" for m in morphisms] + ["(declare-fun |steps| () Int)"]
    facts = [f"(and (<= 0 |n.{m.name}|) (<= |n.{m.name}| {m.uses}))" for m in morphisms if m.uses is not None]
    total = "(+ 0 " + " ".join(f"|n.{m.name}|" for m in morphisms) + ")"
    facts += [f"(<= |steps| {total})", f"(> |steps| {horizon})"]
    return [
        _obligation(
            "bounded",
            f"no composition of at most {horizon} steps exists (the step encoding at horizon {horizon})",
            emit_smt2(inst, horizon, sequential=sequential),
        ),
        _obligation(
            "complete-horizon",
            f"no composition needs more than {horizon} steps (each non-idle step activates a morphism; "
            "n.m ≤ :uses of m)",
            _script(_header(inst, "completeness of the horizon: the use limits"), decls, facts),
        ),
    ]


def _obligation(name: str, proves: str, smtlib: str) -> dict:
    return {"name": name, "proves": proves, "expect": "unsat", "checkers": list(CHECKERS), "smtlib": smtlib}


def certificate(inst: ir.Instance, result: Any) -> dict:
    """The certificate of ``result``, a final "no" of ``catc solve`` (NotCertifiable
    otherwise)."""
    from catc.semantics.horizon import use_bound
    from catc.semantics.relaxed import RelaxedAnalysis

    if getattr(result, "status", None) is None or result.status.value != "unsat":
        raise NotCertifiable("only a final UNSAT answer (no composition of any length) carries a certificate")
    doc: dict[str, Any] = {
        "schema": SCHEMA,
        "problem": inst.problem.name,
        "domain": inst.domain.name,
        "view": inst.view,
    }
    if not result.final:  # a bounded no: a certificate only when the reachable states are few and goal-free
        found = _reachable(inst, doc, result) if result.sequential else None
        if found is None:
            raise NotCertifiable("only a final UNSAT answer (no composition of any length) carries a certificate")
        return found
    analysis = RelaxedAnalysis(inst, _everything())
    if analysis.refutation is not None and len(analysis.state) == len(inst.resources):
        inv = invariant_json(inst, analysis.state)
        doc |= {"answer": "unsat", "method": "invariant", "producer": RELAXED, "horizon": result.horizon}
        doc["invariant"] = inv
        doc["obligations"] = invariant_obligations(inst, inv, result.horizon)
        return _produced(doc, RELAXED)
    bound = use_bound(inst)
    if bound is not None and result.horizon >= bound:
        doc |= {"answer": "unsat", "method": "bounded", "producer": result.backend, "horizon": result.horizon}
        doc["sequential"] = bool(result.sequential)
        doc["obligations"] = bounded_obligations(inst, result.horizon, bool(result.sequential))
        return _produced(doc, result.backend)
    if getattr(result, "refutation", None) is not None and _abstraction_refutes(inst):
        claims = consumption_claims(inst)
        producer = CONSUMPTION if claims else "z3"  # the h_max bound needs no solver; else z3 checked it
        doc |= {"answer": "unsat", "method": "consumption", "producer": producer, "horizon": result.horizon}
        doc["bounds"] = claims
        doc["obligations"] = consumption_obligations(inst)
        return _produced(doc, producer)
    if result.sequential and (getattr(result, "reason", None) or "").startswith("forward search"):
        found = _reachable(inst, doc, result)
        if found is None:
            raise NotCertifiable(
                f"the forward search's reachable states are more than {STATE_LIMIT} (or not all of them can be "
                "written): their invariant is not certified"
            )
        return found
    raise NotCertifiable(
        "this UNSAT was proven neither by relaxed reachability at its fixpoint, nor by the step encoding at a "
        "complete horizon, nor by the consumption abstraction or the forward search: no certificate yet"
    )


def _reachable(inst: ir.Instance, doc: dict[str, Any], result: Any) -> dict | None:
    """The reachable-states certificate (sequential steps): every state compositions of any
    length reach, at most :data:`STATE_LIMIT` and none a goal state; None otherwise."""
    from catc.semantics.search import reachable_states

    found = reachable_states(inst, STATE_LIMIT)
    if found is None:
        return None
    spec = states_json(inst, *found)
    doc = doc | {"answer": "unsat", "method": "reachable", "producer": SEARCH, "horizon": result.horizon}
    doc |= {"sequential": True, "states": spec, "obligations": reachable_obligations(inst, spec, result.horizon)}
    return _produced(doc, SEARCH)


def _abstraction_refutes(inst: ir.Instance) -> bool:
    from catc.smt.backend import Check
    from catc.smt.consumption import Consumption

    a = Consumption(inst)
    return bool(a.labels) and a.check(a.labels)[0] is Check.UNSAT


# -- a core of catc diagnose: its UNSAT, and a witness for each member it cannot lose

WITNESS = "catc.validator"  # the checker of a witness composition


def _labelled(inst: ir.Instance, horizon: int, sequential: bool, components: Sequence[str] | None) -> Any:
    from catc.smt.labelled import LabelledModel

    return LabelledModel(inst, horizon, sequential=sequential, components=components)


def _extended(inst: ir.Instance, horizon: int, components: Sequence[str] | None) -> int:
    """The steps diagnose's labelled formula reaches past ``horizon`` (its ``horizon`` label)."""
    from catc.smt.labelled import _extended_horizon

    return _extended_horizon(inst, horizon, components)


def _core_text(model: Any, inst: ir.Instance, enforced: Sequence[str], what: str) -> str:
    """The labelled formula diagnose asks (every label behind its indicator) with the
    indicators of ``enforced`` asserted."""
    decls, asserts = model.formula()
    body = [text for _, text in asserts] + [str(model.indicator[label]) for label in enforced]
    return _script(_header(inst, what), [s.declaration() for s in decls], body)


def core_obligations(
    inst: ir.Instance,
    core: Sequence[str],
    horizon: int,
    sequential: bool,
    components: Sequence[str] | None,
    sat_for: Sequence[str] | None = None,
    proof: str = "labelled",
) -> tuple[list[dict], dict[str, str]]:
    """The core's UNSAT obligation, and for each member of ``sat_for`` (default: all) the text
    of "the core without it is satisfiable" (used when no witness composition is at hand).
    ``proof``: the core's UNSAT over diagnose's labelled formula (``labelled``), or over the
    consumption abstraction with the core's labels enforced (``consumption``: horizon-free,
    so it proves more; :func:`consumption_core_text`)."""
    from catc.ir.labels import label_index

    asked = list(core if sat_for is None else sat_for)
    lazy = proof == "consumption" and not asked and set(core) <= set(label_index(inst, horizon))
    model = None if lazy else _labelled(inst, horizon, sequential, components)  # (its encoding takes a while)
    unknown = [] if model is None else [label for label in core if label not in model.indicator]
    if unknown:
        raise InputError(f"the core names labels the model does not have: {', '.join(unknown)}", codes.BAD_CERTIFICATE)
    if proof == "consumption":
        unsat = _obligation(
            "core",
            f"the {len(core)} constructs of the core admit no composition of any length (the consumption "
            "abstraction with the core's labels enforced: used components, first firings, total consumption)",
            consumption_core_text(inst, core, components),
        )
    elif proof == "labelled" and model is not None:
        unsat = _obligation(
            "core",
            f"the {len(core)} constructs of the core admit no composition (diagnose's labelled formula, "
            f"horizon {horizon}, extended to {model.extended})",
            _core_text(model, inst, core, "core: the core's labels together are unsat"),
        )
    else:
        raise InputError(f"unknown proof of a core {proof!r}: labelled or consumption", codes.BAD_CERTIFICATE)
    sat = {
        label: _core_text(model, inst, [x for x in core if x != label], f"without {label} the core is satisfiable")
        for label in asked
        if model is not None
    }
    return [unsat], sat


def consumption_core_text(inst: ir.Instance, core: Sequence[str], components: Sequence[str] | None) -> str:
    """The consumption abstraction (:class:`catc.smt.consumption.Consumption`, relative to
    ``components``) with the indicators of the core's labels it has asserted and every other
    indicator denied: every composition of any length meeting the core's labels gives a model
    of it with the core's indicators true, and each indicator occurs *antitonically* — the
    guard of an implication, a ``(not A)`` disjunct of a support, the condition of a
    non-negative amount in an upper-bounded sum — so a model stays one with any other
    indicator made false.  Unsat proves the core unsat at every horizon (a label it has no
    indicator for is left out: weaker).  Denying them is what makes cvc5 quick (10× on a
    100-component catalog): it need not search over the labels the core leaves free."""
    from catc.smt.consumption import Consumption

    a = Consumption(inst, components)
    body = [*a.assertions, *(str(a.indicator[label]) for label in core if label in a.indicator)]
    body += [f"(not {a.indicator[label]})" for label in a.labels if label not in set(core)]
    return _script(
        _header(inst, "core: the consumption abstraction with the core's labels enforced is unsat"),
        [s.declaration() for s in a.declarations],
        body,
    )


def _consumption_refutes_core(inst: ir.Instance, core: Sequence[str], components: Sequence[str] | None) -> bool:
    """Whether the consumption abstraction with the core's labels enforced is unsat (z3, in
    this process; the checkers decide it again)."""
    from catc.smt.backend import Check
    from catc.smt.consumption import Consumption

    a = Consumption(inst, components)
    return a.check(core)[0] is Check.UNSAT


def core_certificate(inst: ir.Instance, diag: Any, sequential: bool, producer: str) -> dict:
    """The certificate of ``diag``'s first core (NotCertifiable without one); the cores after
    it (``--all``) as certificates of their own under ``more``, checked with it."""
    if diag.status.value != "unsat" or not diag.cores:
        raise NotCertifiable("only a diagnosis that found a core carries a certificate")
    first = _core_document(inst, diag, list(diag.cores[0]), sequential, producer)
    more = [_core_document(inst, diag, list(core), sequential, producer) for core in diag.cores[1:]]
    return first | ({"more": more} if more else {})


def _core_document(inst: ir.Instance, diag: Any, core: list[str], sequential: bool, producer: str) -> dict:
    from catc.semantics.witness import witness_plan

    components = diag.relative_to
    extended = _extended(inst, diag.horizon, components)
    witnesses = _quick_witnesses(inst, core, diag.horizon, extended) if components is None else {}
    for label in core:
        if label in witnesses:
            continue
        rest = frozenset(core) - {label}
        found = witness_plan(inst, rest, components, diag.horizon, extended)
        if found is not None:
            witnesses[label] = _witness(
                label, found[0], {"free_initial_values": "1000000000" if found[1] else "as written"}
            )
        elif components is None:  # no composition fixed: solve the instance the rest leaves
            steps = diag.horizon if ir.Label.horizon() in rest else extended
            solved = _solved_witness(inst, rest, label, steps, sequential)
            if solved is not None:
                witnesses[label] = solved
    proof = "consumption" if _consumption_refutes_core(inst, core, components) else "labelled"
    missing = [label for label in core if label not in witnesses]
    obligations, sat = core_obligations(inst, core, diag.horizon, sequential, components, missing, proof)
    for label in core:
        if label in witnesses:
            obligations.append(witnesses[label])
        else:
            o = _obligation(f"sat/{label}", f"the core without {label} is satisfiable", sat[label])
            obligations.append(o | {"expect": "sat", "producer": producer})
    doc: dict[str, Any] = {
        "schema": SCHEMA,
        "problem": inst.problem.name,
        "domain": inst.domain.name,
        "view": inst.view,
    }
    doc |= {"answer": "core", "method": "core", "producer": producer, "horizon": diag.horizon}
    doc |= {"sequential": sequential, "components": None if components is None else list(components), "core": core}
    doc["core_proof"] = proof
    for o in obligations:
        o.setdefault("producer", producer)
    return doc | {"obligations": obligations}


def _witness(label: str, plan: Any, how: Mapping[str, Any]) -> dict:
    """The obligation "this composition meets every member of the core but ``label``"."""
    from catc.semantics.plan import plan_to_json

    return {
        "name": f"witness/{label}",
        "proves": f"the core without {label} is satisfiable: this composition meets every other member",
        "expect": "valid",
        "checkers": [WITNESS],
        "producer": "catc.witness",
        "plan": plan_to_json(plan),
        **how,
    }


def _quick_witnesses(inst: ir.Instance, core: Sequence[str], horizon: int, extended: int) -> dict[str, dict]:
    """The witnesses diagnose's first try finds without a solver (issue 24's
    :class:`~catc.queries.cores.QuickCores`: the least-cost bound's supports, replayed by the
    validator on the instance the other members leave, *freed* as the labelled formula may
    choose — a dropped decrease does not happen, a dropped Boolean or set initial value holds
    every fact; ``"replay": "freed"``)."""
    from catc.queries.cores import QuickCores

    quick = QuickCores(inst, horizon, extended)
    labels = [label for label in core if label in quick.bound.relevant]
    if len(labels) != len(core):
        return {}
    quick.bound.focus(labels)
    quick.irreducible(list(core))
    return {
        label: _witness(label, plan, {"free_initial_values": "1000000000" if big else "as written", "replay": "freed"})
        for label, (plan, big) in quick.witnesses.items()
    }


#: Seconds :func:`_solved_witness` gives the solver per try (none found: a ``sat`` obligation).
WITNESS_SECONDS = 5.0


def _solved_witness(inst: ir.Instance, rest: frozenset, label: str, steps: int, sequential: bool) -> dict | None:
    """A witness of "the core without ``label``" found by ``catc solve`` on the instance the
    other members leave (:func:`witness_instance`): a dropped effect of the member removed
    (it may or may not happen), a dropped Boolean initial value of the member flipped, free
    numeric initial values as written, then at 10⁹.  None when solve finds none in time."""
    from catc.queries.solve import solve

    member = ir.Label.parse(label)
    removed = [label] if member.kind is ir.LabelKind.EFF else []
    initial: dict[str, bool] = {}
    if member.kind is ir.LabelKind.INIT:
        given = inst.problem.init.get(member.parts[0])
        if given is not None and isinstance(given.value, ir.Const) and isinstance(given.value.value, bool):
            initial[member.parts[0]] = not given.value.value
    for big in (False, True):
        how: dict[str, Any] = {"free_initial_values": "1000000000" if big else "as written"}
        how |= {"initial_values": initial} if initial else {}
        how |= {"without_effects": removed} if removed else {}
        case = witness_instance(inst, rest, how)
        if case is None:
            return None
        result = solve(case, horizon=steps, sequential=sequential, timeout=WITNESS_SECONDS)
        if result.status.value == "sat" and result.plan is not None:
            return _witness(label, result.plan, how)
    return None


def witness_instance(
    inst: ir.Instance, rest: frozenset, how: Mapping[str, Any], only: Collection[str] | None = None
) -> ir.Instance | None:
    """The instance a witness is replayed on: exactly the labels ``rest`` enforced
    (:func:`catc.semantics.witness.restricted`), free numeric initial values as written or at
    10⁹, and — each only where its label is not enforced, as the labelled formula leaves it
    free — the Boolean initial values ``initial_values`` sets and the effects
    ``without_effects`` removes (None when the witness asks for something ``rest`` enforces).
    ``only``: keep just these morphisms (a replay's: the others never fire, and building the
    instance is then quick)."""
    from catc.semantics.witness import restricted
    from catgrammar.record import replace

    initial, removed = how.get("initial_values") or {}, how.get("without_effects") or []
    if not (isinstance(initial, dict) and isinstance(removed, list)):
        return None
    for label in removed:  # each an effect of the model that ``rest`` leaves free
        owner = inst.morphisms.get(label.split("/")[1]) if isinstance(label, str) and label.count("/") == 2 else None
        if owner is None or label in rest or not any(e.label == label for e in owner.effects):
            return None
    if only is not None:
        kept = {m: x for m, x in inst.morphisms.items() if m in only}
        inst = ir.Instance(replace(inst.domain, morphisms=ir.frozen(kept)), inst.problem, inst.view)
    case = restricted(inst, rest, how.get("free_initial_values") == "1000000000")
    if how.get("replay") == "freed":  # diagnose's own choice of what the dropped labels do
        from catc.queries.cores import _freed

        return None if initial or removed else _freed(case, rest)
    init = dict(case.problem.init)
    for name, value in initial.items():
        given = init.get(name)
        if given is None or given.label in rest or not isinstance(value, bool):
            return None
        if not (isinstance(given.value, ir.Const) and isinstance(given.value.value, bool)):
            return None
        init[name] = replace(given, value=ir.Const(value, given.value.sort))
    morphisms = dict(case.domain.morphisms)
    for label in removed:
        owner = morphisms.get(label.split("/")[1])
        if owner is not None:
            morphisms[owner.name] = replace(owner, effects=tuple(e for e in owner.effects if e.label != label))
    domain = replace(case.domain, morphisms=ir.frozen(morphisms))
    return ir.Instance(domain, replace(case.problem, init=ir.frozen(init)), case.view)


def _replay(inst: ir.Instance, doc: Mapping[str, Any], o: Mapping[str, Any]) -> tuple[str, float]:
    """A witness composition replayed by the validator on the instance whose constraints are
    the core without the member it names: ``valid`` or ``invalid``."""
    core, label = list(doc["core"]), o["name"].removeprefix("witness/")
    return _replay_rest(inst, doc, o, frozenset(core) - {label})


def _replay_rest(inst: ir.Instance, doc: Mapping[str, Any], o: Mapping[str, Any], rest: frozenset) -> tuple[str, float]:
    """A witness composition replayed on the instance whose constraints are ``rest`` (every
    other construct dropped): ``valid`` or ``invalid``."""
    from catc.semantics.plan import PlanFormatError, read_plan
    from catc.semantics.validate import validate

    t0 = time.perf_counter()
    components = doc.get("components")
    steps = doc["horizon"] if ir.Label.horizon() in rest else _extended(inst, doc["horizon"], components)
    try:
        plan = read_plan(inst, o.get("plan"))
    except PlanFormatError:
        return "invalid", time.perf_counter() - t0
    case = witness_instance(inst, rest, o, {a.morphism for step in plan.steps for a in step})
    if case is None:  # a free value or a removed effect the enforced labels do not leave free
        return "invalid", time.perf_counter() - t0
    ok = validate(case, plan, horizon=steps, sequential=bool(doc.get("sequential"))).ok
    if components is not None:  # relative to a composition: exactly its components are used
        ok = ok and {a.morphism for step in plan.steps for a in step} == set(components)
    return ("valid" if ok else "invalid"), time.perf_counter() - t0


# -- a least set of dropped constraints (catc relax --discrete): a witness, and nothing smaller


def discrete_obligations(
    inst: ir.Instance, dropped: Sequence[str], horizon: int, sequential: bool, components: Sequence[str] | None
) -> tuple[dict, str]:
    """ "Dropping fewer than ``len(dropped)`` labelled constraints restores nothing": the
    labelled formula with at most that many minus one indicators false, unsat; and the text of
    "every label but ``dropped`` together is satisfiable" (when no witness is at hand)."""
    model = _labelled(inst, horizon, sequential, components)
    unknown = [label for label in dropped if label not in model.indicator]
    if unknown or not dropped:
        raise InputError(f"the dropped labels are not labels of the model: {', '.join(unknown)}", codes.BAD_CERTIFICATE)
    decls, asserts = model.formula()
    count = " ".join(f"(ite {model.indicator[label]} 0 1)" for label in model.labels)
    fewer = f"(<= (+ 0 {count}) {len(dropped) - 1})"
    least = _obligation(
        "least",
        f"dropping fewer than {len(dropped)} labelled constraints restores no composition (horizon {horizon}, "
        f"extended to {model.extended})",
        _script(
            _header(inst, f"least: at most {len(dropped) - 1} labels dropped is unsat"),
            [s.declaration() for s in decls],
            [text for _, text in asserts] + [fewer],
        ),
    )
    kept = [label for label in model.labels if label not in dropped]
    return least, _core_text(model, inst, kept, "restorable: every label but the dropped ones is satisfiable")


def discrete_certificate(inst: ir.Instance, result: Any, options: Mapping[str, Any]) -> dict:
    """The certificate of relax --discrete's least set of dropped constraints."""
    from catc.semantics.plan import plan_to_json
    from catc.semantics.witness import witness_plan

    relative = options.get("relative_to")
    components = (tuple(relative) or None) if relative is not None else (inst.problem.deployed or None)
    sequential = bool(options.get("sequential"))
    dropped = list(result.dropped)
    least, sat = discrete_obligations(inst, dropped, result.horizon, sequential, components)
    model = _labelled(inst, result.horizon, sequential, components)
    kept = frozenset(model.labels) - set(dropped)
    found = witness_plan(inst, kept, components, result.horizon, model.extended)
    if found is None:
        second = _obligation("restorable", "every labelled constraint but the dropped ones holds together", sat)
        second |= {"expect": "sat", "producer": "z3"}
    else:
        plan, big = found
        second = {
            "name": "witness",
            "proves": "this composition meets every labelled constraint but the dropped ones",
            "expect": "valid",
            "checkers": [WITNESS],
            "producer": "catc.witness",
            "plan": plan_to_json(plan),
            "free_initial_values": "1000000000" if big else "as written",
        }
    doc: dict[str, Any] = {"schema": SCHEMA, "problem": inst.problem.name, "domain": inst.domain.name}
    doc |= {"view": inst.view, "answer": "least", "method": "discrete", "producer": "z3", "horizon": result.horizon}
    doc |= {"sequential": sequential, "components": None if components is None else list(components)}
    doc["dropped"] = dropped
    return doc | {"obligations": [least | {"producer": "z3"}, second]}


def _replay_discrete(inst: ir.Instance, doc: Mapping[str, Any], o: Mapping[str, Any]) -> tuple[str, float]:
    model = _labelled(inst, doc["horizon"], bool(doc.get("sequential")), doc.get("components"))
    return _replay_rest(inst, doc, o, frozenset(model.labels) - set(doc["dropped"]))


# -- a least restoration of catc relax: the witness, and nothing cheaper


def least_obligation(
    inst: ir.Instance,
    reqs: Sequence[Mapping[str, Any]],
    horizon: int,
    sequential: bool,
    components: Sequence[str] | None,
    cost: Fraction,
) -> dict:
    """ "No restoration of weighted total below ``cost`` exists": relax's slack formula (every
    requirement enforced, a non-negative slack on each eligible one — up and down for an
    initial value) with the total below ``cost``, unsat."""
    from catc.smt.labelled import LabelledModel
    from catc.smt.script import SmtSort, Symbol
    from catc.smt.terms import Term, minus, plus, times, to_real, to_text

    slack: dict[str, str] = {}
    weighted: list[Term] = []
    decls: list[Symbol] = []
    for req in reqs:
        sort = SmtSort.INT if req["integral"] else SmtSort.REAL
        base = f"d.{req['label']}"
        vs = (
            [Symbol(base + ".up", sort), Symbol(base + ".down", sort)]
            if req["kind"] == "initial value"
            else [Symbol(base, sort)]
        )
        slack[req["label"]] = to_text(minus(*vs)) if len(vs) == 2 else vs[0]
        decls += vs
        weighted += [times(Fraction(req["weight"]), to_real(v) if req["integral"] else v) for v in vs]
    model = LabelledModel(
        inst, horizon, sequential=sequential, components=components, horizon_label=False, slack=slack, slack_decls=decls
    )
    fdecls, asserts = model.formula()
    body = [text for _, text in asserts] + [str(model.indicator[label]) for label in model.labels]
    body += [f"(>= {v} {'0' if v.sort is SmtSort.INT else '0.0'})" for v in decls]
    body.append(f"(< {to_text(plus(Fraction(0), *weighted))} {_number(cost, SortKind.REAL)})")
    text = _script(
        _header(inst, f"least: no restoration of weighted total below {cost}"), [s.declaration() for s in fdecls], body
    )
    return _obligation("least", f"no restoration of the eligible requirements has a weighted total below {cost}", text)


def _read_requirements(inst: ir.Instance, reqs: Any) -> list[dict]:
    """The certificate's eligible requirements, each a relaxable label of the model (E1302)."""
    from catc.queries.relax import eligible_requirements

    known = {r.label: r for r in eligible_requirements(inst)}
    if not isinstance(reqs, list):
        raise InputError("a least certificate needs its eligible requirements", codes.BAD_CERTIFICATE)
    for req in reqs:
        r = known.get(str(req.get("label"))) if isinstance(req, dict) else None
        if (
            r is None
            or (req.get("kind"), req.get("integral")) != (r.kind, r.integral)
            or not _pair([req.get("weight"), None])
        ):
            raise InputError(f"not a relaxable requirement of the model: {req!r}", codes.BAD_CERTIFICATE)
    return reqs


def least_certificate(inst: ir.Instance, result: Any, options: Mapping[str, Any]) -> dict:
    """The certificate of a proven least restoration (NotCertifiable otherwise)."""
    from catc.semantics.plan import plan_to_json

    if result.status.value != "relaxed" or not result.proven or not result.attained or result.plan is None:
        raise NotCertifiable("only a restoration proven least, and attained, carries a certificate")
    relative = options.get("relative_to")
    components = (tuple(relative) or None) if relative is not None else (inst.problem.deployed or None)
    sequential = bool(options.get("sequential"))
    reqs = [
        {"label": r.label, "kind": r.kind, "weight": str(r.weight), "integral": r.integral} for r in result.eligible
    ]
    doc: dict[str, Any] = {
        "schema": SCHEMA,
        "problem": inst.problem.name,
        "domain": inst.domain.name,
        "view": inst.view,
    }
    doc |= {"answer": "least", "method": "least", "producer": "z3", "horizon": result.horizon, "sequential": sequential}
    doc |= {"components": None if components is None else list(components), "requirements": reqs}
    doc |= {"relaxations": {r.label: str(r.delta) for r in result.relaxations}, "cost": str(result.cost)}
    witness = {
        "name": "witness",
        "proves": f"this composition reaches the goal with the relaxations applied (weighted total {result.cost})",
        "expect": "valid",
        "checkers": [WITNESS],
        "producer": "z3",
        "plan": plan_to_json(result.plan),
    }
    least = least_obligation(inst, reqs, result.horizon, sequential, components, result.cost) | {"producer": "z3"}
    return doc | {"obligations": [witness, least]}


def _replay_least(inst: ir.Instance, doc: Mapping[str, Any], o: Mapping[str, Any]) -> tuple[str, float]:
    """The witness of a least restoration, replayed on the model with the certificate's
    relaxations applied, and their weighted total checked against the claimed cost."""
    from catc.queries.relax import relaxed_instance
    from catc.semantics.plan import PlanFormatError, read_plan
    from catc.semantics.validate import validate

    t0 = time.perf_counter()
    try:
        deltas = {label: Fraction(v) for label, v in doc["relaxations"].items()}
        weight = {r["label"]: Fraction(r["weight"]) for r in doc["requirements"]}
        total = sum((weight[label] * abs(d) for label, d in deltas.items()), Fraction(0))
        plan = read_plan(inst, o.get("plan"))
    except (PlanFormatError, KeyError, ValueError, TypeError, ZeroDivisionError, AttributeError):
        return "invalid", time.perf_counter() - t0
    case = relaxed_instance(inst, deltas)
    ok = (
        total == Fraction(doc["cost"])
        and validate(case, plan, horizon=doc["horizon"], sequential=bool(doc.get("sequential"))).ok
    )
    components = doc.get("components")
    if components is not None:
        ok = ok and {a.morphism for step in plan.steps for a in step} == set(components)
    return ("valid" if ok else "invalid"), time.perf_counter() - t0


# -- an optimum of catc optimize / catc recompose: the witness, and nothing better


#: The certificate's objectives when they were given on the command line (``--minimize``,
#: ``--maximize``): their source text, which only an interface may parse (the frontend is not
#: the queries' to import) — :func:`objective_texts` gives it, and the IR comes back as
#: ``certify(..., objectives=...)``.
COMMAND_LINE = "command-line"


def command_line_spec(objectives: Sequence[ir.Objective], texts: Any) -> dict:
    """The certificate's ``objectives`` entry for objectives given on the command line:
    each one's sense and source text, in lexicographic order (NotCertifiable when the
    interface did not keep the text)."""
    pairs = list(texts or ())
    if len(pairs) != len(objectives) or any(s != o.sense.value for (s, _), o in zip(pairs, objectives)):
        raise NotCertifiable("the command-line objectives' text was not kept by the interface that asked")
    return {"kind": COMMAND_LINE, "terms": [{"sense": s, "term": t} for s, t in pairs]}


def objective_texts(doc: Mapping[str, Any]) -> list[tuple[str, str]]:
    """The ``(sense, text)`` pairs a certificate of command-line objectives stores, in
    lexicographic order ([] for the problem's own metric; E1302 when malformed)."""
    spec = doc.get("objectives")
    if not (isinstance(spec, dict) and spec.get("kind") == COMMAND_LINE):
        return []
    terms = spec.get("terms")
    if not (isinstance(terms, list) and terms and all(_term_spec(t) for t in terms)):
        raise InputError(
            "a certificate of command-line objectives needs each one's sense and term", codes.BAD_CERTIFICATE
        )
    return [(t["sense"], t["term"]) for t in terms]


def _term_spec(t: Any) -> bool:
    return isinstance(t, dict) and t.get("sense") in ("minimize", "maximize") and isinstance(t.get("term"), str)


def _given(spec: Mapping[str, Any], given: Sequence[ir.Objective] | None) -> list[ir.Objective]:
    """The IR of a certificate's command-line objectives, as the interface parsed them (E1304
    when none did: only an interface may parse text; E1303 when they are not the stored ones)."""
    stored = objective_texts({"objectives": spec})
    if given is None:
        raise InputError(
            "the certificate's objectives were given on the command line ("
            + ", ".join(f"--{s} {t}" for s, t in stored)
            + "): their text is read by catc certify (in Python: certify(..., objectives=[...]))",
            codes.NOT_CERTIFIABLE,
        )
    if [o.sense.value for o in given] != [s for s, _ in stored]:
        raise InputError(
            "the objectives given are not the certificate's: " + ", ".join(f"{s} {t}" for s, t in stored),
            codes.CERTIFICATE_MISMATCH,
        )
    return list(given)


def _objectives(
    inst: ir.Instance, spec: Any, given: Sequence[ir.Objective] | None = None
) -> tuple[ir.Instance, list[ir.Objective], list[ir.Soft]]:
    """The model (with the certificate's deployed composition, for recompose), the objectives
    in lexicographic order and the soft constraints an optimum is claimed for (E1302);
    ``given``: the IR of command-line objectives, parsed by the interface."""
    from dataclasses import replace

    from catc.queries.optimum import objectives_of

    kind = spec.get("kind") if isinstance(spec, dict) else None
    if given is not None and kind != COMMAND_LINE:
        raise InputError(
            "objectives were given, but the certificate is for the problem's own objectives", codes.CERTIFICATE_MISMATCH
        )
    if kind == COMMAND_LINE:
        objectives = _given(spec, given)
    elif kind == "recompose" and spec.get("priority") in ("stability", "objective"):
        deployed = spec.get("deployed")
        if not (isinstance(deployed, list) and all(m in inst.morphisms for m in deployed)):
            raise InputError("the certificate's deployed composition is not of the model", codes.BAD_CERTIFICATE)
        inst = ir.Instance(inst.domain, replace(inst.problem, deployed=tuple(deployed)), inst.view)
        mission = [o for o in objectives_of(inst) if not isinstance(o.term, ir.TotalChurn)]
        churn = ir.Objective(ir.Sense.MINIMIZE, ir.TotalChurn())
        objectives = [churn, *mission] if spec["priority"] == "stability" else [*mission, churn]
    elif kind == "metric":
        objectives = objectives_of(inst)
    else:
        raise InputError(
            "the certificate's objectives are not known: metric, recompose or command-line", codes.BAD_CERTIFICATE
        )
    softs = list(inst.problem.softs)
    if not objectives and softs:
        objectives = [ir.Objective(ir.Sense.MINIMIZE, ir.Const(Fraction(0), ir.REAL))]
    return inst, objectives, softs


def optimal_obligation(
    inst: ir.Instance,
    objectives: Sequence[ir.Objective],
    softs: Sequence[ir.Soft],
    horizon: int,
    sequential: bool,
    values: Sequence[Fraction],
) -> dict:
    """ "No composition of at most ``horizon`` steps is lexicographically better than
    ``values``" (the first objective carrying the soft penalties), over the step encoding."""
    from catc.smt.encoder import Encoder
    from catc.smt.terms import Term, and_, better, eq, ite, minus, or_, plus, to_text

    enc = Encoder(inst, horizon, sequential=sequential)
    enc.unroll(horizon)
    penalty: list[Term] = [ite(str(enc.at_state(s.expr, horizon)), Fraction(0), s.weight) for s in softs]
    improvements: list[Term] = []
    ties: list[Term] = []
    for i, (obj, v) in enumerate(zip(objectives, values)):
        term: Term = enc.objective(obj.term, horizon)
        if i == 0 and penalty:
            term = to_text((plus if obj.sense is ir.Sense.MINIMIZE else minus)(term, *penalty))
        improvements.append(and_(*ties, better(term, v, obj.sense is ir.Sense.MINIMIZE)))
        ties.append(eq(term, v))
    decls, asserts = enc.script.take()
    shown = ", ".join(str(v) for v in values)
    text = _script(
        _header(inst, f"optimal: nothing better than ({shown}) within {horizon} steps"),
        [s.declaration() for s in decls],
        [a for _, a in asserts] + [to_text(or_(*improvements))],
    )
    return _obligation("optimal", f"no composition of at most {horizon} steps is better than ({shown})", text)


def optimal_certificate(inst: ir.Instance, result: Any, options: Mapping[str, Any]) -> dict:
    """The certificate of a proven optimum of optimize or recompose (NotCertifiable otherwise)."""
    from catc.semantics.plan import plan_to_json

    given = options.get("objectives") or None
    if result.query == "recompose":
        spec: dict[str, Any] = {"kind": "recompose", "priority": result.priority, "deployed": list(result.deployed)}
        result = result.result
    elif given is not None:
        spec = command_line_spec(given, options.get("objective_source"))
    else:
        spec = {"kind": "metric"}
    values = [v.value for v in result.values]
    if result.status.value != "opt" or result.plan is None or not all(v.attained for v in result.values):
        raise NotCertifiable("only an optimum proven and attained carries a certificate")
    sequential = bool(options.get("sequential"))
    model, objectives, softs = _objectives(inst, spec, given)
    doc: dict[str, Any] = {
        "schema": SCHEMA,
        "problem": inst.problem.name,
        "domain": inst.domain.name,
        "view": inst.view,
    }
    doc |= {"answer": "optimal", "method": "optimal", "producer": "z3", "horizon": result.horizon}
    doc |= {"sequential": sequential, "objectives": spec, "values": [str(v) for v in values]}
    witness = {
        "name": "witness",
        "proves": f"this composition is valid and scores ({', '.join(map(str, values))})",
        "expect": "valid",
        "checkers": [WITNESS],
        "producer": "z3",
        "plan": plan_to_json(result.plan),
    }
    best = optimal_obligation(model, objectives, softs, result.horizon, sequential, values) | {"producer": "z3"}
    return doc | {"obligations": [witness, best]}


def pareto_obligation(
    inst: ir.Instance,
    objectives: Sequence[ir.Objective],
    horizon: int,
    sequential: bool,
    points: Sequence[Sequence[Fraction]],
) -> dict:
    """ "Every composition of at most ``horizon`` steps is weakly dominated by a point of the
    front": the step encoding with "strictly better than each point in some objective", unsat
    (the guided improvement's last check, over the step encoding rebuilt from the model)."""
    from catc.smt.encoder import Encoder
    from catc.smt.terms import and_, better, or_, to_text

    enc = Encoder(inst, horizon, sequential=sequential)
    enc.unroll(horizon)
    terms = [enc.objective(o.term, horizon) for o in objectives]
    minimizing = [o.sense is ir.Sense.MINIMIZE for o in objectives]
    escapes = [or_(*[better(t, v, m) for t, v, m in zip(terms, point, minimizing)]) for point in points]
    decls, asserts = enc.script.take()
    text = _script(
        _header(
            inst, f"pareto: every composition within {horizon} steps is weakly dominated by one of {len(points)} points"
        ),
        [s.declaration() for s in decls],
        [a for _, a in asserts] + [to_text(and_(*escapes))],
    )
    return _obligation(
        "front", f"every composition of at most {horizon} steps is weakly dominated by a point of the front", text
    )


def pareto_certificate(inst: ir.Instance, result: Any, options: Mapping[str, Any]) -> dict:
    """The certificate of a complete Pareto front, every point attained (NotCertifiable
    otherwise): a witness per point, and "nothing escapes the front"."""
    from catc.ir.text import to_text
    from catc.semantics.plan import plan_to_json

    if result.status.value != "front" or not result.complete:
        raise NotCertifiable("only a complete Pareto front carries a certificate")
    if not all(p.attained for p in result.points):
        raise NotCertifiable("a point of the front is a bound no composition attains: not certified yet")
    given = options.get("objectives") or None
    spec = {"kind": "metric"} if given is None else command_line_spec(given, options.get("objective_source"))
    model, objectives = _pareto_objectives(inst, spec, given)
    if [to_text(o.term) for o in objectives] != [to_text(o.term) for o in result.objectives]:
        raise NotCertifiable("the front's objectives are not the problem's metric")
    sequential = bool(options.get("sequential"))
    points = [list(p.values) for p in result.points]
    doc: dict[str, Any] = {"schema": SCHEMA, "problem": inst.problem.name, "domain": inst.domain.name}
    doc |= {"view": inst.view, "answer": "pareto", "method": "pareto", "producer": "z3", "horizon": result.horizon}
    doc |= {"sequential": sequential, "objectives": spec, "points": [[str(v) for v in p] for p in points]}
    witnesses = [
        {
            "name": f"witness/{i + 1}",
            "proves": f"this composition is valid and scores ({', '.join(map(str, p.values))})",
            "expect": "valid",
            "checkers": [WITNESS],
            "producer": "z3",
            "plan": plan_to_json(p.plan),
        }
        for i, p in enumerate(result.points)
    ]
    front = pareto_obligation(model, objectives, result.horizon, sequential, points) | {"producer": "z3"}
    return doc | {"obligations": [*witnesses, front]}


def _pareto_objectives(
    inst: ir.Instance, spec: Any, given: Sequence[ir.Objective] | None = None
) -> tuple[ir.Instance, list[ir.Objective]]:
    """The objectives of a front (no soft penalties: pareto does not weigh them)."""
    if not (isinstance(spec, dict) and spec.get("kind") in ("metric", COMMAND_LINE)):
        raise InputError(
            "a Pareto certificate's objectives are the problem's metric or the command line's", codes.BAD_CERTIFICATE
        )
    model, objectives, _ = _objectives(inst, spec, given)
    if len(objectives) < 2:
        raise InputError("a Pareto front needs at least two objectives", codes.BAD_CERTIFICATE)
    return model, objectives


def _read_points(doc: Mapping[str, Any], width: int) -> list[list[Fraction]]:
    points = doc.get("points")
    try:
        out = [[Fraction(str(v)) for v in p] for p in points] if isinstance(points, list) else None
    except (ValueError, ZeroDivisionError, TypeError):
        out = None
    if not out or any(len(p) != width for p in out):
        raise InputError("a Pareto certificate needs its points: one exact value per objective", codes.BAD_CERTIFICATE)
    return out


def _replay_point(
    inst: ir.Instance, doc: Mapping[str, Any], o: Mapping[str, Any], given: Sequence[ir.Objective] | None = None
) -> tuple[str, float]:
    """A front point's composition replayed, its values recomputed (optimize's scoring
    without soft penalties) and equal to the point's; and no point dominates another."""
    from catc.queries.optimum import _scores
    from catc.queries.pareto import dominates
    from catc.semantics.plan import PlanFormatError, read_plan
    from catc.semantics.validate import validate

    t0 = time.perf_counter()
    model, objectives = _pareto_objectives(inst, doc["objectives"], given)
    points = _read_points(doc, len(objectives))
    try:
        index = int(str(o["name"]).split("/", 1)[1]) - 1
        claimed = points[index]
        plan = read_plan(model, o.get("plan"))
    except (PlanFormatError, ValueError, TypeError, KeyError, IndexError):
        return "invalid", time.perf_counter() - t0
    if any(dominates(tuple(q), tuple(claimed), objectives) for q in points):
        return "invalid", time.perf_counter() - t0  # another point of the front is better: not Pareto-optimal
    horizon, sequential = doc["horizon"], bool(doc.get("sequential"))
    rep = validate(model, plan, horizon=horizon, sequential=sequential)
    if not rep.ok:
        return "invalid", time.perf_counter() - t0
    scores = _scores(model, plan, objectives, [], horizon, sequential, report=rep)
    return ("valid" if scores == claimed else "invalid"), time.perf_counter() - t0


def _replay_optimal(
    inst: ir.Instance, doc: Mapping[str, Any], o: Mapping[str, Any], given: Sequence[ir.Objective] | None = None
) -> tuple[str, float]:
    """The optimum's composition replayed by the validator, its objective values recomputed
    exactly (the first with the soft penalties: optimize's own scoring) and compared with the
    claimed ones."""
    from catc.queries.optimum import _scores
    from catc.semantics.plan import PlanFormatError, read_plan
    from catc.semantics.validate import validate

    t0 = time.perf_counter()
    model, objectives, softs = _objectives(inst, doc["objectives"], given)
    try:
        claimed = [Fraction(str(v)) for v in doc["values"]]
        plan = read_plan(model, o.get("plan"))
    except (PlanFormatError, ValueError, TypeError, ZeroDivisionError, KeyError):
        return "invalid", time.perf_counter() - t0
    horizon, sequential = doc["horizon"], bool(doc.get("sequential"))
    rep = validate(model, plan, horizon=horizon, sequential=sequential)
    if not rep.ok:
        return "invalid", time.perf_counter() - t0
    scores = _scores(model, plan, list(objectives), list(softs), horizon, sequential, report=rep)
    return ("valid" if scores == claimed else "invalid"), time.perf_counter() - t0


def _produced(doc: dict, producer: str) -> dict:
    for o in doc["obligations"]:
        o["producer"] = producer
    return doc


def _everything() -> Any:
    from catc.semantics.relaxed import _Everything

    return _Everything()


def write_certificate(inst: ir.Instance, result: Any, options: Mapping[str, Any]) -> str:
    """``--certificate FILE``: write ``result``'s certificate (E1304 when it has none)."""
    path = options["certificate"]
    try:
        doc = certificate_of(inst, result, options)
    except NotCertifiable as exc:
        raise InputError(f"no certificate written: {exc}", codes.NOT_CERTIFIABLE) from None
    import json

    try:
        with open(path, "w", encoding="utf-8") as out:
            json.dump(doc, out, indent=2)
            out.write("\n")
    except OSError as exc:
        raise InputError(f"cannot write the certificate to {path}: {exc.strerror or exc}", codes.CANNOT_WRITE) from exc
    count = len(doc["obligations"]) + sum(len(m["obligations"]) for m in doc.get("more", []))
    return f"certificate ({counted(count, 'obligation')}) written to {path}; check it with: catc certify [DOMAIN] PROBLEM {path}"


def certificate_of(inst: ir.Instance, result: Any, options: Mapping[str, Any]) -> dict:
    """The catc.certificate/1 document of any query's answer (NotCertifiable when it has
    none); ``options``: the query's (the semantics, the objectives, the composition)."""
    if result.query in ("optimize", "recompose"):
        return optimal_certificate(inst, result, options)
    if result.query == "pareto":
        return pareto_certificate(inst, result, options)
    if result.query == "relax" and getattr(result, "dropped", None):
        return discrete_certificate(inst, result, options)
    if result.query == "relax":
        return least_certificate(inst, result, options)
    if result.query == "diagnose":
        producer = "catc.relaxed" if result.checks == 0 else str(options.get("backend", "z3"))
        return core_certificate(inst, result, bool(options.get("sequential")), producer)
    return certificate(inst, result)


def certificate_artifact(inst: ir.Instance, result: Any, options: Mapping[str, Any]) -> str:
    """``--certificate FILE`` (called by :mod:`catc.interfaces.command` after the query): write the
    certificate of ``result``; what to tell the user."""
    status = getattr(getattr(result, "status", None), "value", None)
    if result.query == "solve" and status != "unsat":
        return "no certificate written: the answer is not a 'no' (its composition is replayed by the validator)"
    return write_certificate(inst, result, options)


# ====================================================================== checking


class CertifyStatus(Status):
    CERTIFIED = "certified", ExitCode.OK
    REFUTED = "refuted", ExitCode.FAIL  # an obligation is satisfiable, or does not match the model
    UNCHECKED = "unchecked", ExitCode.UNKNOWN  # an obligation no independent checker decided


class Certification(Result):
    """The answer of :func:`certify`: the status and, per obligation, what each checker said."""

    query = "certify"
    __slots__ = ("status", "method", "producer", "obligations", "timings")
    status: CertifyStatus

    def __init__(self, status: CertifyStatus, method: str, producer: str, obligations: list[dict]) -> None:
        self.status = status
        self.method = method
        self.producer = producer
        self.obligations = obligations
        self.timings: dict[str, float] = {}

    def __repr__(self) -> str:
        return f"Certification({self.status.name}, {self.method})"


_CVC5 = """
import sys, cvc5
tm = cvc5.TermManager()
slv = cvc5.Solver(tm)
slv.setOption("tlimit-per", sys.argv[2])
sm = cvc5.SymbolManager(tm)
parser = cvc5.InputParser(slv, sm)
parser.setFileInput(cvc5.InputLanguage.SMT_LIB_2_6, sys.argv[1])
while True:
    cmd = parser.nextCommand()
    if cmd.isNull():
        break
    out = cmd.invoke(slv, sm)
    if out:
        print(out.strip())
"""


# cvc5 on several files, one fresh solver each (nothing is shared between obligations): per
# file a line "catc-obligation I ANSWER SECONDS" (argv: the time limit in ms, then the files)
_CVC5_BATCH = """
import sys, time, cvc5
tm = cvc5.TermManager()
for i, path in enumerate(sys.argv[2:]):
    t0 = time.perf_counter()
    answer = "error"
    try:
        slv = cvc5.Solver(tm)
        slv.setOption("tlimit-per", sys.argv[1])
        sm = cvc5.SymbolManager(tm)
        parser = cvc5.InputParser(slv, sm)
        parser.setFileInput(cvc5.InputLanguage.SMT_LIB_2_6, path)
        while True:
            cmd = parser.nextCommand()
            if cmd.isNull():
                break
            out = cmd.invoke(slv, sm).split()  # "unknown (TIMEOUT)": the first word
            if out and out[0] in ("sat", "unsat", "unknown"):
                answer = out[0]
    except Exception:
        answer = "error"
    print("catc-obligation", i, answer, time.perf_counter() - t0, flush=True)
"""


def z3_command() -> list[str] | None:
    """The z3 binary z3-solver installs (on PATH, or beside the interpreter)."""
    import shutil

    path = shutil.which("z3") or os.path.join(os.path.dirname(sys.executable), "z3")
    return [path] if os.path.exists(path) else None


def cvc5_command() -> list[str] | None:
    """cvc5's SMT-LIB2 front end, in a fresh interpreter (PyPI's cvc5 ships no binary)."""
    import importlib.util

    return None if importlib.util.find_spec("cvc5") is None else [sys.executable, "-c", _CVC5]


def run_checker(checker: str, path: str, seconds: float) -> tuple[str, float]:
    """``checker``'s answer on the SMT-LIB2 file ``path`` (unsat, sat, unknown, timeout,
    missing or error) and the seconds it took."""
    if checker == "z3":
        cmd = z3_command()
        args = None if cmd is None else [*cmd, f"-T:{max(1, int(seconds + 0.999))}", path]
    else:
        cmd = cvc5_command()
        args = None if cmd is None else [*cmd, path, str(int(seconds * 1000))]
    if args is None:
        return "missing", 0.0
    import subprocess

    t0 = time.perf_counter()
    try:
        out = subprocess.run(args, capture_output=True, text=True, timeout=seconds + 5)
    except subprocess.TimeoutExpired:
        return "timeout", time.perf_counter() - t0
    took = time.perf_counter() - t0
    words = out.stdout.split()
    answer = words[0] if words else ""
    if answer in ("unsat", "sat", "unknown"):
        return answer, took
    return ("timeout" if "timeout" in out.stdout + out.stderr else "error"), took


def _checked(obligation: dict, expected: str | None, answers: Mapping[str, tuple[str, float]] | None) -> dict:
    """One obligation's row: ``mismatch`` when its text is not the one rebuilt from the model
    (``expected``), else what the checkers it names answered (``answers``)."""
    row = {"name": obligation["name"], "proves": obligation.get("proves", ""), "producer": obligation["producer"]}
    if answers is None:
        return row | {"status": "mismatch", "checkers": {}, "proved_by": []}
    said = {c: {"answer": answer, "seconds": round(took, 3)} for c, (answer, took) in answers.items()}
    expect = obligation.get("expect", "unsat")
    opposite = {"unsat": "sat", "sat": "unsat", "valid": "invalid"}[expect]
    proved = [c for c, a in said.items() if a["answer"] == expect and c != obligation["producer"]]
    refuted = any(a["answer"] == opposite for a in said.values())
    status = "refuted" if refuted else ("proved" if proved else "unchecked")
    return row | {"status": status, "checkers": said, "proved_by": proved}


def _matches(obligation: dict, expected: str | None) -> bool:
    return expected is not None and _significant(obligation["smtlib"]) == _significant(expected)


def run_batch(checker: str, paths: Sequence[str], seconds: float) -> list[tuple[str, float]]:
    """``checker``'s answer on each SMT-LIB2 file of ``paths``, all in one process (its
    start-up paid once): the z3 binary on one script that runs each file after a ``(reset)``
    with its own time limit; cvc5 with a fresh solver per file.  An obligation the batch did
    not answer (a crash, an error) is run again alone by :func:`run_checker`."""
    import subprocess

    command = z3_command() if checker == "z3" else cvc5_command()
    if command is None:
        return [("missing", 0.0)] * len(paths)
    if len(paths) == 1:
        return [run_checker(checker, paths[0], seconds)]
    ms = str(max(1, int(seconds * 1000)))
    if checker == "z3":
        import tempfile

        # a script of its own: other batches of the same certificate run at the same time
        handle, script = tempfile.mkstemp(suffix=".smt2", prefix="z3-batch-", dir=os.path.dirname(paths[0]))
        with os.fdopen(handle, "w", encoding="utf-8") as out:
            for i, path in enumerate(paths):
                with open(path, encoding="utf-8") as fh:
                    body = fh.read()
                out.write(f'(reset)\n(set-option :timeout {ms})\n(echo "catc-obligation {i}")\n{body}\n')
        args = [*command, script]
    else:
        args = [sys.executable, "-c", _CVC5_BATCH, ms, *paths]
    answers: dict[int, tuple[str, float]] = {}
    current, t0 = -1, time.perf_counter()
    try:
        with subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True) as proc:
            limit = _kill_after(proc, len(paths) * seconds + 5)
            assert proc.stdout is not None
            for line in proc.stdout:
                words = line.split()
                if words[:1] != ["catc-obligation"] or len(words) < 2:
                    if checker == "z3" and current >= 0 and current not in answers and words[:1]:
                        answer = words[0] if words[0] in ("sat", "unsat", "unknown") else "error"
                        answers[current] = (answer, time.perf_counter() - t0)
                    continue
                if checker == "z3":
                    current, t0 = int(words[1]), time.perf_counter()
                elif len(words) == 4:
                    answers[int(words[1])] = (words[2], float(words[3]))
            limit.cancel()
    except OSError:
        pass
    return [
        answers[i] if answers.get(i, ("error", 0.0))[0] != "error" else run_checker(checker, path, seconds)
        for i, path in enumerate(paths)
    ]


def _kill_after(proc: Any, seconds: float) -> Any:
    """Kill ``proc`` after ``seconds`` (the batch's overall limit); cancel it when done."""
    import threading

    timer = threading.Timer(seconds, proc.kill)
    timer.daemon = True
    timer.start()
    return timer


#: Obligations per checker process before a checker's list is split over more processes.
BATCH = 4


def _run_checkers(obligations: Sequence[dict], seconds: float) -> list[dict[str, tuple[str, float]]]:
    """Every checker on every obligation: one process per checker for up to :data:`BATCH`
    obligations (:func:`run_batch`: its start-up paid once), a longer list split round-robin
    over as many processes as there are cores (up to 4), all of them at once on that many
    workers (they share nothing)."""
    import tempfile
    from concurrent.futures import ThreadPoolExecutor

    workers = max(1, min(4, os.cpu_count() or 1))
    with tempfile.TemporaryDirectory(prefix="catc-certify-") as folder:
        paths = []
        for i, o in enumerate(obligations):
            paths.append(os.path.join(folder, f"{i}.smt2"))
            with open(paths[-1], "w", encoding="utf-8") as fh:
                fh.write(o["smtlib"])
        chunks: list[tuple[str, list[int]]] = []
        for c in CHECKERS:
            ids = [i for i, o in enumerate(obligations) if c in o["checkers"]]
            parts = min(workers, -(-len(ids) // BATCH))
            chunks += [(c, ids[j::parts]) for j in range(parts)]
        with ThreadPoolExecutor(max_workers=max(1, min(workers, len(chunks)))) as pool:
            done = list(pool.map(lambda chunk: run_batch(chunk[0], [paths[i] for i in chunk[1]], seconds), chunks))
    out: list[dict[str, tuple[str, float]]] = [{} for _ in obligations]
    for (checker, ids), answers in zip(chunks, done):
        for i, answer in zip(ids, answers):
            out[i][checker] = answer
    return out


def _significant(text: str) -> list[str]:
    """An obligation's commands, without comments and blank lines."""
    return [line.strip() for line in text.splitlines() if line.strip() and not line.lstrip().startswith(";")]


def _labels(doc: Mapping[str, Any], key: str, missing: str) -> list[str]:
    """The certificate's non-empty list of labels under ``key`` (E1302 ``missing`` if not)."""
    labels = doc.get(key)
    if not (isinstance(labels, list) and labels and all(isinstance(x, str) for x in labels)):
        raise InputError(missing, codes.BAD_CERTIFICATE)
    return labels


def _components(inst: ir.Instance, doc: Mapping[str, Any]) -> list[str] | None:
    """The certificate's components (None: not given), each a morphism of the model."""
    components = doc.get("components")
    if components is not None and not (isinstance(components, list) and all(c in inst.morphisms for c in components)):
        raise InputError("the certificate's components are not morphisms of the model", codes.BAD_CERTIFICATE)
    return components


def _expected(inst: ir.Instance, doc: Mapping[str, Any], given: Sequence[ir.Objective] | None = None) -> dict[str, str]:
    """The obligations' text as the model and the certificate's claims give them (``given``:
    the IR of command-line objectives, parsed by the interface)."""
    method, horizon = doc.get("method"), doc.get("horizon")
    if not isinstance(horizon, int) or horizon < 0:
        raise InputError("the certificate's horizon must be a whole number", codes.BAD_CERTIFICATE)
    if method == "invariant":
        built = invariant_obligations(inst, _read_invariant(inst, doc.get("invariant")), horizon)
    elif method == "bounded":
        from catc.semantics.horizon import use_bound

        bound = use_bound(inst)
        if bound is None or horizon < bound:
            return {}  # the horizon is not complete for this model: nothing matches
        built = bounded_obligations(inst, horizon, bool(doc.get("sequential")))
    elif method == "consumption":
        if not _claims_hold(inst, doc.get("bounds", [])):
            return {}  # a claimed bound the model does not give: nothing matches
        built = consumption_obligations(inst)
    elif method == "reachable":
        if doc.get("sequential") is not True:
            raise InputError("a reachable-states certificate is for sequential steps", codes.BAD_CERTIFICATE)
        built = reachable_obligations(inst, _read_states(inst, doc.get("states")), horizon)
    elif method == "optimal":
        model, objectives, softs = _objectives(inst, doc.get("objectives"), given)
        try:
            values = [Fraction(str(v)) for v in doc.get("values") or []]
        except (ValueError, ZeroDivisionError):
            raise InputError("an optimal certificate needs its values: exact numbers", codes.BAD_CERTIFICATE) from None
        if len(values) != len(objectives):
            raise InputError("an optimal certificate needs one value per objective", codes.BAD_CERTIFICATE)
        built = [optimal_obligation(model, objectives, softs, horizon, bool(doc.get("sequential")), values)]
        return {o["name"]: o["smtlib"] for o in built} | {"witness": ""}
    elif method == "pareto":
        model, objectives = _pareto_objectives(inst, doc.get("objectives"), given)
        points = _read_points(doc, len(objectives))
        built = [pareto_obligation(model, objectives, horizon, bool(doc.get("sequential")), points)]
        return {o["name"]: o["smtlib"] for o in built} | {f"witness/{i + 1}": "" for i in range(len(points))}
    elif method == "discrete":
        dropped = _labels(doc, "dropped", "a discrete certificate needs its dropped labels")
        components = _components(inst, doc)
        least, restorable = discrete_obligations(inst, dropped, horizon, bool(doc.get("sequential")), components)
        return {"least": least["smtlib"], "restorable": restorable, "witness": ""}
    elif method == "least":
        reqs = _read_requirements(inst, doc.get("requirements"))
        try:
            cost = Fraction(str(doc.get("cost")))
        except (ValueError, TypeError, ZeroDivisionError):
            raise InputError("a least certificate needs its cost: an exact number", codes.BAD_CERTIFICATE) from None
        components = doc.get("components")
        built = [least_obligation(inst, reqs, horizon, bool(doc.get("sequential")), components, cost)]
        return {o["name"]: o["smtlib"] for o in built} | {"witness": ""}
    elif method == "core":
        core = _labels(doc, "core", "a core certificate needs its core: a non-empty list of labels")
        components = _components(inst, doc)
        names = {o["name"] for o in doc["obligations"]}
        asked = [label for label in core if f"sat/{label}" in names]  # only the texts a checker will read
        proof = doc.get("core_proof", "labelled")
        built, sat = core_obligations(inst, core, horizon, bool(doc.get("sequential")), components, asked, proof)
        witnesses = {f"witness/{label}": "" for label in core}  # replayed by the validator
        return (
            {o["name"]: o["smtlib"] for o in built} | {f"sat/{label}": text for label, text in sat.items()} | witnesses
        )
    else:
        raise InputError(f"unknown certificate method {method!r}", codes.BAD_CERTIFICATE)
    return {o["name"]: o["smtlib"] for o in built}


def read_certificate(path: str) -> dict:
    """A certificate file → its document (E1301 unreadable or not JSON, E1302 not a
    catc.certificate/1 document)."""
    import json

    try:
        with open(path, encoding="utf-8") as fh:
            doc = json.load(fh)
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise InputError(f"cannot read the certificate {path}: {exc}", codes.UNREADABLE_CERTIFICATE) from None
    _shape(doc, path)
    more = doc.get("more", [])
    if more and not (isinstance(more, list) and doc.get("method") == "core"):
        raise InputError(f"{path}: only a core certificate holds more cores", codes.BAD_CERTIFICATE)
    for i, nested in enumerate(more, start=2):
        _shape(nested, f"{path} (core {i})")
        if nested.get("method") != "core" or "more" in nested:
            raise InputError(f"{path}: core {i} must be a core certificate of its own", codes.BAD_CERTIFICATE)
    return doc


def _shape(doc: Any, path: str) -> None:
    """E1302 unless ``doc`` is a catc.certificate/1 document with well-formed obligations."""
    if not isinstance(doc, dict) or doc.get("schema") != SCHEMA:
        raise InputError(f"{path} is not a {SCHEMA} document", codes.BAD_CERTIFICATE)
    obligations = doc.get("obligations")
    if not isinstance(obligations, list) or not obligations:
        raise InputError(f"{path}: a certificate needs a non-empty list of obligations", codes.BAD_CERTIFICATE)
    for o in obligations:
        why = _malformed(o)
        if why is not None:
            raise InputError(f"{path}: {why}", codes.BAD_CERTIFICATE)


def _malformed(o: Any) -> str | None:
    """Why an obligation is not one (None when it is)."""
    base = {"name": str, "producer": str, "checkers": list}
    if not isinstance(o, dict) or not all(isinstance(o.get(k), t) for k, t in base.items()):
        return "each obligation needs name, producer and checkers"
    expect = o.get("expect", "unsat")
    if expect == "valid":
        if o["checkers"] != [WITNESS] or not isinstance(o.get("plan"), dict):
            return f"a witness ({o['name']}) needs a plan and the checker {WITNESS}"
        return None
    if expect not in ("unsat", "sat") or not isinstance(o.get("smtlib"), str):
        return f"obligation {o['name']}: expect unsat, sat or valid; an SMT obligation needs its smtlib"
    if not o["checkers"] or not set(o["checkers"]) <= set(CHECKERS):
        return f"unknown checker in {o['checkers']} (known: z3, cvc5)"
    return None


def _same_problem(inst: ir.Instance, doc: Mapping[str, Any]) -> None:
    if (doc.get("problem"), doc.get("domain")) != (inst.problem.name, inst.domain.name):
        raise InputError(
            f"the certificate is for problem '{doc.get('problem')}' of domain '{doc.get('domain')}', not "
            f"'{inst.problem.name}' of '{inst.domain.name}'",
            codes.CERTIFICATE_MISMATCH,
        )


def certify(
    inst: ir.Instance,
    certificate: str | Mapping[str, Any],
    *,
    check_timeout: float | None = None,
    objectives: Sequence[ir.Objective] | None = None,
) -> Certification:
    """Check ``certificate`` (a file or a document) against ``inst`` (InputError: E1301–E1304).
    ``objectives``: for a certificate of objectives given on the command line, their IR —
    the interface parses the text the certificate stores (:func:`objective_texts`)."""
    doc = read_certificate(certificate) if isinstance(certificate, str) else dict(certificate)
    _same_problem(inst, doc)
    t0 = time.perf_counter()
    given = list(objectives) if objectives else None
    expected = _expected(inst, doc, given)
    seconds = CHECK_TIMEOUT if check_timeout is None else check_timeout
    smt = [o for o in doc["obligations"] if o.get("expect", "unsat") != "valid"]
    matching = [o for o in smt if _matches(o, expected.get(o["name"]))]
    from concurrent.futures import ThreadPoolExecutor

    answers: dict[int, Mapping[str, tuple[str, float]]] = {}
    if any(o.get("expect") == "valid" for o in doc["obligations"]):
        with ThreadPoolExecutor(max_workers=1) as pool:  # the checkers' processes run while the validator replays
            checked = pool.submit(_run_checkers, matching, seconds)
            _replays(inst, doc, expected, given, answers)
            answers |= dict(zip((id(o) for o in matching), checked.result()))
    else:
        answers |= dict(zip((id(o) for o in matching), _run_checkers(matching, seconds)))
    rows = [_checked(o, expected.get(o["name"]), answers.get(id(o))) for o in doc["obligations"]]
    missing = sorted(_missing(doc, expected))
    rows += [
        {"name": n, "proves": "", "producer": "", "status": "missing", "checkers": {}, "proved_by": []} for n in missing
    ]
    if not expected:
        rows.append(
            {
                "name": "bounds" if doc.get("method") == "consumption" else "horizon",
                "proves": "",
                "producer": "",
                "status": "mismatch",
                "checkers": {},
                "proved_by": [],
            }
        )
    for i, nested in enumerate(doc.get("more") or [], start=2):  # a diagnosis's later cores
        if not isinstance(nested, dict) or nested.get("method") != "core" or "more" in nested:
            raise InputError(f"core {i} must be a core certificate of its own", codes.BAD_CERTIFICATE)
        _shape(nested, f"core {i}")
        later = certify(inst, nested, check_timeout=check_timeout)
        rows += [r | {"name": f"core {i}: {r['name']}"} for r in later.obligations]
    states = {r["status"] for r in rows}
    if states <= {"proved"}:
        status = CertifyStatus.CERTIFIED
    elif states & {"refuted", "mismatch", "missing"}:
        status = CertifyStatus.REFUTED
    else:
        status = CertifyStatus.UNCHECKED
    result = Certification(status, str(doc.get("method")), str(doc.get("producer")), rows)
    result.timings = {"total": time.perf_counter() - t0}
    return result


def _replays(
    inst: ir.Instance,
    doc: Mapping[str, Any],
    expected: Mapping[str, str],
    given: Sequence[ir.Objective] | None,
    answers: dict[int, Mapping[str, tuple[str, float]]],
) -> None:
    """The validator's answer on each composition the certificate holds (into ``answers``)."""
    for o in doc["obligations"]:
        if o.get("expect") == "valid" and doc.get("method") == "core" and o["name"] in expected:
            answers[id(o)] = {WITNESS: _replay(inst, doc, o)}
        elif o.get("expect") == "valid" and doc.get("method") == "least" and o["name"] == "witness":
            answers[id(o)] = {WITNESS: _replay_least(inst, doc, o)}
        elif o.get("expect") == "valid" and doc.get("method") == "optimal" and o["name"] == "witness":
            answers[id(o)] = {WITNESS: _replay_optimal(inst, doc, o, given)}
        elif o.get("expect") == "valid" and doc.get("method") == "discrete" and o["name"] == "witness":
            answers[id(o)] = {WITNESS: _replay_discrete(inst, doc, o)}
        elif o.get("expect") == "valid" and doc.get("method") == "pareto" and o["name"] in expected:
            answers[id(o)] = {WITNESS: _replay_point(inst, doc, o, given)}


def _missing(doc: Mapping[str, Any], expected: Mapping[str, str]) -> set[str]:
    """The obligations the certificate should hold and does not (for a core, each member
    needs a witness or a satisfiable obligation)."""
    names = {o["name"] for o in doc["obligations"]}
    if doc.get("method") == "discrete":  # the least obligation, and a witness or "restorable"
        return ({"least"} - names) | (set() if {"witness", "restorable"} & names else {"witness"})
    if doc.get("method") != "core":
        return set(expected) - names
    gone = {"core"} - names
    for label in doc["core"]:
        if not {f"witness/{label}", f"sat/{label}"} & names:
            gone.add(f"witness/{label}")
    return gone


def certify_json(inst: ir.Instance, result: Certification) -> dict:
    failed = [r["name"] for r in result.obligations if r["status"] != "proved"]
    return {
        "schema": "catc.certify/1",
        "status": result.status.value,
        "problem": inst.problem.name,
        "domain": inst.domain.name,
        "method": result.method,
        "producer": result.producer,
        "obligations": result.obligations,
        "failed": failed,
    }


_SAID = {
    "proved": "proved",
    "refuted": "REFUTED (a checker found it satisfiable)",
    "unchecked": "not decided by an independent checker",
    "mismatch": "does not match the model (rebuilt from the model and the certificate's claims)",
    "missing": "missing from the certificate",
}


def render(
    console: Console, inst: ir.Instance, result: Certification, options: Mapping[str, Any] | None = None
) -> None:
    head = {"certified": "CERTIFIED", "refuted": "REJECTED", "unchecked": "UNCHECKED"}[result.status.value]
    console.print(f"{head}  {result.method} certificate of problem {inst.problem.name} (produced by {result.producer})")
    for r in result.obligations:
        by = ", ".join(f"{c}: {a['answer']} ({a['seconds']:.2f} s)" for c, a in r["checkers"].items())
        console.print(f"  {r['name']}: {_SAID[r['status']]}" + (f" — {escape(by)}" if by else ""))


def _check(inst: ir.Instance, options: Mapping[str, Any]) -> str | None:
    """Read the certificate before running: its input errors have their own codes."""
    path = options.get("certificate_file")
    if not path:
        return "give the certificate: catc certify PROBLEM CERTIFICATE"
    doc = read_certificate(path)
    _same_problem(inst, doc)
    _expected(inst, doc, options.get("objectives") or None)
    return None


def _stored_objectives(options: Mapping[str, Any]) -> list[tuple[str, str]]:
    """The query's :attr:`~catc.queries.base.Query.objective_texts`: the command-line
    objectives the certificate stores, for the interface to parse (none when ``--minimize``
    or ``--maximize`` restate them, or the file cannot be read: ``check`` says why)."""
    path = options.get("certificate_file")
    if options.get("objectives") or not path:
        return []
    try:
        return objective_texts(read_certificate(path))
    except InputError:
        return []


def _run(
    inst: ir.Instance,
    certificate_file: str,
    check_timeout: float | None = None,
    horizon: int | None = None,
    sequential: bool = False,
    objectives: list[ir.Objective] | None = None,
) -> Certification:
    """The query's ``run`` (the horizon and the semantics are the certificate's own)."""
    return certify(inst, certificate_file, check_timeout=check_timeout, objectives=objectives)


QUERY = Query(
    "certify",
    summary="Check a catc.certificate/1 (from --certificate: a final UNSAT, a core, a least restoration, an "
    "optimum) with the z3 binary, cvc5 and the validator.",
    description="PATHS is PROBLEM, or DOMAIN PROBLEM, then the certificate.  Exit 0 when every obligation is "
    "proven by a checker other than the tool that produced the answer; 1 when one is refuted or does not match the "
    "model; 3 when one is undecided; 2 on an input error.",
    options=(
        Option("certificate_file", ("CERTIFICATE",), Kind.DOCUMENT_FILE, "The catc.certificate/1 file."),
        Option(
            "check_timeout",
            ("--check-timeout",),
            Kind.SECONDS,
            f"Seconds each checker may take on one obligation (default {CHECK_TIMEOUT:g}).",
        ),
        objectives_option(
            "A command-line objective of the certificate, restated (default: the text the certificate stores).",
            "A command-line objective of the certificate, restated (default: the text the certificate stores).",
        ),
        json_option("catc.certify/1"),
    ),
    run=_run,
    to_json=certify_json,
    render=render,
    check=_check,
    objective_texts=_stored_objectives,
)
