"""The certificates of an optimum: a least restoration of ``catc relax``, an optimal
composition of ``catc optimize`` / ``catc recompose``, a Pareto front — each a witness and
"nothing cheaper (better)" as an unsat obligation."""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir import SortKind
from catc.queries.base import (
    InputError,
)
from catc.queries.certify.document import (
    SCHEMA,
    SEARCH,
    WITNESS,
    NotCertifiable,
    _header,
    _number,
    _obligation,
    _pair,
    _script,
)
from catgrammar import codes

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


# -- a shortest composition (the unified-planning engine's SOLVED_OPTIMALLY for plan length)


def shortest_obligations(inst: ir.Instance, length: int, sequential: bool) -> list[dict]:
    """ "No composition of fewer than ``length`` steps": the bounded problem at ``length`` − 1
    (``catc compile``'s SMT-LIB2), unsat; none when ``length`` is 0 (nothing is shorter)."""
    from catc.smt.smtlib import emit_smt2

    if length == 0:
        return []
    return [
        _obligation(
            "shorter",
            f"no composition of at most {length - 1} steps exists (the step encoding at horizon {length - 1})",
            emit_smt2(inst, length - 1, sequential=sequential),
        )
    ]


def shortest_certificate(inst: ir.Instance, result: Any, options: Mapping[str, Any]) -> dict:
    """The certificate of a composition proven shortest (a ``catc solve`` answer whose plan is
    shortest): the witness, replayed by the validator with exactly ``length`` steps, and the
    bounded problem one step shorter, unsat."""
    from catc.semantics.plan import plan_to_json

    if result.status.value != "sat" or result.plan is None or not getattr(result, "shortest", False):
        raise NotCertifiable("only a composition proven shortest carries a certificate of its length")
    sequential = bool(options.get("sequential", result.sequential))
    length = len(result.plan.steps)
    producer = str(options.get("producer", SEARCH))  # the engine's: A* over the forward search
    doc: dict[str, Any] = {"schema": SCHEMA, "problem": inst.problem.name, "domain": inst.domain.name}
    doc |= {"view": inst.view, "answer": "shortest", "method": "shortest", "producer": producer, "horizon": length}
    doc["sequential"] = sequential
    witness = {
        "name": "witness",
        "proves": f"this composition of {length} steps reaches the goal",
        "expect": "valid",
        "checkers": [WITNESS],
        "producer": producer,
        "plan": plan_to_json(result.plan),
    }
    shorter = [o | {"producer": producer} for o in shortest_obligations(inst, length, sequential)]
    return doc | {"obligations": [witness, *shorter]}


def _replay_shortest(inst: ir.Instance, doc: Mapping[str, Any], o: Mapping[str, Any]) -> tuple[str, float]:
    """The witness of a shortest composition: valid on the model, with exactly the
    certificate's ``horizon`` steps."""
    from catc.semantics.plan import PlanFormatError, read_plan
    from catc.semantics.validate import validate

    t0 = time.perf_counter()
    try:
        plan = read_plan(inst, o.get("plan"))
    except PlanFormatError:
        return "invalid", time.perf_counter() - t0
    length, sequential = doc["horizon"], bool(doc.get("sequential"))
    ok = len(plan.steps) == length and validate(inst, plan, horizon=length, sequential=sequential).ok
    return ("valid" if ok else "invalid"), time.perf_counter() - t0
