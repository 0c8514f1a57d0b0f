"""The README's promises: its quick-start commands are what CI runs, its example output is real."""

from __future__ import annotations

import re

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
