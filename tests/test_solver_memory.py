"""The solver's memory limit is a value of each backend, not a switch of the process
(issue 23): ``open_backend(memory=...)`` gives it, and the default the executable sets with
``--memory`` (:func:`catc.smt.backend.limit_solver_memory`) holds in its own context only —
another thread, or a copy of the context made before, still opens backends without one."""

from __future__ import annotations

import contextvars
import threading

from catc.smt.backend import limit_solver_memory, open_backend, solver_memory


def test_each_backend_has_its_own_memory_limit():
    a, b = open_backend(memory=300), open_backend(memory=0)
    assert (a.memory, b.memory) == (300, 0)
    assert open_backend().memory == solver_memory()


def test_the_executables_default_stays_in_its_context():
    def in_a_context() -> tuple[int, int, int]:
        before = open_backend().memory
        limit_solver_memory(512)
        seen: list[int] = []
        thread = threading.Thread(target=lambda: seen.append(open_backend().memory))
        thread.start()
        thread.join()
        return before, open_backend().memory, seen[0]

    assert contextvars.copy_context().run(in_a_context) == (0, 512, 0)
    assert open_backend().memory == 0  # the context that ran it is untouched
