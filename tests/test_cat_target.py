"""The ``.cat`` writer as the registered target ``cat`` (issue 23): listed by the target
registry, so ``catc export cat``, ``Model.export("cat")`` and the language server's
``catc.export.cat`` come from one entry, and its files round-trip.

The round trip is checked against independent facts, not against the writer's own output:
the written problem passes ``catc check`` with no error, ``catc fmt --check`` leaves it as it
is, solving it gives the same status and the same least number of steps as the original, and
the original's composition is accepted by the validator on the written model."""

from __future__ import annotations

import json

import pytest
from conftest import ROOT, run_catc

from catc.api import load
from catc.frontend.formatter import format_text
from catc.targets import registry

#: examples without a (:view ...) of their own (a view's projection is not written back)
EXAMPLES = [
    "examples/detection/person.cat",
    "examples/detection/unmodeled-class.cat",
    "examples/gpu-allocation/max-confidence.cat",
    "examples/lifelong/budget-cut.cat",
    "examples/navigation/farthest.cat",
    "examples/search-and-rescue/event1-fresh.cat",
    "examples/holes/talk.cat",
]


def test_the_registry_lists_the_cat_target():
    assert "cat" in registry.names()
    target = registry.get("cat")
    assert target.command == ("export", "cat") and target.layout is not None
    assert registry.by_command(("export", "cat")) is target
    assert "cat" in run_catc("export", "--help").stdout


@pytest.mark.parametrize("path", EXAMPLES)
def test_export_cat_round_trips(path, tmp_path):
    out = tmp_path / "out"
    wrote = run_catc("export", "cat", ROOT / path, "-o", out)
    assert wrote.exit_code == 0, wrote.stderr
    problem, domain = out / "problem.cat", out / "domain.cat"
    checked = run_catc("check", problem, "--format", "json")
    assert checked.exit_code == 0, checked.stdout
    assert run_catc("fmt", "--check", problem, domain).exit_code == 0  # laid out as catc fmt does
    before, after = run_catc("solve", ROOT / path, "--json"), run_catc("solve", problem, "--json")
    assert before.exit_code == after.exit_code
    a, b = json.loads(before.stdout), json.loads(after.stdout)
    assert (a["status"], a["problem"], a["domain"]) == (b["status"], b["problem"], b["domain"])
    if a["status"] == "sat":
        assert len(a["steps"]) == len(b["steps"])  # both the shortest composition
        plan = tmp_path / "plan.json"
        plan.write_text(before.stdout)
        assert run_catc("validate", problem, plan).exit_code == 0


def test_every_interface_gives_the_same_text(tmp_path):
    path = ROOT / "examples/gpu-allocation/max-confidence.cat"
    files = load(path).export("cat")
    assert format_text(files.domain) == files.domain and format_text(files.problem) == files.problem
    printed = run_catc("export", "cat", path)
    assert printed.exit_code == 0 and printed.stdout == files.domain + "\n" + files.problem
    doc = json.loads(run_catc("export", "cat", path, "--json").stdout)
    assert doc == {"schema": "catc.export-cat/1", "domain": files.domain, "problem": files.problem}


def test_a_projected_model_is_an_input_error():
    res = run_catc("export", "cat", ROOT / "examples/semantics/view.cat", "--problem", "shop-software")
    assert res.exit_code == 2
    assert "error[E0901]" in res.stderr and "view" in res.stderr
