"""The certificates of a final UNSAT of ``catc solve``: the relaxed fixpoint as an inductive
invariant, the step encoding at a complete horizon, the consumption abstraction, and the
forward search's reachable states."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir import SortKind
from catc.queries.base import (
    InputError,
)
from catc.queries.certify.bdd import ATOM_LIMIT, BDD_STATE_LIMIT
from catc.queries.certify.document import (
    CONSUMPTION,
    RELAXED,
    SCHEMA,
    SEARCH,
    NotCertifiable,
    _header,
    _inductive,
    _number,
    _obligation,
    _pair,
    _produced,
    _script,
)
from catgrammar import codes

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


def invariant_obligations(inst: ir.Instance, inv: Mapping[str, Mapping[str, Any]], horizon: int) -> list[dict]:
    """Initiation, consecution and goal exclusion of ``inv`` over the unrelaxed one-step
    encoding (the symbolic universes of ``horizon``)."""
    return _inductive(inst, horizon, False, lambda enc, state: invariant_text(enc, inv, state))


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


def state_bounded_obligations(inst: ir.Instance, horizon: int, sequential: bool) -> list[dict]:
    """The bounded problem at ``horizon`` = N − 1, N the model's count of states
    (:func:`catc.semantics.horizon.state_bound`).  Its completeness — some shortest
    composition visits no state twice, and at most N states exist — is not an SMT
    obligation: ``catc certify`` counts N again from the model (docs/semantics.md)."""
    from catc.smt.smtlib import emit_smt2

    return [
        _obligation(
            "bounded",
            f"no composition of at most {horizon} steps exists (the step encoding at horizon {horizon}; the model "
            f"has at most {horizon + 1} states, so a shortest composition has at most {horizon} steps)",
            emit_smt2(inst, horizon, sequential=sequential),
        )
    ]


def certificate(
    inst: ir.Instance, result: Any, *, state_limit: int = STATE_LIMIT, bdd_limit: int = BDD_STATE_LIMIT
) -> dict:
    """The certificate of ``result``, a final "no" of ``catc solve`` (NotCertifiable
    otherwise).  ``state_limit``: the most reachable states listed one by one (``reachable``);
    more, up to ``bdd_limit``, go into a BDD (``bdd``)."""
    from catc.queries.certify.finals import simple_path_certificate, sum_certificate
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
        found = _reachable(inst, doc, result, state_limit, bdd_limit) if result.sequential else None
        found = _state_bounded(inst, doc, result) if found is None else found
        if found is None:
            raise NotCertifiable("only a final UNSAT answer (no composition of any length) carries a certificate")
        return found
    found = simple_path_certificate(doc, inst, result)  # no path of t steps visits no state twice
    if found is not None:
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
    found = sum_certificate(doc, inst, result)
    if found is not None:
        return found
    if result.sequential and (getattr(result, "reason", None) or "").startswith("forward search"):
        found = _reachable(inst, doc, result, state_limit, bdd_limit)
        if found is None:
            raise NotCertifiable(
                f"the forward search's reachable states are more than {bdd_limit} (or not all of them can be "
                f"written, or their BDD has more than {ATOM_LIMIT} atoms): their invariant is not certified"
            )
        return found
    found = _state_bounded(inst, doc, result)
    if found is not None:
        return found
    raise NotCertifiable(
        "this UNSAT was proven neither by relaxed reachability at its fixpoint, nor by the step encoding at a "
        "complete horizon, nor by the consumption abstraction, a conserved sum, the absence of a path visiting no "
        "state twice or the forward search: no certificate yet"
    )


def _reachable(inst: ir.Instance, doc: dict[str, Any], result: Any, limit: int, bdd_limit: int) -> dict | None:
    """The reachable-states certificate (sequential steps): every state compositions of any
    length reach, none a goal state — listed when at most ``limit``, else as a BDD
    (:func:`~catc.queries.certify.bdd.bdd_certificate`); None otherwise."""
    from catc.queries.certify.bdd import bdd_certificate
    from catc.semantics.search import reachable_states

    found = reachable_states(inst, max(limit, bdd_limit))  # once: the list or the BDD takes them
    if found is None:
        return None
    if len(found[1]) > limit:
        return bdd_certificate(inst, doc, result, found)
    spec = states_json(inst, *found)
    doc = doc | {"answer": "unsat", "method": "reachable", "producer": SEARCH, "horizon": result.horizon}
    doc |= {"sequential": True, "states": spec, "obligations": reachable_obligations(inst, spec, result.horizon)}
    return _produced(doc, SEARCH)


def _state_bounded(inst: ir.Instance, doc: dict[str, Any], result: Any) -> dict | None:
    """The reachable-state bound's certificate: the model has at most N states and the
    answer's horizon reaches N − 1 (a shortest composition visits no state twice); None
    otherwise."""
    from catc.semantics.horizon import state_bound

    states = state_bound(inst, result.horizon + 1)
    if states is None or result.horizon < states - 1:
        return None
    horizon = max(states - 1, 0)
    doc = doc | {"answer": "unsat", "method": "state-bounded", "producer": result.backend, "horizon": horizon}
    doc |= {"sequential": bool(result.sequential), "state_count": states}
    doc["obligations"] = state_bounded_obligations(inst, horizon, bool(result.sequential))
    return _produced(doc, result.backend)


def _abstraction_refutes(inst: ir.Instance) -> bool:
    from catc.smt.backend import Check
    from catc.smt.consumption import Consumption

    a = Consumption(inst)
    return bool(a.labels) and a.check(a.labels)[0] is Check.UNSAT


def _everything() -> Any:
    from catc.semantics.relaxed import _Everything

    return _Everything()
