"""The command line keeps checked standard-library domains between runs
(:mod:`catc.frontend.stdlib_cache`): a hit parses and checks none of them, answers as a
miss does, and anything that made the kept IR — a standard-library file, the checker's
code — changes the key; a damaged file is a miss."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from conftest import CATC_CACHE, ROOT, answer_document

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


def test_entries_made_under_another_key_stay(tmp_path):
    """Two checkouts sharing one cache folder (their keys differ: other paths) each find their
    own entries after the other wrote (put used to delete every other key's entry of a name)."""
    _, domain = _robot_base(None)
    libs = []
    for name in ("a", "b"):
        libs.append(tmp_path / name)
        shutil.copytree(stdlib_dir(), libs[-1])
    a, b = (StdlibCache(tmp_path / "c", lib) for lib in libs)
    assert a.key != b.key
    a.put("robot-base", domain)
    b.put("robot-base", domain)
    assert StdlibCache(tmp_path / "c", libs[0]).get("robot-base") == domain
    assert StdlibCache(tmp_path / "c", libs[1]).get("robot-base") == domain
    assert len(list((tmp_path / "c").iterdir())) == 2


def test_the_folder_keeps_the_most_recent_entries_only(tmp_path, monkeypatch):
    from catc.frontend import stdlib_cache

    monkeypatch.setattr(stdlib_cache, "KEPT", 2)
    folder = tmp_path / "c"
    folder.mkdir()
    for i in range(3):  # entries of other keys, written long ago, oldest first
        (folder / f"compute-0000000{i}.pickle").write_bytes(b"x")
        os.utime(folder / f"compute-0000000{i}.pickle", (1000 + i, 1000 + i))
    _, domain = _robot_base(None)
    cache = StdlibCache(folder, stdlib_dir())
    cache.put("robot-base", domain)
    left = sorted(p.name for p in folder.iterdir())
    assert len(left) == 2 and "compute-00000002.pickle" in left, left
    assert cache.get("robot-base") == domain  # the new entry is one of those kept


def test_the_tests_keep_their_own_cache(monkeypatch):
    """The test processes (and the commands they start) use a private cache folder
    (tests/conftest.py), never the user's ~/.cache/catc."""
    from catc.interfaces.command import stdlib_cache

    assert os.environ["CATC_CACHE"] == CATC_CACHE and os.path.isdir(CATC_CACHE)
    used = stdlib_cache()
    assert used is not None and used.parent == Path(CATC_CACHE)
    monkeypatch.delenv("CATC_CACHE")
    assert stdlib_cache() != used  # the user's default folder is another
