"""Finding a problem's domain (catc.frontend.workspace): the files beside a problem are read
through the language's tokenizer, only when they are regular files of a bounded size, and a
file that was not asked for never fails a command that names its domain (issue 15, Found 7);
a file holding only a domain with errors shows those errors (Found 12)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import run_catc, run_catc_process

from catc.frontend.workspace import Workspace
from catgrammar.diagnostics import Diagnostics

DOMAIN = "(define (domain d) (:requirements :numeric) (:resources (x real)))\n"
PROBLEM = "(define (problem p) (:domain d) (:init (= x 1)) (:goal (>= x 1)))\n"


def write(folder: Path, name: str, text: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / name
    path.write_text(text)
    return path


def test_a_comment_inside_the_domain_header_does_not_hide_the_domain(tmp_path):
    """`(define (domain d ; ...` defines d, as the parser and `catc check FOLDER` say, so
    a problem beside it finds it (the old regex did not: fmt would have changed the meaning)."""
    write(tmp_path, "dom.cat", "(define (domain d ; the domain\n) (:requirements :numeric) (:resources (x real)))\n")
    problem = write(tmp_path, "prob.cat", PROBLEM)
    assert run_catc("check", tmp_path).exit_code == 0
    res = run_catc("solve", problem)
    assert res.exit_code == 0 and "SAT" in res.stdout, res.output
    assert run_catc("check", problem).exit_code == 0


def test_a_domain_after_a_megabyte_of_comments_is_found(tmp_path):
    write(tmp_path, "dom.cat", ("; " + "x" * 98 + "\n") * 11_000 + DOMAIN)
    problem = write(tmp_path, "prob.cat", PROBLEM)
    res = run_catc("solve", problem)
    assert res.exit_code == 0 and "SAT" in res.stdout, res.output


def test_only_real_definitions_count():
    from catc.frontend.workspace import defined_domains

    text = '; (define (domain a))\n(define (domain b) (:resources (s bool :doc "(define (domain c))")))\n'
    assert defined_domains(text) == ["b"]
    assert defined_domains("(define (domain e)) ¤ (define (domain f))") == ["e"]  # up to a stray character
    assert defined_domains("(define (problem p) (:domain d))") == []


def _special_files(folder: Path) -> None:
    if not hasattr(os, "mkfifo"):  # pragma: no cover - Windows
        pytest.skip("no FIFOs here")
    os.mkfifo(folder / "y.cat")
    (folder / "z.cat").symlink_to("/dev/zero")


def test_a_fifo_or_a_device_beside_the_problem_is_never_read(tmp_path):
    """A FIFO and a link to /dev/zero named *.cat beside the problem used to hang check and
    solve (the domain named on the command line, so every sibling was scanned).  Run in a
    process with a generous timeout: the assertion is that it returned."""
    domain = write(tmp_path / "elsewhere", "dom.cat", DOMAIN)
    problem = write(tmp_path / "here", "prob.cat", PROBLEM)
    _special_files(problem.parent)
    for command in ("check", "solve"):
        res = run_catc_process(command, domain, problem, timeout=120)
        assert res.exit_code == 0, res.output
    # without the domain, the search says it is missing (after the standard library)
    res = run_catc_process("solve", problem, timeout=120)
    assert res.exit_code == 2 and "error[E0207]" in res.stderr


def test_a_fifo_named_on_the_command_line_is_an_input_error(tmp_path):
    _special_files(tmp_path)
    for name in ("y.cat", "z.cat"):
        res = run_catc_process("check", tmp_path / name, timeout=120)
        assert res.exit_code == 2 and "error[E0001]" in res.stdout and "not a regular file" in res.stdout


def test_the_language_server_analysis_does_not_read_a_fifo(tmp_path):
    problem = write(tmp_path, "prob.cat", PROBLEM)
    _special_files(tmp_path)
    code = (
        "import sys; from catc.interfaces.lsp import analyse; "
        "a = analyse(sys.argv[1], open(sys.argv[1]).read()); "
        "print(sorted(d.code for d in a.diagnostics))"
    )
    proc = subprocess.run([sys.executable, "-c", code, str(problem)], capture_output=True, timeout=120, text=True)
    assert proc.returncode == 0 and "E0207" in proc.stdout, proc.stderr


@pytest.mark.parametrize(
    "copy",
    [
        "(define (domain d) (:requirements :numeric) (:resources (x real) ))) oops\n",  # does not parse
        "(define (domain d) (:requirements :numeric) (:resources (x rea)))\n",  # parses, does not check
    ],
)
def test_a_broken_copy_beside_the_problem_does_not_fail_a_command_that_names_its_domain(tmp_path, copy):
    good = write(tmp_path / "good", "dom.cat", DOMAIN)
    write(tmp_path / "work", "dom-copy.cat", copy)
    problem = write(tmp_path / "work", "prob.cat", PROBLEM)
    res = run_catc("solve", good, problem)
    assert res.exit_code == 0 and "SAT" in res.stdout, res.output
    assert run_catc("check", good, problem).exit_code == 0
    # asked for nothing else, the problem means the copy beside it, and its errors are shown
    res = run_catc("solve", problem)
    assert res.exit_code == 2 and "dom-copy.cat:1:" in res.stderr, res.output


def test_a_broken_sibling_does_not_hide_a_good_one(tmp_path):
    write(tmp_path, "a-broken.cat", "(define (domain d) (:resources (x real) ))) oops\n")
    write(tmp_path, "b-dom.cat", DOMAIN)
    problem = write(tmp_path, "prob.cat", PROBLEM)
    res = run_catc("solve", problem)
    assert res.exit_code == 0 and "SAT" in res.stdout, res.output


def test_a_sibling_past_the_size_cap_is_skipped(tmp_path):
    write(tmp_path, "dom.cat", "; padding\n" * 100 + DOMAIN)
    problem = write(tmp_path, "prob.cat", PROBLEM)
    ws = Workspace(Diagnostics(), scan_max_bytes=500)
    ws.load(str(problem))
    assert ws.find_domain("d", str(problem)) is None
    ws = Workspace(Diagnostics())
    ws.load(str(problem))
    assert ws.find_domain("d", str(problem)) is not None


def test_a_file_with_only_a_broken_domain_shows_its_errors(tmp_path):
    """`catc solve FILE` on a file that defines only a domain, with errors: the file's own
    located errors (as check shows them), then why there is nothing to solve, located."""
    path = write(tmp_path, "dom.cat", "(define (domain d) (:requirements :numeric)\n (:resources (x rea)))\n")
    res = run_catc("solve", path)
    assert res.exit_code == 2
    assert f"{path}:2:17: error[E0202]: unknown sort 'rea'" in res.stderr, res.output
    assert f"{path}:1:17: error[E0206]: no (define (problem ...)) found" in res.stderr
    doc = json.loads(run_catc("solve", path, "--json").stdout)
    assert {d["code"] for d in doc["diagnostics"]} == {"E0206", "E0202"}
    assert all(d["location"] is not None for d in doc["diagnostics"])


def test_a_file_with_only_a_good_domain_says_where(tmp_path):
    path = write(tmp_path, "dom.cat", DOMAIN)
    res = run_catc("solve", path)
    assert res.exit_code == 2 and f"{path}:1:17: error[E0206]" in res.stderr and "domain 'd'" in res.stderr
