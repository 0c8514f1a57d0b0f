"""What long queries tell the user while they run: the ``progress(message)`` callbacks behind
the terminal status line (catc.interfaces.command.reporter), checked against the examples' hand-derived
expectations (examples/*/expect.toml)."""

from __future__ import annotations

import io
import re
from fractions import Fraction

from conftest import ROOT

from catc.frontend.workspace import load_instance
from catc.interfaces import command
from catc.ir.views import apply_view
from catc.queries.diagnose import diagnose
from catc.queries.optimize import OptStatus, optimize
from catc.queries.recompose import recompose
from catc.queries.relax import relax
from catgrammar.diagnostics import Diagnostics


def load(path: str):
    _, inst = load_instance(None, str(ROOT / "examples" / path), Diagnostics())
    return apply_view(inst, None)


def test_optimize_says_each_phase_of_deepen():
    seen: list[str] = []
    # event II: the shortest composition has 10 steps (search-and-rescue/expect.toml) of a 24-step horizon
    result = optimize(load("search-and-rescue/event2-out-of-range.cat"), progress=seen.append)
    assert result.status is OptStatus.OPT
    horizons = [
        int(m.group(1))
        for m in map(re.compile(r"looking for a first composition: horizon (\d+) of 24$").match, seen)
        if m
    ]
    assert horizons == list(range(11))
    assert "first composition: 10 steps; is there a better one within 24 steps?" in seen
    assert seen.index("first composition: 10 steps; is there a better one within 24 steps?") == len(horizons)


def test_optimize_single_says_what_it_optimises():
    seen: list[str] = []
    optimize(load("gpu-allocation/retask.cat"), strategy="single", horizon=5, progress=seen.append)
    assert seen == ["optimising over 5 steps"]


def test_relax_shows_the_best_restoration_found_so_far():
    seen: list[str] = []
    result = relax(load("lifelong/budget-cut.cat"), progress=seen.append)
    assert result.status == "relaxed" and result.proven
    assert seen[0] == "looking for a restoration"
    costs = [
        Fraction(m.group(1))
        for m in map(re.compile(r"best restoration so far: weighted total (\S+);").match, seen)
        if m
    ]
    # improving, and the last one shown is the answer: +19,860 USD (lifelong/expect.toml)
    assert costs and costs == sorted(costs, reverse=True) and costs[-1] == result.cost == 19860
    seen.clear()
    relax(load("lifelong/budget-cut.cat"), discrete=True, progress=seen.append)
    assert seen == ["looking for the fewest requirements to drop"]


def test_diagnose_says_what_it_checks_and_shrinks():
    seen: list[str] = []
    result = diagnose(load("lifelong/budget-cut.cat"), progress=seen.append)
    assert result.status == "unsat"
    assert seen[0] == f"checking {result.total} requirements together"
    assert re.fullmatch(r"0 core\(s\) found; shrinking a core of \d+ requirements", seen[1])


def test_recompose_passes_progress_to_optimize():
    seen: list[str] = []
    recompose(load("lifelong/cheaper-camera.cat"), progress=seen.append)
    assert seen and all(
        m.startswith(("optimising over", "looking for a first composition", "first composition", "optimum over"))
        for m in seen
    )


def test_the_status_line_shows_the_message_and_the_time_so_far():
    from rich.console import Console

    class Status:
        shown = None

        def update(self, renderable):
            self.shown = renderable

    status = Status()
    report = command.reporter(status)
    report("optimising over 5 steps [not markup]")
    console = Console(width=80, record=True, file=io.StringIO())
    console.print(status.shown)
    assert re.fullmatch(r"optimising over 5 steps \[not markup\] \(\d+\.\d s\)\n", console.export_text())
    assert command.reporter(None) is None
