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


def _closure_conflicts(extra: str) -> tuple[list[str], list[str]]:
    """What ``pip check`` would say about ``catc-lang[extra]``: every requirement of the core
    and of the extra, and of the installed distributions they need (transitively), checked
    against the installed versions.  Returns (conflicts, requirements not installed)."""
    from importlib import metadata

    from packaging.requirements import Requirement

    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    todo = [Requirement(r) for r in (*project["dependencies"], *project["optional-dependencies"][extra])]
    seen: set[str] = set()
    conflicts, missing = [], []
    while todo:
        req = todo.pop()
        if req.marker is not None and not req.marker.evaluate({"extra": ""}):
            continue
        try:
            dist = metadata.distribution(req.name)
        except metadata.PackageNotFoundError:
            missing.append(req.name)
            continue
        if not req.specifier.contains(dist.version, prereleases=True):
            conflicts.append(f"{req} but {req.name} {dist.version} is installed")
        key = dist.metadata["Name"].lower()
        if key not in seen:
            seen.add(key)
            todo.extend(Requirement(r) for r in dist.requires or ())
    return conflicts, missing


def test_the_baselines_extra_is_complete_and_conflict_free():
    """`pip install 'catc-lang[baselines]'` is all `catc export pddl --run` needs, and what it
    installs agrees with itself (PyPI pddl, which pins lark<1.2, is not part of it)."""
    import pytest

    conflicts, missing = _closure_conflicts("baselines")
    if missing:
        pytest.importorskip(missing[0], reason=f"the baselines extra is not installed ({', '.join(missing)})")
    assert conflicts == []
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    names = {
        r.split("[")[0].split("=")[0].split(">")[0].split("<")[0].strip()
        for r in project["optional-dependencies"]["baselines"]
    }
    assert "pddl" not in names
