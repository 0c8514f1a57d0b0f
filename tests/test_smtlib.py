"""`catc compile --emit smt2` is equivalent to the API encoding: solved in separate processes by
the `z3` binary shipped with z3-solver and by cvc5 (PyPI), every example gets the answer
`catc solve` gives at the same horizon (single encoding, idle steps allowed)."""

from __future__ import annotations

import shutil
import subprocess
import sys
import textwrap
import tomllib

import pytest
from conftest import ROOT, run_catc

from catc.frontend.workspace import load_instance
from catc.ir.views import apply_view
from catc.queries.solve import solve
from catc.semantics.horizon import default_horizon
from catc.smt.smtlib import emit_smt2
from catgrammar.diagnostics import Diagnostics

CVC5_SCRIPT = textwrap.dedent(
    """
    import sys, cvc5
    tm = cvc5.TermManager()
    slv = cvc5.Solver(tm)
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
)


def example_problems():
    for expect in sorted((ROOT / "examples").glob("*/expect.toml")):
        for case in tomllib.loads(expect.read_text())["case"]:
            yield pytest.param(
                expect.parent / case["file"],
                case.get("problem"),
                id=f"{expect.parent.name}/{case['file']}:{case.get('problem', '')}",
            )


def z3_binary() -> str:
    path = shutil.which("z3")
    if path is None:  # the wheel's binary lives next to the interpreter's scripts
        candidate = ROOT.parent / "bin" / "z3"
        path = str(candidate) if candidate.exists() else None
    assert path, "the z3 binary installed by z3-solver is not on PATH"
    return path


@pytest.mark.parametrize("path, problem", list(example_problems()))
def test_emitted_smt2_agrees_with_the_api_in_z3_and_cvc5(tmp_path, path, problem):
    diags = Diagnostics()
    _, inst = load_instance(None, str(path), diags, problem_name=problem)
    inst = apply_view(inst, None)
    k = default_horizon(inst)
    expected = solve(inst, horizon=k, strategy="single", validate_answer=False).status.value
    smt = tmp_path / "problem.smt2"
    smt.write_text(emit_smt2(inst, k))
    z3_out = subprocess.run([z3_binary(), str(smt)], capture_output=True, text=True, timeout=120)
    assert z3_out.stdout.split()[0] == expected, z3_out.stdout + z3_out.stderr
    cvc5_out = subprocess.run(
        [sys.executable, "-c", CVC5_SCRIPT, str(smt)], capture_output=True, text=True, timeout=300
    )
    assert cvc5_out.returncode == 0, cvc5_out.stderr
    assert cvc5_out.stdout.split()[0] == expected, cvc5_out.stdout + cvc5_out.stderr


def test_named_assertions_map_cores_to_source(tmp_path):
    out = tmp_path / "coarse.smt2"
    res = run_catc("compile", str(ROOT / "examples/navigation/coarse.cat"), "-o", str(out))
    assert res.exit_code == 0, res.output
    text = out.read_text() + "(get-unsat-core)\n"
    out.write_text(text)
    z3_out = subprocess.run([z3_binary(), str(out)], capture_output=True, text=True, timeout=60)
    lines = z3_out.stdout.split("\n")
    assert lines[0] == "unsat"
    core = {name.strip("|") for name in lines[1].strip("()").split()}
    # the reserve, the battery reading and the trip length conflict through move's precondition
    assert {"init/battery", "init/reserve", "goal/1", "pre/move/1"} <= core


def test_compile_names_every_source_label():
    res = run_catc("compile", str(ROOT / "examples/detection/person.cat"), "--horizon", "3")
    for label in (
        "pre/camera-driver/1",
        "pre/camera-driver/2",
        "init/ram",
        "goal/1",
        "bound/camera-driver/ram-req",
        "bounds/ram",
    ):
        assert f":named |{label}|" in res.stdout
