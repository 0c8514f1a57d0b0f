"""The queries, by name.  Adding a query: one module defining ``QUERY`` (see
:mod:`catc.queries.base`), and one line here.  Modules are imported on first use, so
answering one query loads only its own module."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from fractions import Fraction
from typing import TYPE_CHECKING, Any

from catc.queries.base import Query
from catgrammar.registry import Registry

if TYPE_CHECKING:  # pragma: no cover
    from catc import ir

QUERIES: dict[str, str] = {
    "solve": "catc.queries.solve",
    "optimize": "catc.queries.optimize",
    "pareto": "catc.queries.pareto",
    "diagnose": "catc.queries.diagnose",
    "relax": "catc.queries.relax",
    "recompose": "catc.queries.recompose",
    "synthesize": "catc.queries.synthesize",
    "validate": "catc.queries.validate",
    "certify": "catc.queries.certify",
}

REGISTRY: Registry[Query] = Registry("query", QUERIES, "QUERY")


def names() -> list[str]:
    return REGISTRY.names()


def get(name: str) -> Query:
    """The query named ``name`` (:class:`~catgrammar.registry.UnknownName`, a KeyError, when
    there is none)."""
    return REGISTRY.get(name)


def for_result(result: object) -> Query:
    """The query whose answer ``result`` is."""
    name = getattr(type(result), "query", "")
    if name not in QUERIES:
        raise TypeError(f"not a catc query result: {type(result).__name__}")
    return get(name)


def deploy_query(inst: ir.Instance) -> str:
    """The query that finds the composition to deploy (``catc ground``, the runtime): the
    optimum when the problem says what is best — a metric or soft constraints — else the
    shortest (``solve``)."""
    return "optimize" if inst.problem.metric is not None or inst.problem.softs else "solve"


def relax_weights(
    inst: ir.Instance, only: Iterable[str], weights: Mapping[str, Fraction] | None, fixed: Iterable[str]
) -> tuple[dict[str, Fraction], str | None]:
    """The weights ``relax`` gives by default (:func:`catc.queries.relax.unit_safe_weights`),
    for the runtime's ``[relax]`` policy (the relax module loads only when asked)."""
    found: tuple[dict[str, Fraction], str | None] = REGISTRY.module("relax").unit_safe_weights(
        inst, only, weights, fixed
    )
    return found


def certificate_artifact(inst: ir.Instance, result: object, options: Mapping[str, Any]) -> str:
    """``--certificate FILE`` of any query that offers it: write the proof of its answer and
    say where (the certificate module loads only when asked)."""
    artifact: str = REGISTRY.module("certify").certificate_artifact(inst, result, options)
    return artifact


def certificate_document(
    inst: ir.Instance, result: object, options: Mapping[str, Any] | None = None
) -> tuple[dict[str, Any] | None, str]:
    """The catc.certificate/1 document proving ``result`` (any query's answer; ``options``:
    the query's, e.g. ``sequential``), or ``None`` and why there is none."""
    certify = REGISTRY.module("certify")
    try:
        return certify.certificate_of(inst, result, options or {}), ""
    except certify.NotCertifiable as exc:
        return None, str(exc)
