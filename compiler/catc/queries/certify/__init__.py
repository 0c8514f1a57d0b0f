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
* a final UNSAT by **no path of t steps visiting no state twice** (the recurrence diameter):
  that path, unsat, and the bounded problem at t − 1, unsat (``simple-path``,
  :mod:`catc.queries.certify.finals`);
* a final UNSAT by **the forward search**: its reachable states as an inductive invariant of
  the sequential one-step encoding — listed (``reachable``, at most 2,000) or as a reduced
  ordered BDD written as a ``let``/``ite`` DAG (``bdd``, :mod:`catc.queries.certify.bdd`);
* a final UNSAT by **a conserved sum**: the sums, the numeric ranges and the unwritten numbers
  as an inductive invariant of the one-step encoding (``conserved-sum``);
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

from collections.abc import Mapping
from typing import Any

from catc import ir
from catc.queries.base import InputError, Kind, Option, Query, json_option, objectives_option
from catc.queries.certify.check import Certification as Certification

# what the package offers (the registry, the interfaces, the tests): each from its module
from catc.queries.certify.check import CertifyStatus as CertifyStatus
from catc.queries.certify.check import certify as certify
from catc.queries.certify.check import certify_json as certify_json
from catc.queries.certify.check import prepared
from catc.queries.certify.check import render as render
from catc.queries.certify.checkers import cvc5_command as cvc5_command
from catc.queries.certify.checkers import run_checker as run_checker
from catc.queries.certify.checkers import z3_command as z3_command
from catc.queries.certify.cores import consumption_core_text as consumption_core_text
from catc.queries.certify.cores import core_certificate as core_certificate
from catc.queries.certify.cores import core_obligations as core_obligations
from catc.queries.certify.cores import discrete_certificate as discrete_certificate
from catc.queries.certify.cores import discrete_obligations as discrete_obligations
from catc.queries.certify.cores import witness_instance as witness_instance
from catc.queries.certify.document import CHECK_TIMEOUT as CHECK_TIMEOUT
from catc.queries.certify.document import SCHEMA as SCHEMA
from catc.queries.certify.document import NotCertifiable as NotCertifiable
from catc.queries.certify.document import read_certificate as read_certificate
from catc.queries.certify.finals import simple_path_obligations as simple_path_obligations
from catc.queries.certify.finals import sum_obligations as sum_obligations
from catc.queries.certify.optimal import least_certificate as least_certificate
from catc.queries.certify.optimal import least_obligation as least_obligation
from catc.queries.certify.optimal import objective_texts as objective_texts
from catc.queries.certify.optimal import optimal_certificate as optimal_certificate
from catc.queries.certify.optimal import optimal_obligation as optimal_obligation
from catc.queries.certify.optimal import pareto_certificate as pareto_certificate
from catc.queries.certify.optimal import pareto_obligation as pareto_obligation
from catc.queries.certify.optimal import shortest_certificate as shortest_certificate
from catc.queries.certify.produce import certificate_artifact as certificate_artifact
from catc.queries.certify.produce import certificate_of as certificate_of
from catc.queries.certify.produce import write_certificate as write_certificate
from catc.queries.certify.unsat import bounded_obligations as bounded_obligations
from catc.queries.certify.unsat import certificate as certificate
from catc.queries.certify.unsat import consumption_obligations as consumption_obligations
from catc.queries.certify.unsat import invariant_obligations as invariant_obligations
from catc.queries.certify.unsat import reachable_obligations as reachable_obligations
from catc.queries.certify.unsat import state_bounded_obligations as state_bounded_obligations


def _check(inst: ir.Instance, options: Mapping[str, Any]) -> str | None:
    """Read the certificate before running: its input errors have their own codes."""
    path = options.get("certificate_file")
    if not path:
        return "give the certificate: catc certify PROBLEM CERTIFICATE"
    prepared(inst, path, options.get("objectives") or None)  # run finds it done
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
