"""Property: every valid model the strategies of tests/strategies.py generate goes through
the whole pipeline cleanly (issue 15, item 2).

Each model checks without errors; ``catc solve`` answers SAT or UNSAT (no deadline: nothing
here is timed); a SAT composition is accepted by the independent validator (inside solve,
and once more on its own); ``catc fmt`` is idempotent on the text and meaning-preserving
(the formatted text checks to the same diagnostics and the same IR, positions aside); the
PDDL exports either succeed or refuse with an ``ExportError``.  The oracle is the fuzzing
harness's (benchmarks/fuzz_oracle.py), so the fuzzer and these tests hold the pipeline to
one standard.
"""

from __future__ import annotations

import os
import sys

import pytest
from conftest import ROOT
from hypothesis import HealthCheck, given, settings
from strategies import models

sys.path.insert(0, str(ROOT / "benchmarks"))
import fuzz_oracle

from catc.api import loads
from catc.frontend.formatter import format_text

SETTINGS = {
    "deadline": None,
    "suppress_health_check": [HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
}


def _pipeline(tmp_path, model) -> list[str]:
    work = tmp_path / "work"
    work.mkdir(exist_ok=True)
    for old in work.iterdir():
        old.unlink()
    reached: list[str] = []
    findings = fuzz_oracle.examine(model.text.encode(), work, timeout=None, reached=reached)
    assert findings == [], model.text
    assert "checked clean" in reached, model.text
    assert {"answered sat", "answered unsat"} & set(reached), (reached, model.text)
    return reached


@settings(max_examples=int(os.environ.get("CATC_PROPERTY_EXAMPLES", "25")), **SETTINGS)
@given(model=models())
def test_generated_models_check_solve_validate_and_format(tmp_path, model):
    _pipeline(tmp_path, model)


@pytest.mark.slow
@settings(max_examples=400, **SETTINGS)
@given(model=models(max_morphisms=5, max_horizon=4))
def test_generated_models_at_scale(tmp_path, model):
    _pipeline(tmp_path, model)


@settings(max_examples=10, **SETTINGS)
@given(model=models())
def test_generated_models_are_already_valid_and_reach_every_sort(model):
    """The strategies' own promise: a model loads through the public API, and it declares
    a resource of every sort the language has."""
    inst = loads({"gen.cat": model.text}, "gen.cat").instance
    kinds = {r.sort.kind.value for r in inst.resources.values()}
    assert {"bool", "int", "real", "enum", "symbol", "set"} <= kinds, kinds
    assert format_text(format_text(model.text)) == format_text(model.text)


def test_the_oracle_can_fail(tmp_path):
    """The oracle reports what it is there to report: a formatter that changes the meaning,
    a validator that rejects the solver's answer, an exception inside a stage."""
    text = (ROOT / "examples/semantics/frame.cat").read_bytes()
    work = tmp_path / "w"
    work.mkdir()
    original = fuzz_oracle.format_file

    def reorder(path, diags):  # a "formatter" that turns the first `true` into `false`
        raw, formatted = original(path, diags)
        return raw, formatted.replace("true", "false", 1)

    fuzz_oracle.format_file = reorder
    try:
        found = fuzz_oracle.examine(text, work, timeout=None)
    finally:
        fuzz_oracle.format_file = original
    assert [f.category for f in found] == [fuzz_oracle.MEANING]

    def broken_validate(*args, **kwargs):
        raise RuntimeError("boom")

    saved, fuzz_oracle.validate = fuzz_oracle.validate, broken_validate
    try:
        found = fuzz_oracle.examine(text, work, timeout=None)
    finally:
        fuzz_oracle.validate = saved
    assert fuzz_oracle.INTERNAL in [f.category for f in found]
