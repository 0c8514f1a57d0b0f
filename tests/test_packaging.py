"""The distribution ships every subpackage (a plain `pip install .` must get them all)."""

from __future__ import annotations

import tomllib

from conftest import ROOT


def test_every_package_folder_is_listed_in_pyproject():
    conf = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    listed = set(conf["packages"])
    roots = conf["package-dir"]
    found = set()
    for package, folder in roots.items():
        base = ROOT / folder
        for init in base.rglob("__init__.py"):
            rel = init.parent.relative_to(base)
            found.add(".".join((package, *rel.parts)) if rel.parts else package)
    assert found == listed, f"missing from pyproject: {found - listed}; listed but absent: {listed - found}"
