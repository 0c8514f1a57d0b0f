"""The command line keeps checked standard-library domains between runs
(:mod:`catc.frontend.stdlib_cache`): a hit parses and checks none of them, answers as a
miss does, and anything that made the kept IR — a standard-library file, the checker's
code — changes the key; a damaged file is a miss."""

from __future__ import annotations

import shutil

from conftest import ROOT, answer_document

from catc.frontend.stdlib_cache import StdlibCache
from catc.frontend.workspace import Workspace, stdlib_dir
from catgrammar.diagnostics import Diagnostics

PERSON = ROOT / "examples/detection/person.cat"  # its domain imports robot-base: five stdlib domains


def _robot_base(cache: StdlibCache) -> tuple[Workspace, object]:
    ws = Workspace(Diagnostics(), stdlib_cache=cache)
    return ws, ws.domain_ir("robot-base", None, None, importing=True)


def test_a_hit_parses_nothing_and_gives_the_same_domain(tmp_path):
    cache = StdlibCache(tmp_path, stdlib_dir())
    first_ws, first = _robot_base(cache)
    assert any("robot-base.cat" in f for f in first_ws.files)  # a miss: parsed and checked
    kept = sorted(p.name.rsplit("-", 1)[0] for p in tmp_path.iterdir())
    assert kept == ["compute", "electromechanical", "external", "information", "robot-base"]
    again_ws, again = _robot_base(StdlibCache(tmp_path, stdlib_dir()))
    assert again_ws.files == {} and again == first and again is not first
    assert again_ws.checked_domains() == [again]
    _, fresh = _robot_base(None)  # no cache at all: the same domain
    assert fresh == again


def test_the_key_follows_the_standard_library_text(tmp_path):
    lib = tmp_path / "lib"
    shutil.copytree(stdlib_dir(), lib)
    before = StdlibCache(tmp_path / "c", lib).key
    (lib / "compute.cat").write_text((lib / "compute.cat").read_text() + "\n; an edit\n")
    assert StdlibCache(tmp_path / "c", lib).key != before


def test_a_damaged_file_is_a_miss(tmp_path):
    cache = StdlibCache(tmp_path, stdlib_dir())
    _, first = _robot_base(cache)
    for p in tmp_path.iterdir():
        p.write_bytes(b"not a pickle")
    ws, again = _robot_base(StdlibCache(tmp_path, stdlib_dir()))
    assert again == first and any("robot-base.cat" in f for f in ws.files)


def test_the_command_line_answers_alike_with_and_without_it(tmp_path, monkeypatch):
    monkeypatch.setenv("CATC_CACHE", "off")
    without = answer_document("solve", str(PERSON), "--json")
    assert not (tmp_path / "stdlib").exists()
    monkeypatch.setenv("CATC_CACHE", str(tmp_path))
    filling = answer_document("solve", str(PERSON), "--json")
    assert len(list((tmp_path / "stdlib").iterdir())) == 5
    hit = answer_document("solve", str(PERSON), "--json")
    assert without == filling == hit and without["status"] == "sat"
    diagnose = answer_document("diagnose", str(ROOT / "examples/lifelong/budget-cut.cat"), "--json")
    monkeypatch.setenv("CATC_CACHE", "off")
    assert answer_document("diagnose", str(ROOT / "examples/lifelong/budget-cut.cat"), "--json") == diagnose
