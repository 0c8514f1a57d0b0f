"""benchmarks/mutation.py stages the repository as mutmut 3 expects (the run itself is a
scheduled job, minutes long: docs/benchmarks.md records it)."""

from __future__ import annotations

import sys
import tomllib

from conftest import ROOT

sys.path.insert(0, str(ROOT / "benchmarks"))
import mutation


def test_the_staged_copy_is_laid_out_for_mutmut(tmp_path):
    for target, (source, tests) in mutation.TARGETS.items():
        where = mutation.stage(target, tmp_path / target)
        assert (where / "src" / source).is_file()
        assert (where / "src" / "catgrammar" / "parser.py").is_file()
        config = tomllib.loads((where / "pyproject.toml").read_text())["tool"]["mutmut"]
        assert config["only_mutate"] == [f"src/{source}"]
        assert config["source_paths"] == ["src/catc"]
        assert config["pytest_add_cli_args_test_selection"] == tests
        for test in tests:  # every test file named exists
            assert (where / test).is_file(), test
