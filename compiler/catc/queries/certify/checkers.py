"""The independent checkers: the z3 binary and cvc5's SMT-LIB2 front end, each in a process
of its own with a time limit, several obligations per process."""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Sequence
from typing import Any

from catc.queries.certify.document import CHECKERS

_CVC5 = """
import sys, cvc5
tm = cvc5.TermManager()
slv = cvc5.Solver(tm)
slv.setOption("tlimit-per", sys.argv[2])
sm = cvc5.SymbolManager(tm)
parser = cvc5.InputParser(slv, sm)
parser.setFileInput(cvc5.InputLanguage.SMT_LIB_2_6, sys.argv[1])
while True:
    cmd = parser.nextCommand()
    if cmd.isNull():
        break
    out = cmd.invoke(slv, sm)
    if out:
        print(out.strip())
"""


# cvc5 on several files, one fresh solver each (nothing is shared between obligations): per
# file a line "catc-obligation I ANSWER SECONDS" (argv: the time limit in ms, then the files)
_CVC5_BATCH = """
import sys, time, cvc5
tm = cvc5.TermManager()
for i, path in enumerate(sys.argv[2:]):
    t0 = time.perf_counter()
    answer = "error"
    try:
        slv = cvc5.Solver(tm)
        slv.setOption("tlimit-per", sys.argv[1])
        sm = cvc5.SymbolManager(tm)
        parser = cvc5.InputParser(slv, sm)
        parser.setFileInput(cvc5.InputLanguage.SMT_LIB_2_6, path)
        while True:
            cmd = parser.nextCommand()
            if cmd.isNull():
                break
            out = cmd.invoke(slv, sm).split()  # "unknown (TIMEOUT)": the first word
            if out and out[0] in ("sat", "unsat", "unknown"):
                answer = out[0]
    except Exception:
        answer = "error"
    print("catc-obligation", i, answer, time.perf_counter() - t0, flush=True)
"""


def z3_command() -> list[str] | None:
    """The z3 binary z3-solver installs (on PATH, or beside the interpreter)."""
    import shutil

    path = shutil.which("z3") or os.path.join(os.path.dirname(sys.executable), "z3")
    return [path] if os.path.exists(path) else None


def cvc5_command() -> list[str] | None:
    """cvc5's SMT-LIB2 front end, in a fresh interpreter (PyPI's cvc5 ships no binary)."""
    import importlib.util

    return None if importlib.util.find_spec("cvc5") is None else [sys.executable, "-c", _CVC5]


def run_checker(checker: str, path: str, seconds: float) -> tuple[str, float]:
    """``checker``'s answer on the SMT-LIB2 file ``path`` (unsat, sat, unknown, timeout,
    missing or error) and the seconds it took."""
    if checker == "z3":
        cmd = z3_command()
        args = None if cmd is None else [*cmd, f"-T:{max(1, int(seconds + 0.999))}", path]
    else:
        cmd = cvc5_command()
        args = None if cmd is None else [*cmd, path, str(int(seconds * 1000))]
    if args is None:
        return "missing", 0.0
    import subprocess

    t0 = time.perf_counter()
    try:
        out = subprocess.run(args, capture_output=True, text=True, timeout=seconds + 5)
    except subprocess.TimeoutExpired:
        return "timeout", time.perf_counter() - t0
    took = time.perf_counter() - t0
    words = out.stdout.split()
    answer = words[0] if words else ""
    if answer in ("unsat", "sat", "unknown"):
        return answer, took
    return ("timeout" if "timeout" in out.stdout + out.stderr else "error"), took


def run_batch(checker: str, paths: Sequence[str], seconds: float) -> list[tuple[str, float]]:
    """``checker``'s answer on each SMT-LIB2 file of ``paths``, all in one process (its
    start-up paid once): the z3 binary on one script that runs each file after a ``(reset)``
    with its own time limit; cvc5 with a fresh solver per file.  An obligation the batch did
    not answer (a crash, an error) is run again alone by :func:`run_checker`."""
    import subprocess

    command = z3_command() if checker == "z3" else cvc5_command()
    if command is None:
        return [("missing", 0.0)] * len(paths)
    if len(paths) == 1:
        return [run_checker(checker, paths[0], seconds)]
    ms = str(max(1, int(seconds * 1000)))
    if checker == "z3":
        import tempfile

        # a script of its own: other batches of the same certificate run at the same time
        handle, script = tempfile.mkstemp(suffix=".smt2", prefix="z3-batch-", dir=os.path.dirname(paths[0]))
        with os.fdopen(handle, "w", encoding="utf-8") as out:
            for i, path in enumerate(paths):
                with open(path, encoding="utf-8") as fh:
                    body = fh.read()
                out.write(f'(reset)\n(set-option :timeout {ms})\n(echo "catc-obligation {i}")\n{body}\n')
        args = [*command, script]
    else:
        args = [sys.executable, "-c", _CVC5_BATCH, ms, *paths]
    answers: dict[int, tuple[str, float]] = {}
    current, t0 = -1, time.perf_counter()
    try:
        with subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True) as proc:
            limit = _kill_after(proc, len(paths) * seconds + 5)
            assert proc.stdout is not None
            for line in proc.stdout:
                words = line.split()
                if words[:1] != ["catc-obligation"] or len(words) < 2:
                    if checker == "z3" and current >= 0 and current not in answers and words[:1]:
                        answer = words[0] if words[0] in ("sat", "unsat", "unknown") else "error"
                        answers[current] = (answer, time.perf_counter() - t0)
                    continue
                if checker == "z3":
                    current, t0 = int(words[1]), time.perf_counter()
                elif len(words) == 4:
                    answers[int(words[1])] = (words[2], float(words[3]))
            limit.cancel()
    except OSError:
        pass
    return [
        answers[i] if answers.get(i, ("error", 0.0))[0] != "error" else run_checker(checker, path, seconds)
        for i, path in enumerate(paths)
    ]


def _kill_after(proc: Any, seconds: float) -> Any:
    """Kill ``proc`` after ``seconds`` (the batch's overall limit); cancel it when done."""
    import threading

    timer = threading.Timer(seconds, proc.kill)
    timer.daemon = True
    timer.start()
    return timer


#: Obligations per checker process before a checker's list is split over more processes.
BATCH = 4


def _run_checkers(obligations: Sequence[dict], seconds: float) -> list[dict[str, tuple[str, float]]]:
    """Every checker on every obligation: one process per checker for up to :data:`BATCH`
    obligations (:func:`run_batch`: its start-up paid once), a longer list split round-robin
    over as many processes as there are cores (up to 4), all of them at once on that many
    workers (they share nothing)."""
    import tempfile
    from concurrent.futures import ThreadPoolExecutor

    workers = max(1, min(4, os.cpu_count() or 1))
    with tempfile.TemporaryDirectory(prefix="catc-certify-") as folder:
        paths = []
        for i, o in enumerate(obligations):
            paths.append(os.path.join(folder, f"{i}.smt2"))
            with open(paths[-1], "w", encoding="utf-8") as fh:
                fh.write(o["smtlib"])
        chunks: list[tuple[str, list[int]]] = []
        for c in CHECKERS:
            ids = [i for i, o in enumerate(obligations) if c in o["checkers"]]
            parts = min(workers, -(-len(ids) // BATCH))
            chunks += [(c, ids[j::parts]) for j in range(parts)]

        def check(chunk: tuple[str, list[int]]) -> list[tuple[str, float]]:
            checker, ids = chunk
            files = [paths[i] for i in ids]
            if sum(len(obligations[i]["smtlib"]) for i in ids) <= IN_PROCESS:
                here = _here(checker, files, seconds)
                if here is not None:
                    return here
            return run_batch(checker, files, seconds)

        with ThreadPoolExecutor(max_workers=max(1, min(workers, len(chunks)))) as pool:
            done = list(pool.map(check, chunks))
    out: list[dict[str, tuple[str, float]]] = [{} for _ in obligations]
    for (checker, ids), answers in zip(chunks, done):
        for i, answer in zip(ids, answers):
            out[i][checker] = answer
    return out


#: The most SMT-LIB2 text (characters, all of a checker's obligations) a checker decides inside
#: catc's own process: a few small obligations, where a fresh process's start-up would be most
#: of the time (the examples' certificates); more goes to processes of their own, where a
#: crash or a runaway cannot take catc with it and the batch's time limit kills.
IN_PROCESS = 64_000


def _here(checker: str, paths: Sequence[str], seconds: float) -> list[tuple[str, float]] | None:
    """``checker``'s answer on each file through its Python API in this process (cvc5:
    :func:`catc.smt.cvc5backend.answer_file`, its parser and a fresh solver per file; z3:
    :func:`catc.smt.z3backend.answer_file`, a fresh context per file; each its own time
    limit); an obligation it errs on is run again alone in a process of its own
    (:func:`run_checker`).  None when the checker is not installed."""
    import functools

    from catc.smt.backend import BackendError

    try:
        if checker == "cvc5":
            from catc.smt import cvc5backend

            answer_file: Any = functools.partial(cvc5backend.answer_file, manager=cvc5backend.term_manager())
        else:
            from catc.smt import z3backend

            answer_file = z3backend.answer_file
    except (BackendError, ImportError):
        return None
    out = []
    for path in paths:
        t0 = time.perf_counter()
        try:
            answer = answer_file(path, int(seconds * 1000))
        except Exception:
            answer = "error"
        took = time.perf_counter() - t0
        out.append((answer, took) if answer in ("sat", "unsat", "unknown") else run_checker(checker, path, seconds))
    return out
