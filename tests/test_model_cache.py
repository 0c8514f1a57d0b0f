"""The command line keeps checked user models between runs (:mod:`catc.frontend.model_cache`):
a hit parses and checks nothing and gives the instance a check gives; any change to what the
check read — a file's text (even an edit of the same length that keeps the file's time), a
file added beside the model, the view, the limits — is a miss; a file changed just before or
during the check is not kept; a damaged entry is a miss."""

from __future__ import annotations

import os
import shutil
import time
from pathlib import Path

import pytest
from conftest import ROOT, answer_document

from catc.frontend import session, workspace
from catc.frontend.session import load_checked
from catgrammar import limits
from catgrammar.diagnostics import Diagnostics

NAVIGATION = ROOT / "examples/navigation"


def _age(folder: Path) -> None:
    """Every file of ``folder`` and the folder itself last changed an hour ago (settled)."""
    old = time.time() - 3600
    for p in [*folder.iterdir(), folder]:
        os.utime(p, (old, old))


@pytest.fixture
def model(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A copy of examples/navigation, settled, as the working folder."""
    folder = tmp_path / "navigation"
    shutil.copytree(NAVIGATION, folder)
    _age(folder)
    monkeypatch.chdir(tmp_path)
    return folder


class Counting:
    """Counts the checks that ran (the workspace's load_instance), so a hit is seen as none."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch) -> None:
        self.runs = 0
        real = workspace.load_instance

        def counted(*args, **kwargs):  # type: ignore[no-untyped-def]
            self.runs += 1
            return real(*args, **kwargs)

        monkeypatch.setattr(workspace, "load_instance", counted)


def _load(cache: Path, problem: str = "navigation/farthest.cat", **options):  # type: ignore[no-untyped-def]
    diags = Diagnostics()
    inst = load_checked(problem, None, diags, stdlib_cache=cache / "stdlib", model_cache=cache / "models", **options)
    assert not diags.has_errors, diags
    return inst


def test_a_hit_checks_nothing_and_gives_the_same_instance(model, tmp_path, monkeypatch):
    checks = Counting(monkeypatch)
    first = _load(tmp_path / "c")
    assert checks.runs == 1 and len(list((tmp_path / "c/models").iterdir())) == 1
    again = _load(tmp_path / "c")
    assert checks.runs == 1  # a hit
    assert again == first and again is not first
    uncached = load_checked("navigation/farthest.cat", None, Diagnostics())
    assert again == uncached


def test_the_folder_keeps_the_most_recent_entries_only(model, tmp_path, monkeypatch):
    """Every folder catc runs in adds an entry: beyond KEPT, the oldest go."""
    from catc.frontend import model_cache

    monkeypatch.setattr(model_cache, "KEPT", 2)
    models = tmp_path / "c/models"
    models.mkdir(parents=True)
    for i in range(3):  # three older entries of other command lines
        (models / f"model-old{i}.pickle").write_bytes(b"x")
        os.utime(models / f"model-old{i}.pickle", (1000 + i, 1000 + i))
    _load(tmp_path / "c")
    left = sorted(p.name for p in models.iterdir())
    assert len(left) == 2 and "model-old2.pickle" in left, left
    checks = Counting(monkeypatch)
    _load(tmp_path / "c")
    assert checks.runs == 0  # the new entry is one of those kept


def test_an_edit_of_the_same_length_keeping_the_time_is_a_miss(model, tmp_path, monkeypatch):
    checks = Counting(monkeypatch)
    problem = model / "farthest.cat"
    first = _load(tmp_path / "c")
    stat = problem.stat()
    text = problem.read_text()
    assert "(= battery 73.3)" in text
    problem.write_text(text.replace("(= battery 73.3)", "(= battery 83.3)"))
    os.utime(problem, ns=(stat.st_atime_ns, stat.st_mtime_ns))  # same size, same time
    again = _load(tmp_path / "c")
    assert checks.runs == 2 and again != first
    assert again == load_checked("navigation/farthest.cat", None, Diagnostics())


def test_the_domain_file_is_part_of_the_entry(model, tmp_path, monkeypatch):
    checks = Counting(monkeypatch)
    _load(tmp_path / "c")
    domain = model / "domain.cat"
    domain.write_text(domain.read_text() + "\n; an edit\n")
    _age(model)
    _load(tmp_path / "c")
    assert checks.runs == 2


def test_a_file_added_beside_the_model_is_a_miss(model, tmp_path, monkeypatch):
    checks = Counting(monkeypatch)
    _load(tmp_path / "c")
    (model / "other.cat").write_text("; nothing yet\n")
    _age(model)
    _load(tmp_path / "c")
    assert checks.runs == 2


def test_the_view_the_problem_and_the_limits_are_part_of_the_request(model, tmp_path, monkeypatch):
    checks = Counting(monkeypatch)
    _load(tmp_path / "c")
    _load(tmp_path / "c", problem_name="nav-farthest")
    assert checks.runs == 2
    with limits.using(limits.current().replace(tokens=100_000)):
        _load(tmp_path / "c")
    assert checks.runs == 3
    _load(tmp_path / "c")
    assert checks.runs == 3  # the first entry still holds


def test_a_file_changed_just_before_the_check_is_not_kept(model, tmp_path, monkeypatch):
    checks = Counting(monkeypatch)
    (model / "farthest.cat").touch()  # now: the check may not have read what is there after it
    _load(tmp_path / "c")
    _load(tmp_path / "c")
    assert checks.runs == 2
    assert not (tmp_path / "c/models").exists()


def test_a_damaged_entry_is_a_miss(model, tmp_path, monkeypatch):
    checks = Counting(monkeypatch)
    first = _load(tmp_path / "c")
    for p in (tmp_path / "c/models").iterdir():
        p.write_bytes(b"not a pickle")
    assert _load(tmp_path / "c") == first and checks.runs == 2


def test_the_command_line_answers_alike_with_and_without_it(tmp_path, monkeypatch):
    folder = tmp_path / "lifelong"
    shutil.copytree(ROOT / "examples/lifelong", folder)
    _age(folder)
    monkeypatch.setenv("CATC_CACHE", "off")
    budget = str(folder / "budget-cut.cat")
    without = [answer_document(q, budget, "--json") for q in ("diagnose", "relax")]
    monkeypatch.setenv("CATC_CACHE", str(tmp_path / "c"))
    filling = [answer_document(q, budget, "--json") for q in ("diagnose", "relax")]
    assert len(list((tmp_path / "c/models").iterdir())) == 1  # one model, one entry
    hit = [answer_document(q, budget, "--json") for q in ("diagnose", "relax")]
    assert without == filling == hit


def test_session_loads_no_parser_for_a_hit():
    """The session module itself loads no parser or checker (a hit needs neither)."""
    assert not hasattr(session, "Workspace") and not hasattr(session, "lint_domain")
