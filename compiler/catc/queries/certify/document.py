"""The ``catc.certificate/1`` document: its constants, how an obligation is written, and
how a certificate file is read and checked for shape (E1301, E1302, E1303)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir import SortKind
from catc.queries.base import (
    InputError,
)
from catgrammar import codes

SCHEMA = "catc.certificate/1"
CHECKERS = ("z3", "cvc5")
RELAXED = "catc.relaxed"  # the producer of an invariant: catc's relaxed reachability
CONSUMPTION = "catc.consumption"  # issue 24's h_max least-consumption bound (no solver)
SEARCH = "catc.search"  # the forward search's reachable states
#: How long each checker may take on one obligation, in seconds (``--check-timeout``).
CHECK_TIMEOUT = 60.0


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


def _pair(v: Any) -> bool:
    if not (isinstance(v, list) and len(v) == 2):
        return False
    try:
        return all(x is None or isinstance(Fraction(x), Fraction) for x in v)
    except (ValueError, TypeError, ZeroDivisionError):
        return False


def _obligation(name: str, proves: str, smtlib: str) -> dict:
    return {"name": name, "proves": proves, "expect": "unsat", "checkers": list(CHECKERS), "smtlib": smtlib}


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


WITNESS = "catc.validator"  # the checker of a witness composition


def _produced(doc: dict, producer: str) -> dict:
    for o in doc["obligations"]:
        o["producer"] = producer
    return doc


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
