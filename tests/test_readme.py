"""The README's promises: its quick-start commands are what CI runs, its example output is real."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest
from conftest import ROOT, run_catc, run_catc_process

README = (ROOT / "README.md").read_text()


def shell_blocks() -> list[str]:
    return re.findall(r"```sh\n(.*?)```", README, re.S)


def test_quick_start_is_two_commands_and_ci_runs_the_test_one():
    blocks = shell_blocks()
    assert len(blocks) >= 2
    install_and_run, test = blocks[0].strip(), blocks[1].strip()
    assert install_and_run.startswith("pip install . && catc ")
    ci = (ROOT / ".ci" / "run").read_text()
    assert test in ci, f"{test!r} is not what .ci/run runs"


def test_quick_start_main_job_succeeds():
    command = shell_blocks()[0].strip().split("&&", 1)[1].split()
    assert command[0] == "catc"
    res = run_catc(*command[1:])
    assert res.exit_code == 0, res.output


def test_every_command_example_is_real_output():
    """Each ```text block that starts with `$ catc ...` and ends with `...` shows the true start
    of that command's output (run in a fresh process: Z3's choice among equally good θ values
    depends on the solver's history, which in-process tests share)."""
    blocks = re.findall(r"```text\n\$ catc ([^\n]+)\n(.*?)\.\.\.\n```", README, re.S)
    assert len(blocks) >= 2
    for command, shown in blocks:
        res = run_catc_process(*command.split())
        assert res.exit_code == 0, res.output
        assert res.stdout.startswith(shown), (command, res.stdout[: len(shown) + 80])


def test_error_example_is_real_output():
    m = re.search(r"```text\n\$ catc (check [^\n]+)\n(.*?)```", README, re.S)
    assert m
    args = m.group(1).split()
    res = run_catc(*args)
    assert res.stdout + res.stderr == m.group(2)


def _shell_transcripts(tool: str) -> list[list[tuple[str, str, bool]]]:
    """Each ```text block of the README that starts with `$ TOOL`: (command, output shown,
    shown output is only the start) for every `$ ` line in it."""
    out = []
    for block in re.findall(rf"```text\n(\$ {tool} .*?)```", README, re.S):
        steps, parts = [], re.split(r"^\$ ", block, flags=re.M)[1:]
        for part in parts:
            command, _, shown = part.partition("\n")
            partial = shown.endswith("...\n")
            steps.append((command, shown[: -len("...\n")] if partial else shown, partial))
        out.append(steps)
    return out


def _masked(text: str) -> str:
    """Timings and clock times vary between runs; nothing else may."""
    text = re.sub(r"\[\d+\.\d+ s", "[T s", text)
    return re.sub(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d+Z", "TIME", text)


@pytest.mark.slow
def test_the_runtime_examples_are_real_output(tmp_path):
    """The `$ catrt ...` transcripts, run in a fresh folder (examples/ linked in): the same
    lines, timings aside."""
    import os
    import subprocess

    transcripts = _shell_transcripts("catrt")
    assert len(transcripts) >= 2
    bin_dir = Path(sys.executable).parent
    env = {**os.environ, "PATH": f"{bin_dir}{os.pathsep}{os.environ['PATH']}"}
    for i, steps in enumerate(transcripts):
        cwd = tmp_path / f"t{i}"
        cwd.mkdir()
        (cwd / "examples").symlink_to(ROOT / "examples")
        for command, shown, partial in steps:
            res = subprocess.run(["bash", "-c", command], cwd=cwd, env=env, capture_output=True, text=True, timeout=600)
            assert res.returncode == 0, (command, res.stderr)
            got, want = _masked(res.stdout + res.stderr), _masked(shown)
            assert got.startswith(want) if partial else got == want, (command, got)
