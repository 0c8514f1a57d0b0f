"""The driver of ``catc certify``: rebuild every obligation from the model and the
certificate's claims, run the checkers and the validator, and say what each proved."""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from fractions import Fraction
from typing import Any

from catc import ir
from catc.present.console import Console, escape
from catc.queries.base import (
    ExitCode,
    InputError,
    Result,
    Status,
)
from catc.queries.certify.bdd import bdd_obligations, read_bdd
from catc.queries.certify.checkers import _run_checkers
from catc.queries.certify.cores import _replay, _replay_discrete, core_obligations, discrete_obligations
from catc.queries.certify.document import (
    CHECK_TIMEOUT,
    WITNESS,
    _components,
    _labels,
    _same_problem,
    _shape,
    _significant,
    read_certificate,
)
from catc.queries.certify.finals import _read_sums, expected_simple_path, sum_obligations
from catc.queries.certify.optimal import (
    _objectives,
    _pareto_objectives,
    _read_points,
    _read_requirements,
    _replay_least,
    _replay_optimal,
    _replay_point,
    _replay_shortest,
    least_obligation,
    optimal_obligation,
    pareto_obligation,
    shortest_obligations,
)
from catc.queries.certify.unsat import (
    _claims_hold,
    _read_invariant,
    _read_states,
    bounded_obligations,
    consumption_obligations,
    invariant_obligations,
    reachable_obligations,
    state_bounded_obligations,
)
from catgrammar import codes


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


def _searched(inst: ir.Instance, doc: Mapping[str, Any], method: str, horizon: int) -> list[dict]:
    """The obligations of the forward search's reachable states: listed (``reachable``) or as
    a BDD (``bdd``), over the sequential one-step encoding."""
    if doc.get("sequential") is not True:
        raise InputError("a reachable-states certificate is for sequential steps", codes.BAD_CERTIFICATE)
    if method == "bdd":
        return bdd_obligations(inst, read_bdd(inst, doc.get("bdd")), horizon)
    return reachable_obligations(inst, _read_states(inst, doc.get("states")), horizon)


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
    elif method == "state-bounded":
        from catc.semantics.horizon import state_bound

        states = state_bound(inst, horizon + 1)
        if states is None or doc.get("state_count") != states or horizon < states - 1:
            return {}  # the model does not have that few states: the horizon is not complete
        built = state_bounded_obligations(inst, horizon, bool(doc.get("sequential")))
    elif method == "simple-path":
        built = expected_simple_path(inst, doc, horizon)
    elif method == "conserved-sum":
        built = sum_obligations(inst, _read_sums(inst, doc.get("conserved")), horizon, bool(doc.get("sequential")))
    elif method == "shortest":
        built = shortest_obligations(inst, horizon, bool(doc.get("sequential")))
        return {o["name"]: o["smtlib"] for o in built} | {"witness": ""}
    elif method == "consumption":
        if not _claims_hold(inst, doc.get("bounds", [])):
            return {}  # a claimed bound the model does not give: nothing matches
        built = consumption_obligations(inst)
    elif method in ("reachable", "bdd"):
        built = _searched(inst, doc, method, horizon)
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


#: What :func:`prepared` read and rebuilt last: (the instance, the file, its stamp, the
#: objectives, the document, the expected texts) — the query's ``check`` reads the file and
#: rebuilds every obligation before ``run``, which then need not do it again.
_PREPARED: list[tuple[Any, ...]] = []


def prepared(inst: ir.Instance, path: str, given: Sequence[ir.Objective] | None) -> tuple[dict, dict[str, str]]:
    """The certificate file ``path`` read, checked to be of ``inst``'s problem, and its
    obligations' texts rebuilt from the model (:func:`_expected`); the last answer again when
    the same instance, file (unchanged since) and objectives are asked again."""
    import os

    try:
        stat = os.stat(path)
        stamp: tuple[int, int] | None = (stat.st_mtime_ns, stat.st_size)
    except OSError:
        stamp = None  # read_certificate says why
    for entry in _PREPARED:
        if stamp is not None and entry[0] is inst and entry[1:3] == (path, stamp) and _same(entry[3], given):
            return entry[4], entry[5]
    doc = read_certificate(path)
    _same_problem(inst, doc)
    expected = _expected(inst, doc, given)
    _PREPARED[:] = [(inst, path, stamp, None if given is None else list(given), doc, expected)]
    return doc, expected


def _same(a: Sequence[Any] | None, b: Sequence[Any] | None) -> bool:
    """The same objectives: both none, or the very same objects in order."""
    if a is None or b is None:
        return a is b
    return len(a) == len(b) and all(x is y for x, y in zip(a, b))


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
    given = list(objectives) if objectives else None
    if isinstance(certificate, str):
        doc, expected = prepared(inst, certificate, given)
    else:
        doc = dict(certificate)
        _same_problem(inst, doc)
        expected = _expected(inst, doc, given)
    t0 = time.perf_counter()
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
        elif o.get("expect") == "valid" and doc.get("method") == "shortest" and o["name"] == "witness":
            answers[id(o)] = {WITNESS: _replay_shortest(inst, doc, o)}
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
