"""The presolve of ``catc solve`` skips the consumption abstraction's solver check when a
component set found without a solver already satisfies it (issue 23, start-up): the check
could prove nothing then, and the process makes one Z3 context, as a hand-written script does.

The skip is checked against the solver itself: wherever the solver-free test passes, the
abstraction's own check answers SAT (so the skipped check would have returned no proof)."""

from __future__ import annotations

import subprocess
import sys

import pytest
from conftest import ROOT

from catc.api import load, loads
from catc.queries.solve import _passes_abstraction
from catc.smt.backend import Check
from catc.smt.consumption import Consumption, consumption_proof

#: (file, problem name or None) — feasible and infeasible examples, with and without resources
CASES = [
    ("examples/detection/person.cat", None),
    ("examples/gpu-allocation/max-confidence.cat", None),
    ("examples/navigation/farthest.cat", None),
    ("examples/navigation/coarse.cat", None),
    ("examples/lifelong/budget-cut.cat", None),
    ("examples/lifelong/cheaper-camera.cat", None),
    ("examples/search-and-rescue/budget-cut.cat", None),
    ("examples/search-and-rescue/mission.cat", None),
    ("examples/semantics/fixed-parameter.cat", "split-fixed"),
    ("examples/semantics/view.cat", "shop-full"),
    ("examples/pareto-design/design.cat", None),
]


#: catalogs of benchmarks/catalog_gen.py whose every alternative is affordable but no choice
#: of one per capability fits together (issue 24): only the abstraction sees that
CATALOG_VARIANTS = ["budget", "power", "ram", "missing"]


def _catalog(variant: str):
    sys.path.insert(0, str(ROOT / "benchmarks"))
    import catalog_gen as gen

    cat = gen.build(12, 4)
    text, _ = gen.problem_text(cat, variant)
    files = {"domain.cat": gen.domain_text(cat, missing=variant == "missing"), f"{variant}.cat": text}
    return loads(files, f"{variant}.cat").instance


def _instances():
    for path, problem in CASES:
        yield (
            path if problem is None else f"{path}:{problem}",
            lambda p=path, n=problem: load(ROOT / p, problem_name=n).instance,
        )
    for v in CATALOG_VARIANTS:
        yield f"catalog-{v}", lambda v=v: _catalog(v)


INSTANCES = list(_instances())


@pytest.mark.parametrize("make", [m for _, m in INSTANCES], ids=[name for name, _ in INSTANCES])
def test_the_test_passes_only_where_the_check_answers_sat(make):
    inst = make()
    a = Consumption(inst)
    if _passes_abstraction(inst):
        assert a.check(a.labels)[0] is Check.SAT
        assert consumption_proof(inst) is None
    else:  # nothing claimed; the check runs (on these catalogs it proves infeasibility)
        assert a.labels


def test_both_sides_are_covered():
    """The cases include instances the test passes and instances the check must settle."""
    passes = [_passes_abstraction(make()) for _, make in INSTANCES]
    assert any(passes) and not all(passes)


def _contexts(*args: str) -> int:
    """How many Z3 contexts ``catc ARGS`` makes in a fresh process."""
    probe = (
        "import z3\n"
        "made = []\n"
        "init = z3.Context.__init__\n"
        "def counted(self, *a, **k):\n"
        "    made.append(1)\n"
        "    init(self, *a, **k)\n"
        "z3.Context.__init__ = counted\n"
        "from catc.interfaces.entry import main\n"
        "try:\n"
        f"    main({list(args)!r})\n"
        "except SystemExit:\n"
        "    pass\n"
        "import sys\n"
        "print(len(made), file=sys.stderr)\n"
    )
    proc = subprocess.run([sys.executable, "-c", probe], cwd=ROOT, capture_output=True, text=True, timeout=120)
    return int(proc.stderr.split()[-1])


def test_a_plain_solve_makes_one_z3_context():
    assert _contexts("solve", "examples/detection/person.cat", "--json") == 1
    assert _contexts("check", "examples/detection/person.cat") == 0  # the probe counts what is made


def test_relax_shares_its_search_context_with_the_counting_bound():
    """relax on lifelong/budget-cut: the search's context (its two solvers) only; the counting
    bound's solver shares it (3 before), and the consumption bound, which has a context of its
    own, is not needed: the first restoration meets the counting bound (2 before).  On
    navigation/coarse the counting bound does not prove the first restoration least, and the
    consumption bound is made, as before (3: with the at-bound restoration's)."""
    assert _contexts("relax", "examples/lifelong/budget-cut.cat", "--json") == 1
    assert _contexts("relax", "examples/navigation/coarse.cat", "--json") == 3


def test_recompose_spares_the_refutation_its_deployed_composition_answers():
    """recompose on lifelong/cheaper-camera: the first composition (churn 4) is beaten by the
    deployed one (churn 0), so no refutation of "anything better than the first?" is tried;
    left are the deepening solve's context and the optimiser's over the first length (6
    before the fifth start-up step, 3 before the sixth).  That nothing within the horizon
    beats its optimum (churn 0, 0 USD) needs no solver now (tests/test_churn_floor.py); where
    the counting proof runs instead, its solver shares the optimiser's context, read by then."""
    assert _contexts("recompose", "examples/lifelong/cheaper-camera.cat", "--json") == 2
