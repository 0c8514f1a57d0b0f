"""The certificates of a core of ``catc diagnose`` (its UNSAT, and a witness per member it
cannot lose) and of ``catc relax --discrete``'s least set of dropped constraints."""

from __future__ import annotations

import re
import time
from collections.abc import Collection, Mapping, Sequence
from typing import Any

from catc import ir
from catc.queries.base import (
    InputError,
)
from catc.queries.certify.document import SCHEMA, WITNESS, NotCertifiable, _header, _obligation, _script
from catgrammar import codes

# -- a core of catc diagnose: its UNSAT, and a witness for each member it cannot lose


def _labelled(inst: ir.Instance, horizon: int, sequential: bool, components: Sequence[str] | None) -> Any:
    from catc.smt.labelled import LabelledModel

    return LabelledModel(inst, horizon, sequential=sequential, components=components)


def _extended(inst: ir.Instance, horizon: int, components: Sequence[str] | None) -> int:
    """The steps diagnose's labelled formula reaches past ``horizon`` (its ``horizon`` label);
    the last answer kept, as every witness of a core asks the same."""
    from catc.smt.labelled import _extended_horizon

    key = (horizon, None if components is None else tuple(components))
    if not (_EXTENDED and _EXTENDED[0][0] is inst and _EXTENDED[0][1] == key):
        _EXTENDED[:] = [(inst, key, _extended_horizon(inst, horizon, components))]
    steps: int = _EXTENDED[0][2]
    return steps


_EXTENDED: list[tuple[Any, Any, int]] = []


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
    100-component catalog): it need not search over the labels the core leaves free.  An
    implication whose guard has a denied indicator as a conjunct holds in every model and is
    left out (:func:`_vacuous`; cvc5 3× quicker again at n = 100): fewer assertions, so unsat
    still proves the core, and the same models, so it is unsat exactly when the whole is."""
    from catc.smt.consumption import Consumption

    a = Consumption(inst, components)
    denied = {str(a.indicator[label]) for label in a.labels if label not in set(core)}
    body = [text for text in a.assertions if not _vacuous(text, denied)]
    body += [str(a.indicator[label]) for label in core if label in a.indicator]
    body += [f"(not {a.indicator[label]})" for label in a.labels if label not in set(core)]
    return _script(
        _header(inst, "core: the consumption abstraction with the core's labels enforced is unsat"),
        [s.declaration() for s in a.declarations],
        body,
    )


def _vacuous(text: str, denied: Collection[str]) -> bool:
    """Whether ``text`` is ``(=> G φ)`` with ``G`` a symbol of ``denied`` or an ``(and ...)``
    with one among its top-level conjuncts (each a symbol, ``|quoted|`` or not)."""
    if not text.startswith("(=> "):
        return False
    guard = _first_term(text, 4)
    if guard in denied:
        return True
    if not guard.startswith("(and "):
        return False
    i, conjuncts = 5, []
    while i < len(guard) - 1:
        term = _first_term(guard, i)
        if not term:
            break
        conjuncts.append(term)
        i += len(term) + 1
    return any(term in denied for term in conjuncts)


_ATOM_END = re.compile(r"[\s()]")


def _first_term(text: str, start: int) -> str:
    """The s-expression term of ``text`` that begins at ``start`` ("" when none does)."""
    if text[start : start + 1] == "|":  # a quoted symbol
        end = text.find("|", start + 1)
        return text[start:] if end < 0 else text[start : end + 1]
    if text[start : start + 1] != "(":  # a plain symbol or literal
        found = _ATOM_END.search(text, start)
        return text[start : found.start() if found else len(text)]
    depth, quoted = 0, False
    for i in range(start, len(text)):
        c = text[i]
        if quoted:
            quoted = c != "|"
        elif c == "|":
            quoted = True
        elif c == "(":
            depth += 1
        elif c == ")":
            if depth == 0:
                return text[start:i]
            depth -= 1
            if depth == 0:
                return text[start : i + 1]
        elif c.isspace() and depth == 0:
            return text[start:i]
    return text[start:]


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
