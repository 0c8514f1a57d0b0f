"""The executable frees the deepening solve's Z3 context once its first composition is read,
before optimize/recompose make the optimiser's (issue 23, start-up): with the executable's
allocator setting (:func:`catc.smt.backend._reuse_freed_memory`) the optimiser's context is
made in the memory the freed one leaves, instead of ~16 MB of fresh pages.  The answers do
not depend on it (tests/golden: the same answers); these tests check that the context is
freed, that the others are still kept to the process's end, and the bookkeeping."""

from __future__ import annotations

import json
import subprocess
import sys

from conftest import ROOT

from catc.smt import backend


def _probe(*args: str) -> tuple[dict, list[list[bool]]]:
    """``catc ARGS`` in a fresh process set up as the executable's: its JSON answer and, as
    each Z3 context is made, which of those made before it are still alive (then)."""
    probe = (
        "import weakref, z3\n"
        "made, seen = [], []\n"
        "init = z3.Context.__init__\n"
        "def tracked(self, *a, **k):\n"
        "    seen.append(''.join(str(int(r() is not None)) for r in made) or '-')\n"
        "    init(self, *a, **k)\n"
        "    made.append(weakref.ref(self))\n"
        "z3.Context.__init__ = tracked\n"
        "from catc.interfaces.entry import configure_process, main\n"
        "configure_process()\n"  # as the executable does (with argv None, then ends by os._exit)
        "try:\n"
        f"    main({list(args)!r})\n"
        "except SystemExit:\n"
        "    pass\n"
        "import sys\n"
        "print(' '.join(seen), file=sys.stderr)\n"
    )
    proc = subprocess.run([sys.executable, "-c", probe], cwd=ROOT, capture_output=True, text=True, timeout=120)
    seen = proc.stderr.strip().splitlines()[-1].split()
    return json.loads(proc.stdout), [[c == "1" for c in s.strip("-")] for s in seen]


def test_recompose_frees_the_deepening_context_before_the_optimisers():
    """lifelong/cheaper-camera (its comment: churn 0, 0 USD left, stability first): two
    contexts; when the optimiser's is made, the deepening solve's is gone."""
    doc, alive = _probe("recompose", "examples/lifelong/cheaper-camera.cat", "--json")
    assert doc["churn"] in (0, "0")
    assert alive == [[], [False]]


def test_other_contexts_are_still_kept():
    """relax on navigation/coarse makes three contexts (tests/test_presolve_contexts.py): none
    of them is a deepening's, and each is alive when the next is made."""
    _, alive = _probe("relax", "examples/navigation/coarse.cat", "--json")
    assert alive == [[], [True], [True, True]]


def test_release_kept_drops_only_what_was_kept_since_the_mark():
    token = backend._KEPT.set([])
    try:
        backend.kept("a")
        mark = backend.kept_mark()
        backend.kept("b")
        backend.kept("c")
        assert backend.kept_mark() == 3
        backend.release_kept(mark)
        assert backend._KEPT.get() == ["a"]
    finally:
        backend._KEPT.reset(token)
    assert backend.kept_mark() == 0  # not keeping: nothing to release
    backend.release_kept(0)
