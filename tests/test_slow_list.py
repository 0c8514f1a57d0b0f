"""tests/slow_tests.txt names tests that exist: a renamed or deleted test would otherwise leave
a stale line, and its successor would run in the default group unnoticed (issue 28)."""

from __future__ import annotations

import re

from conftest import ROOT


def test_every_line_of_the_slow_list_names_a_test_that_exists():
    stale = []
    for text in (ROOT / "tests" / "slow_tests.txt").read_text(encoding="utf-8").splitlines():
        line = text.strip()
        if not line or line.startswith("#"):
            continue
        path, _, name = line.partition("::")
        function = name.split("[", 1)[0]
        source = ROOT / path
        if not source.is_file() or not re.search(
            rf"^\s*(async )?def {re.escape(function)}\(", source.read_text(), re.M
        ):
            stale.append(line)
    assert not stale, stale
