"""Shared fixtures: the repository's .cat corpus and a CLI runner that never hides crashes."""

from __future__ import annotations

import atexit
import os
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import pytest
from click.testing import CliRunner

ROOT = Path(__file__).resolve().parent.parent

# pint's cache (~/.cache/pint) is shared by every process on the machine: whether a test found
# an entry there decided whether it passed (issue 28: test_units failed wherever pint built its
# registry afresh).  Each test process (each xdist worker, and the commands its tests start)
# has a cache folder of its own, empty at the start.
_PINT_CACHE = tempfile.mkdtemp(prefix="catc-pint-cache-")
os.environ["CATC_PINT_CACHE"] = _PINT_CACHE
atexit.register(shutil.rmtree, _PINT_CACHE, True)
# Likewise catc's own cache of checked standard-library domains and models ($CATC_CACHE,
# catc.interfaces.command.stdlib_cache): without this every command a test runs — in-process
# or as a child process, which inherits the variable — wrote into the user's ~/.cache/catc.
# Set here, on import, so that it holds from collection on in every test process.
CATC_CACHE = tempfile.mkdtemp(prefix="catc-cache-")
os.environ["CATC_CACHE"] = CATC_CACHE
atexit.register(shutil.rmtree, CATC_CACHE, True)
FIXTURES = Path(__file__).resolve().parent / "fixtures"


def repo_cat_files(*, invalid: bool = False) -> list[Path]:
    """Every tracked-or-present .cat file of the repository (not node_modules/build output)."""
    skip = {"node_modules", ".git", "build", "dist", ".pytest_cache"}
    out = []
    for p in sorted(ROOT.rglob("*.cat")):
        rel = p.relative_to(ROOT)
        if skip & set(rel.parts):
            continue
        is_invalid = "invalid" in rel.parts or "bad" in rel.parts
        if is_invalid == invalid:
            out.append(p)
    return out


@dataclass
class Result:
    exit_code: int
    stdout: str
    stderr: str

    @property
    def output(self) -> str:
        return self.stdout + self.stderr


class _Executable:
    """``catc`` as the executable runs it (:func:`catc.interfaces.entry.main`: a plain ``catc solve``
    without click, everything else through click), shaped for ``CliRunner.invoke``."""

    name = "catc"

    @staticmethod
    def main(args, prog_name=None, **_):
        from catc.interfaces.entry import main

        main(list(args))


def run_catc(*args: str, cwd: Path | None = None, via_click: bool = False) -> Result:
    """Run the CLI in-process as the executable does (``via_click``: always through
    click's parser); any exception escaping is a test failure."""
    from catc.interfaces.cli import main

    runner = CliRunner()
    res = runner.invoke(main if via_click else _Executable, [str(a) for a in args], catch_exceptions=True)
    if res.exception is not None and not isinstance(res.exception, SystemExit):
        raise AssertionError(f"catc {' '.join(map(str, args))} raised {res.exception!r}") from res.exception
    return Result(res.exit_code, res.stdout, res.stderr)


def answer_document(*args: str) -> dict:
    """The JSON answer of ``catc ARGS`` (which must exit 0), without its timings: two runs
    of one question compare equal."""
    import json

    res = run_catc(*args)
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)
    doc.pop("timings", None)
    return doc


def run_catc_process(*args: str, timeout: float = 120, input: bytes | None = None) -> Result:
    """Run ``python -m catc`` in a fresh process (for end-to-end behaviour)."""
    proc = subprocess.run(
        [sys.executable, "-m", "catc", *map(str, args)],
        capture_output=True,
        timeout=timeout,
        input=input,
        cwd=ROOT,
    )
    return Result(proc.returncode, proc.stdout.decode("utf-8", "replace"), proc.stderr.decode("utf-8", "replace"))


@pytest.fixture
def catc():
    return run_catc


def word_uses(text: str, name: str) -> list[int]:
    """By hand (a regex, not catc's tokenizer): offsets of ``name`` as a whole word outside
    comments and strings — what the language server's references are checked against."""
    out = []
    for m in re.finditer(rf"(?<![\w-]){re.escape(name)}(?![\w-])", text):  # names may hold '-'
        before = text[text.rfind("\n", 0, m.start()) + 1 : m.start()]
        if ";" not in before and before.count('"') % 2 == 0:
            out.append(m.start())
    return out


def pytest_report_header(config):
    """Which real tools check the grounding artifacts in this run (tests/test_deploy.py)."""
    from fake_docker import real_compose
    from grounding_checks import rcl_checker_name

    return [f"ROS 2 parameter files: {rcl_checker_name()}", f"Docker Compose v2: {real_compose() or 'absent'}"]


# ---------------------------------------------------------------- the slow group

_SLOW_LIST = Path(__file__).resolve().parent / "slow_tests.txt"


def _slow_ids() -> tuple[set[str], set[str]]:
    """The measured heavy tests (tests/slow_tests.txt): exact node ids, and whole tests."""
    exact, whole = set(), set()
    for text in _SLOW_LIST.read_text().splitlines():
        line = text.strip()
        if line and not line.startswith("#"):
            (exact if "[" in line else whole).add(line)
    return exact, whole


def pytest_collection_modifyitems(config, items):
    """Mark the tests of tests/slow_tests.txt `slow`: the default run (pyproject's addopts)
    leaves them to .ci/run's slow and baselines steps (issue 28: README command ≤ 3 min)."""
    exact, whole = _slow_ids()
    rootdir = Path(str(config.rootpath))
    for item in items:
        nodeid = Path(item.fspath).resolve().relative_to(rootdir).as_posix() + "::" + item.name
        if nodeid in exact or nodeid.split("[", 1)[0] in whole:
            item.add_marker(pytest.mark.slow)
