"""The generic registry (catgrammar.registry) behind the query, target, lint and backend
registries: a name → "module:attr" table, imported on first use."""

from __future__ import annotations

import subprocess
import sys

import pytest
from conftest import ROOT

from catc.frontend.lints import registry as lints
from catc.queries import registry as queries
from catc.smt.backend import BackendError, open_backend
from catc.targets import registry as targets
from catgrammar.registry import Registry, UnknownName


def test_a_part_is_found_by_name_with_the_default_or_its_own_attribute():
    reg: Registry[object] = Registry("thing", {"frac": "fractions:Fraction", "path": "pathlib"}, "PurePath")
    assert reg.names() == ["frac", "path"] and "frac" in reg and "nope" not in reg
    from fractions import Fraction
    from pathlib import PurePath

    assert reg.get("frac") is Fraction and reg.get("path") is PurePath


def test_an_unknown_name_is_a_key_error_naming_what_there_is():
    reg: Registry[object] = Registry("thing", {"b": "fractions", "a": "pathlib"}, "X")
    with pytest.raises(KeyError) as exc:
        reg.get("c")
    assert isinstance(exc.value, UnknownName)
    assert str(exc.value) == "unknown thing 'c'; expected one of: a, b"
    for registry, kind in ((queries, "query"), (targets, "target"), (lints, "lint")):
        with pytest.raises(UnknownName, match=f"unknown {kind} 'nope'"):
            registry.get("nope")
    with pytest.raises(BackendError, match="unknown backend 'nope'; expected one of: cvc5, z3"):
        open_backend("nope")


def test_entries_are_read_live(monkeypatch):
    monkeypatch.setitem(targets.TARGETS, "again", "catc.targets.smt2")
    assert "again" in targets.names() and targets.get("again") is targets.get("smt2")


def test_nothing_is_imported_before_it_is_asked_for():
    probe = (
        "import sys\n"
        "from catc.targets import registry\n"
        "before = 'catc.targets.pddl_target' in sys.modules\n"
        "registry.get('smt2')\n"
        "print(before, 'catc.targets.smt2' in sys.modules, 'catc.targets.pddl_target' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", probe], cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert out.stdout.split() == ["False", "True", "False"]
