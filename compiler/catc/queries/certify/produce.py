"""Which certificate an answer carries (:func:`certificate_of`) and ``--certificate FILE``
(:func:`certificate_artifact`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from catc import ir
from catc.present.console import counted
from catc.queries.base import (
    InputError,
)
from catc.queries.certify.cores import core_certificate, discrete_certificate
from catc.queries.certify.document import NotCertifiable
from catc.queries.certify.optimal import (
    least_certificate,
    optimal_certificate,
    pareto_certificate,
    shortest_certificate,
)
from catc.queries.certify.unsat import certificate
from catgrammar import codes


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
    if result.query == "solve" and options.get("shortest"):  # the engine's SOLVED_OPTIMALLY for plan length
        return shortest_certificate(inst, result, options)
    return certificate(inst, result)


def certificate_artifact(inst: ir.Instance, result: Any, options: Mapping[str, Any]) -> str:
    """``--certificate FILE`` (called by :mod:`catc.interfaces.command` after the query): write the
    certificate of ``result``; what to tell the user."""
    status = getattr(getattr(result, "status", None), "value", None)
    if result.query == "solve" and status != "unsat":
        return "no certificate written: the answer is not a 'no' (its composition is replayed by the validator)"
    return write_certificate(inst, result, options)
