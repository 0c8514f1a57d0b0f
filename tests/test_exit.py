"""How the ``catc`` executable ends (:func:`catc.interfaces.entry.leave`): once the answer is
printed it ends the process without the interpreter's teardown (issue 23, start-up), after
running the ``atexit`` functions and flushing its output; with another thread still running
it leaves the ending to Python.  Each test runs a fresh process, as the executable does."""

from __future__ import annotations

import json
import subprocess
import sys

from conftest import ROOT, run_catc, run_catc_process


def _probe(body: str, *argv: str) -> subprocess.CompletedProcess[str]:
    """Run ``body`` then the executable's ``main()`` on ``argv`` in a fresh process."""
    code = f"import sys\nsys.argv = ['catc', *{list(argv)!r}]\n{body}\n"
    return subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)


def test_answers_and_exit_codes_are_those_of_the_command():
    ok = run_catc_process("solve", "examples/detection/person.cat", "--json")
    assert ok.exit_code == 0 and json.loads(ok.stdout)["status"] == "sat"
    assert run_catc_process("solve", "examples/lifelong/budget-cut.cat").exit_code == 1  # unsat
    missing = run_catc_process("solve", "missing.cat")
    assert missing.exit_code == 2 and "error[E0001]" in missing.stderr


def test_output_larger_than_a_pipe_is_written_whole():
    whole = run_catc_process("compile", "examples/search-and-rescue/mission.cat")
    assert whole.exit_code == 0 and len(whole.stdout) > 100_000
    assert whole.stdout == run_catc("compile", ROOT / "examples/search-and-rescue/mission.cat").stdout


def test_the_fast_ending_is_taken_and_still_runs_the_exit_functions(tmp_path):
    ran, ended = tmp_path / "atexit", tmp_path / "status"
    body = (
        "import atexit, os\n"
        f"atexit.register(lambda: open({str(ran)!r}, 'w').write('ran'))\n"
        "real = os._exit\n"
        f"def recorded(status):\n    open({str(ended)!r}, 'w').write(str(status))\n    real(status)\n"
        "os._exit = recorded\n"
        "from catc.interfaces.entry import main\n"
        "main()\n"
    )
    proc = _probe(body, "solve", "examples/detection/person.cat", "--json")
    assert proc.returncode == 0 and json.loads(proc.stdout)["status"] == "sat"
    assert ran.read_text() == "ran" and ended.read_text() == "0"
    unsat = _probe(body, "solve", "examples/lifelong/budget-cut.cat")
    assert unsat.returncode == 1 and ended.read_text() == "1"


def test_with_another_thread_running_python_ends_the_process():
    body = (
        "import threading\n"
        "release = threading.Event()\n"
        "threading.Thread(target=release.wait).start()\n"
        "from catc.interfaces.entry import main\n"
        "try:\n    main()\n"
        "except SystemExit as exc:\n    release.set()\n    print('returned', exc.code, file=sys.stderr)\n"
    )
    proc = _probe(body, "check", "examples/detection/person.cat")
    assert proc.returncode == 0 and "returned 0" in proc.stderr
